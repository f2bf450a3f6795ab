// minigolf.World and minigolf.Data: a field's MuJoCo world and live numpy views of its mjData.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>

#include <fmt/format.h>

#include "python/bindings.hpp"

namespace mg::python {

void bind_worlds(py::module_& m) {
  py::class_<sim::World>(
      m, "World",
      "A field's MuJoCo world (immutable, shared by threads). `model_*` arrays are read-only "
      "numpy views of the live mjModel.")
      .def_property_readonly("field", &sim::World::field,
                             py::return_value_policy::reference_internal)
      .def(
          "make_data",
          [](const sim::World& w) {
            Data d;
            d.world = &w;
            d.owned = w.make_data();
            d.d = d.owned.get();
            return d;
          },
          py::keep_alive<0, 1>(), "A fresh mjData (ball on the tee, hole at the field's default)")
      .def(
          "reset", [](const sim::World& w, Data& d) { w.reset(data_of(w, d)); },
          "Ball on the tee, hole at the default")
      .def(
          "step",
          [](const sim::World& w, Data& d, int n) {
            mjData* dd = data_of(w, d);
            if (n < 0) throw InputError(fmt::format("step: n: expected >= 0, got {}", n));
            py::gil_scoped_release release;
            for (int i = 0; i < n; ++i) w.step(dd);
          },
          py::arg("data"), py::arg("n") = 1,
          "`n` physics steps (rolling resistance included) of timestep s")
      .def(
          "set_hole",
          [](const sim::World& w, Data& d, std::array<double, 2> p) {
            w.set_hole(data_of(w, d), p);
          },
          "Moves the hole to (x, y) [m]")
      .def(
          "hole_position",
          [](const sim::World& w, const Data& d) { return w.hole_position(data_of(w, d)); }, "[m]")
      .def_property_readonly("mjcf", &sim::World::mjcf, "The generated MJCF text")
      .def_property_readonly("nq", [](const sim::World& w) { return w.model()->nq; })
      .def_property_readonly("nv", [](const sim::World& w) { return w.model()->nv; })
      .def_property_readonly("nu", [](const sim::World& w) { return w.model()->nu; })
      .def_property_readonly("nbody", [](const sim::World& w) { return w.model()->nbody; })
      .def_property_readonly("ngeom", [](const sim::World& w) { return w.model()->ngeom; })
      .def_property_readonly(
          "timestep", [](const sim::World& w) { return w.model()->opt.timestep; }, "[s]")
      .def_property_readonly(
          "ball_qpos", [](const sim::World& w) { return w.ids().ball_qpos; },
          "Index of the ball's first qpos (centre x, y, z [m], then the quaternion)")
      .def_property_readonly(
          "ball_dof", [](const sim::World& w) { return w.ids().ball_dof; },
          "Index of the ball's first dof (linear velocity [m/s], then angular [rad/s])")
      .def("body_id",
           [](const sim::World& w, const std::string& name) {
             const int id = mj_name2id(w.model(), mjOBJ_BODY, name.c_str());
             if (id < 0) throw InputError(fmt::format("body_id: no body named '{}'", name));
             return id;
           })
      .def("body_name",
           [](const sim::World& w, int id) {
             if (id < 0 || id >= w.model()->nbody)
               throw InputError(fmt::format("body_name: no body {}", id));
             const char* n = mj_id2name(w.model(), mjOBJ_BODY, id);
             return std::string(n ? n : "");
           })
#define MG_MODEL_VIEW(name, rows, cols)                         \
  .def_property_readonly("model_" #name, [](py::object self) {  \
    const mjModel* mm = self.cast<const sim::World&>().model(); \
    return view(mm->name, mm->rows, cols, self, false);         \
  })
          MG_MODEL_VIEW(body_pos, nbody, 3) MG_MODEL_VIEW(body_quat, nbody, 4)
              MG_MODEL_VIEW(body_mass, nbody, 1) MG_MODEL_VIEW(body_inertia, nbody, 3)
                  MG_MODEL_VIEW(geom_size, ngeom, 3) MG_MODEL_VIEW(geom_pos, ngeom, 3)
                      MG_MODEL_VIEW(geom_friction, ngeom, 3) MG_MODEL_VIEW(geom_type, ngeom, 1)
                          MG_MODEL_VIEW(jnt_range, njnt, 2) MG_MODEL_VIEW(jnt_qposadr, njnt, 1)
                              MG_MODEL_VIEW(dof_damping, nv, 1)
                                  MG_MODEL_VIEW(actuator_ctrlrange, nu, 2)
                                      MG_MODEL_VIEW(qpos0, nq, 1);
#undef MG_MODEL_VIEW

  py::class_<Data>(
      m, "Data",
      "An mjData of a world. Its arrays are writable numpy views of the live data: they see every "
      "step and every write goes into the simulation.")
      .def_property(
          "time", [](const Data& d) { return d.d->time; }, [](Data& d, double t) { d.d->time = t; },
          "Simulation time [s]")
#define MG_DATA_VIEW(name, rows, cols)                   \
  .def_property_readonly(#name, [](py::object self) {    \
    Data& dd = self.cast<Data&>();                       \
    const mjModel* mm = dd.world->model();               \
    return view(dd.d->name, mm->rows, cols, self, true); \
  })
          MG_DATA_VIEW(qpos, nq, 1) MG_DATA_VIEW(qvel, nv, 1) MG_DATA_VIEW(qacc, nv, 1)
              MG_DATA_VIEW(ctrl, nu, 1) MG_DATA_VIEW(qfrc_applied, nv, 1)
                  MG_DATA_VIEW(xfrc_applied, nbody, 6) MG_DATA_VIEW(xpos, nbody, 3)
                      MG_DATA_VIEW(xquat, nbody, 4) MG_DATA_VIEW(xmat, nbody, 9)
                          MG_DATA_VIEW(geom_xpos, ngeom, 3) MG_DATA_VIEW(mocap_pos, nmocap, 3)
                              MG_DATA_VIEW(mocap_quat, nmocap, 4) MG_DATA_VIEW(qfrc_actuator, nv, 1)
                                  MG_DATA_VIEW(qacc_warmstart, nv, 1);
#undef MG_DATA_VIEW
}

}  // namespace mg::python
