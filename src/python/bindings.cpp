// The `minigolf` Python module (pybind11): the library's fields, worlds, putts, learners, DS
// rollouts, teacher and experiments. Units: metres, seconds, radians, m/s. Long calls release the
// GIL; mg::InputError -> ValueError, mg::IoError -> OSError, mg::NumericalError ->
// minigolf.NumericalError (a RuntimeError), other mg::Error -> RuntimeError, with the messages
// the CLI prints after "minigolf: error: ".
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <mujoco/mujoco.h>

#include "core/error.hpp"
#include "ds/hitting_ds.hpp"
#include "ds/hitting_model.hpp"
#include "experiments/collect.hpp"
#include "experiments/evaluate.hpp"
#include "experiments/sweep.hpp"
#include "field/field.hpp"
#include "field/situations.hpp"
#include "learning/learner.hpp"
#include "sim/putt.hpp"
#include "sim/world.hpp"
#include "system/distributed.hpp"
#include "system/system.hpp"
#include "teacher/teacher.hpp"
#include "python/py_data.hpp"

namespace py = pybind11;
using namespace mg;
using python::Data;
using python::data_of;

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// A numpy array over `p` (no copy) that keeps `owner` alive; read-only unless `writeable`.
template <typename T>
py::array view(T* p, py::ssize_t rows, py::ssize_t cols, py::handle owner, bool writeable) {
  std::vector<py::ssize_t> shape{rows};
  if (cols > 1) shape.push_back(cols);
  py::array a(py::dtype::of<T>(), shape, p, owner);
  if (!writeable) a.attr("setflags")(py::arg("write") = false);
  return a;
}

py::array_t<double> matrix(const Eigen::MatrixXd& m) {
  py::array_t<double> a({m.rows(), m.cols()});
  auto r = a.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) r(i, j) = m(i, j);
  return a;
}

Eigen::MatrixXd to_matrix(const Array& a, const char* what) {
  if (a.ndim() != 2) throw InputError(fmt::format("{}: expected a 2-D array (N x D), got {} dimensions", what, a.ndim()));
  Eigen::MatrixXd m(a.shape(0), a.shape(1));
  auto r = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i)
    for (py::ssize_t j = 0; j < a.shape(1); ++j) m(i, j) = r(i, j);
  return m;
}

py::array_t<double> points(const std::vector<std::array<double, 2>>& p) {
  py::array_t<double> a({static_cast<py::ssize_t>(p.size()), py::ssize_t{2}});
  auto r = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < p.size(); ++i) r(i, 0) = p[i][0], r(i, 1) = p[i][1];
  return a;
}

// ---- worlds and their MuJoCo data


/// A SystemData that refuses to be used by two threads at once.
struct PySystemData {
  explicit PySystemData(const system::System& s) : system(&s), data(s) {}
  const system::System* system;
  system::SystemData data;
  std::mutex busy;
};

class Lease {
 public:
  explicit Lease(PySystemData* d) : d_(d) {
    if (d_ && !d_->busy.try_lock())
      throw std::runtime_error("SystemData: in use by another thread (make one per thread)");
  }
  ~Lease() {
    if (d_) d_->busy.unlock();
  }
  Lease(const Lease&) = delete;
  Lease& operator=(const Lease&) = delete;

 private:
  PySystemData* d_;
};

// ---- putts

struct PuttResult {
  std::string field;
  bool ball_only = true;
  std::array<double, 2> hole{0, 0};
  double angle = 0, speed = 0;
  sim::PuttOutcome outcome;
  control::AngleSpeed club, launch;
  control::CoreTiming timing;
  std::string plant_path, plant_hash;  ///< empty: no plant file
};

py::dict putt_dict(const PuttResult& r) {
  const sim::PuttOutcome& o = r.outcome;
  py::dict d;
  d["field"] = r.field;
  d["hole"] = py::make_tuple(r.hole[0], r.hole[1]);
  d["angle"] = r.angle;
  d["speed"] = r.speed;
  d["sunk"] = o.sunk;
  d["end"] = sim::to_string(o.end);
  d["rest_position"] = py::make_tuple(o.rest_position[0], o.rest_position[1]);
  d["closest_approach"] = o.closest_approach;
  d["duration"] = o.duration;
  d["steps"] = o.steps;
  if (r.plant_path.empty()) {
    d["plant"] = py::none();
  } else {
    py::dict plant;
    plant["path"] = r.plant_path, plant["hash"] = r.plant_hash;
    d["plant"] = plant;
  }
  if (!r.ball_only) {
    py::dict club, launch, timing;
    club["angle"] = r.club.angle, club["speed"] = r.club.speed;
    launch["angle"] = r.launch.angle, launch["speed"] = r.launch.speed;
    timing["core_update_p99_us"] = r.timing.core_update_p99_us;
    timing["core_update_max_us"] = r.timing.core_update_max_us;
    timing["overruns"] = r.timing.overruns;
    d["club"] = club, d["launch"] = launch, d["timing"] = timing;
  }
  return d;
}

PuttResult do_putt(const system::System& sys, PySystemData* pdata, double angle, double speed,
                   std::optional<std::array<double, 2>> hole_opt, bool ball_only, double max_duration,
                   double record_interval) {
  PuttResult r;
  r.field = sys.field().name;
  r.ball_only = ball_only;
  r.angle = angle;
  r.speed = speed;
  r.hole = hole_opt ? *hole_opt : sys.field().hole.position;
  r.plant_path = sys.plant().source;
  r.plant_hash = sys.plant().hash;
  Lease lease(pdata);
  std::optional<system::SystemData> local;
  py::gil_scoped_release release;
  system::SystemData& data = pdata ? pdata->data : local.emplace(sys);
  if (ball_only) {  // as `minigolf putt --ball-only`
    sim::PuttRequest request;
    request.angle = angle;
    request.speed = speed;
    request.max_duration = max_duration;
    request.record_interval = record_interval;
    request.validate();
    field::check_hole_position(sys.field(), r.hole);
    const auto real = system::real_hole(sys, r.hole);  // where the plant's hole really is
    field::check_hole_position(sys.ball_world().field(), real);
    r.outcome = sim::simulate_putt(sys.ball_world(), data.ball.get(), real, request);
    return r;
  }
  // as `minigolf putt` (the arm)
  sys.check_request(angle, speed, "putt");
  control::FullPuttOptions options;
  options.max_duration = max_duration;
  options.record_interval = record_interval;
  const control::FullPuttResult f = system::arm_putt(sys, data, r.hole, angle, speed, options);
  if (f.hit_refused) throw InputError("putt: the module refused the hit request");
  if (!f.hit) throw NumericalError("putt: the club did not reach the ball");
  r.outcome = f.outcome;
  r.club = f.club;
  r.launch = f.launch;
  r.timing = f.timing;
  return r;
}

py::array_t<double> trajectory(const sim::PuttOutcome& o) {
  py::array_t<double> a({static_cast<py::ssize_t>(o.trajectory.size()), py::ssize_t{7}});
  auto r = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < o.trajectory.size(); ++i) {
    const auto& s = o.trajectory[i];
    const double row[7] = {s.t, s.x, s.y, s.z, s.vx, s.vy, s.vz};
    for (int j = 0; j < 7; ++j) r(i, j) = row[j];
  }
  return a;
}

std::vector<std::string> default_names(int n, const std::vector<std::string>& preferred, const char* prefix) {
  if (n == static_cast<int>(preferred.size())) return preferred;
  if (n == 1 && !preferred.empty()) return {preferred[0]};
  std::vector<std::string> names;
  for (int i = 0; i < n; ++i) names.push_back(fmt::format("{}{}", prefix, i));
  return names;
}

/// The teacher's options for the field's region, with the Python arguments' budgets and margins.
teacher::TeacherOptions teacher_options(const system::System& sys, const std::string& strategy, int max_full_putts,
                                        int max_ball_putts, double margin_angle, double margin_speed) {
  teacher::TeacherOptions t = teacher::options_for(sys.field().situations, strategy);
  t.max_full_putts = max_full_putts;
  t.max_ball_putts = max_ball_putts;
  t.margin_angle = margin_angle;
  t.margin_speed = margin_speed;
  t.validate();
  return t;
}

const teacher::TeacherOptions kTeacherDefaults{};

}  // namespace

PYBIND11_MODULE(_minigolf, m) {
  m.doc() = "A simulated Barrett WAM that learns to putt: fields, worlds, putts, learners, DS rollouts, "
            "teacher, evaluation. Units: m, s, rad, m/s.";

  static py::exception<NumericalError> numerical(m, "NumericalError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const IoError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const NumericalError& e) {
      numerical(e.what());
    } catch (const Error& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });
  m.attr("mpi_built") = system::mpi_built();

  // ---------------------------------------------------------------- fields
  py::class_<field::Situations>(m, "Situations", "Where the hole may be on a field (the region a learner covers).")
      .def_property_readonly("shape", [](const field::Situations& s) { return field::to_string(s.shape); },
                             "'line', 'grid', 'box' or 'list'")
      .def_readonly("learn_speed", &field::Situations::learn_speed,
                    "True: outputs (angle, speed); False: angle only at `speed`")
      .def_readonly("speed", &field::Situations::speed, "Club speed of an angle-only region [m/s] (0 otherwise)")
      .def_readonly("strategy", &field::Situations::strategy, "The teacher's default strategy here")
      .def("collection_points", [](const field::Situations& s) { return points(s.collection_points()); },
           "Hole positions a data set is collected at, (N, 2) [m]")
      .def("sample", [](const field::Situations& s, int n, std::uint64_t seed) {
             if (n < 0) throw InputError(fmt::format("sample: n: expected >= 0, got {}", n));
             return points(s.sample(n, seed));
           }, py::arg("n"), py::arg("seed") = 1,
           "`n` test situations drawn uniformly from the region with `seed`, (n, 2) [m]")
      .def_property_readonly("bounds", &field::Situations::bounds,
                             "(x_min, x_max, y_min, y_max) [m] of every hole the region holds or samples");

  py::class_<field::Field>(m, "Field", "A minigolf lane: bounds, surface, tee, hole, ball, resistances.")
      .def_static("load", [](const std::string& name) { return field::load_field(name); }, py::arg("name_or_path"),
                  "Loads a shipped field by name ('flat') or a field YAML file by path.")
      .def_static("shipped", &field::list_shipped_fields, "Names of the shipped fields")
      .def_readonly("name", &field::Field::name)
      .def_readonly("description", &field::Field::description)
      .def_readonly("source", &field::Field::source, "File the field was read from")
      .def_readonly("bounds", &field::Field::bounds, "Lane (x_min, x_max, y_min, y_max) [m]")
      .def_readonly("tee", &field::Field::tee, "Ball start (x, y) [m]")
      .def_property_readonly("hole_position", [](const field::Field& f) { return f.hole.position; },
                             "Default hole centre (x, y) [m]")
      .def_property_readonly("hole_diameter", [](const field::Field& f) { return f.hole.diameter; }, "[m]")
      .def_property_readonly("hole_depth", [](const field::Field& f) { return f.hole.depth; }, "[m]")
      .def_property_readonly("ball_radius", [](const field::Field& f) { return f.ball.radius; }, "[m]")
      .def_property_readonly("ball_mass", [](const field::Field& f) { return f.ball.mass; }, "[kg]")
      .def_readonly("rolling_resistance", &field::Field::rolling_resistance, "Penner's rho [-]")
      .def_readonly("sliding_friction", &field::Field::sliding_friction, "Ball-lane Coulomb friction [-]")
      .def_readonly("situations", &field::Field::situations)
      .def("region", &field::region_from_spec,
           py::arg("spec") = "",
           "The field's region of situations, or the one of `spec` (as `--situations`: line:X0,Y0:X1,Y1:N, "
           "grid:X0,X1:Y0,Y1:NX,NY, box:..., list:X,Y;X,Y), checked against the lane (ValueError)")
      .def("check_hole", [](const field::Field& f, std::array<double, 2> hole) { field::check_hole_position(f, hole); },
           py::arg("hole"), "Raises ValueError unless a hole at (x, y) [m] lies on the lane and off the tee")
      .def("height", [](const field::Field& f, py::object x, py::object y) -> py::object {
             const py::module_ np = py::module_::import("numpy");
             const py::tuple b = np.attr("broadcast_arrays")(np.attr("asarray")(x, "float64"), np.attr("asarray")(y, "float64"));
             const Array bx = np.attr("ascontiguousarray")(b[0]), by = np.attr("ascontiguousarray")(b[1]);
             Array out(std::vector<py::ssize_t>(bx.shape(), bx.shape() + bx.ndim()));
             for (py::ssize_t i = 0; i < bx.size(); ++i) {
               if (!std::isfinite(bx.data()[i]) || !std::isfinite(by.data()[i]))
                 throw InputError(fmt::format("Field.height: expected finite x and y, got ({}, {}) at index {}",
                                              bx.data()[i], by.data()[i], i));
               out.mutable_data()[i] = f.height(bx.data()[i], by.data()[i]);
             }
             if (bx.ndim() == 0) return py::float_(out.data()[0]);
             return out;
           }, py::arg("x"), py::arg("y"), "Lane height at (x, y) [m] (arrays broadcast)")
      .def("__repr__", [](const field::Field& f) { return fmt::format("<minigolf.Field '{}'>", f.name); });

  // ---------------------------------------------------------------- worlds
  py::class_<sim::World>(m, "World",
                         "A field's MuJoCo world (immutable, shared by threads). `model_*` arrays are read-only "
                         "numpy views of the live mjModel.")
      .def_property_readonly("field", &sim::World::field, py::return_value_policy::reference_internal)
      .def("make_data", [](const sim::World& w) {
             Data d;
             d.world = &w;
             d.owned = w.make_data();
             d.d = d.owned.get();
             return d;
           }, py::keep_alive<0, 1>(), "A fresh mjData (ball on the tee, hole at the field's default)")
      .def("reset", [](const sim::World& w, Data& d) { w.reset(data_of(w, d)); }, "Ball on the tee, hole at the default")
      .def("step", [](const sim::World& w, Data& d, int n) {
             mjData* dd = data_of(w, d);
             if (n < 0) throw InputError(fmt::format("step: n: expected >= 0, got {}", n));
             py::gil_scoped_release release;
             for (int i = 0; i < n; ++i) w.step(dd);
           }, py::arg("data"), py::arg("n") = 1, "`n` physics steps (rolling resistance included) of timestep s")
      .def("set_hole", [](const sim::World& w, Data& d, std::array<double, 2> p) { w.set_hole(data_of(w, d), p); },
           "Moves the hole to (x, y) [m]")
      .def("hole_position", [](const sim::World& w, const Data& d) { return w.hole_position(data_of(w, d)); }, "[m]")
      .def_property_readonly("mjcf", &sim::World::mjcf, "The generated MJCF text")
      .def_property_readonly("nq", [](const sim::World& w) { return w.model()->nq; })
      .def_property_readonly("nv", [](const sim::World& w) { return w.model()->nv; })
      .def_property_readonly("nu", [](const sim::World& w) { return w.model()->nu; })
      .def_property_readonly("nbody", [](const sim::World& w) { return w.model()->nbody; })
      .def_property_readonly("ngeom", [](const sim::World& w) { return w.model()->ngeom; })
      .def_property_readonly("timestep", [](const sim::World& w) { return w.model()->opt.timestep; }, "[s]")
      .def_property_readonly("ball_qpos", [](const sim::World& w) { return w.ids().ball_qpos; },
                             "Index of the ball's first qpos (centre x, y, z [m], then the quaternion)")
      .def_property_readonly("ball_dof", [](const sim::World& w) { return w.ids().ball_dof; },
                             "Index of the ball's first dof (linear velocity [m/s], then angular [rad/s])")
      .def("body_id", [](const sim::World& w, const std::string& name) {
             const int id = mj_name2id(w.model(), mjOBJ_BODY, name.c_str());
             if (id < 0) throw InputError(fmt::format("body_id: no body named '{}'", name));
             return id;
           })
      .def("body_name", [](const sim::World& w, int id) {
             if (id < 0 || id >= w.model()->nbody) throw InputError(fmt::format("body_name: no body {}", id));
             const char* n = mj_id2name(w.model(), mjOBJ_BODY, id);
             return std::string(n ? n : "");
           })
#define MG_MODEL_VIEW(name, rows, cols)                                                                \
  .def_property_readonly("model_" #name, [](py::object self) {                                         \
    const mjModel* mm = self.cast<const sim::World&>().model();                                        \
    return view(mm->name, mm->rows, cols, self, false);                               \
  })
      MG_MODEL_VIEW(body_pos, nbody, 3) MG_MODEL_VIEW(body_quat, nbody, 4) MG_MODEL_VIEW(body_mass, nbody, 1)
      MG_MODEL_VIEW(body_inertia, nbody, 3) MG_MODEL_VIEW(geom_size, ngeom, 3) MG_MODEL_VIEW(geom_pos, ngeom, 3)
      MG_MODEL_VIEW(geom_friction, ngeom, 3) MG_MODEL_VIEW(geom_type, ngeom, 1) MG_MODEL_VIEW(jnt_range, njnt, 2)
      MG_MODEL_VIEW(jnt_qposadr, njnt, 1) MG_MODEL_VIEW(dof_damping, nv, 1) MG_MODEL_VIEW(actuator_ctrlrange, nu, 2)
      MG_MODEL_VIEW(qpos0, nq, 1);
#undef MG_MODEL_VIEW

  py::class_<Data>(m, "Data",
                   "An mjData of a world. Its arrays are writable numpy views of the live data: they see every "
                   "step and every write goes into the simulation.")
      .def_property("time", [](const Data& d) { return d.d->time; }, [](Data& d, double t) { d.d->time = t; },
                    "Simulation time [s]")
#define MG_DATA_VIEW(name, rows, cols)                                                                 \
  .def_property_readonly(#name, [](py::object self) {                                                  \
    Data& dd = self.cast<Data&>();                                                                     \
    const mjModel* mm = dd.world->model();                                                             \
    return view(dd.d->name, mm->rows, cols, self, true);                              \
  })
      MG_DATA_VIEW(qpos, nq, 1) MG_DATA_VIEW(qvel, nv, 1) MG_DATA_VIEW(qacc, nv, 1) MG_DATA_VIEW(ctrl, nu, 1)
      MG_DATA_VIEW(qfrc_applied, nv, 1) MG_DATA_VIEW(xfrc_applied, nbody, 6) MG_DATA_VIEW(xpos, nbody, 3)
      MG_DATA_VIEW(xquat, nbody, 4) MG_DATA_VIEW(xmat, nbody, 9) MG_DATA_VIEW(geom_xpos, ngeom, 3)
      MG_DATA_VIEW(mocap_pos, nmocap, 3) MG_DATA_VIEW(mocap_quat, nmocap, 4) MG_DATA_VIEW(qfrc_actuator, nv, 1)
      MG_DATA_VIEW(qacc_warmstart, nv, 1);
#undef MG_DATA_VIEW

  // ---------------------------------------------------------------- the system
  py::class_<PySystemData>(m, "SystemData",
                           "Per-thread mutable state for putts on one System (its mjData's). One per thread.")
      .def_property_readonly("arm", py::cpp_function([](PySystemData& s) {
             Data d;
             d.world = &s.system->arm_world();
             d.d = s.data.arm.get();
             return d;
           }, py::keep_alive<0, 1>()), "The arm world's mjData (live views; full-system putts)")
      .def_property_readonly("ball", py::cpp_function([](PySystemData& s) {
             Data d;
             d.world = &s.system->ball_world();
             d.d = s.data.ball.get();
             return d;
           }, py::keep_alive<0, 1>()), "The ball-only world's mjData (live views; ball-only putts)");

  py::class_<PuttResult>(m, "PuttResult", "The outcome of one putt.")
      .def_readonly("field", &PuttResult::field)
      .def_readonly("ball_only", &PuttResult::ball_only)
      .def_readonly("hole", &PuttResult::hole, "Hole centre (x, y) [m]")
      .def_readonly("angle", &PuttResult::angle, "Requested angle [rad] (club hitting angle, or ball launch angle)")
      .def_readonly("speed", &PuttResult::speed, "Requested speed [m/s] (club speed, or ball launch speed)")
      .def_property_readonly("sunk", [](const PuttResult& r) { return r.outcome.sunk; })
      .def_property_readonly("end", [](const PuttResult& r) { return sim::to_string(r.outcome.end); },
                             "How the run ended: 'sunk', 'at rest', 'time out' or 'left the lane'")
      .def_property_readonly("rest_position", [](const PuttResult& r) { return r.outcome.rest_position; },
                             "Ball (x, y) when the run ended [m]")
      .def_property_readonly("closest_approach", [](const PuttResult& r) { return r.outcome.closest_approach; },
                             "Minimum horizontal distance ball centre - hole centre [m]")
      .def_property_readonly("approach_speed", [](const PuttResult& r) { return r.outcome.approach_speed; },
                             "Ball speed where it met the hole (or at its closest approach) [m/s]")
      .def_property_readonly("duration", [](const PuttResult& r) { return r.outcome.duration; },
                             "Simulated time until the outcome was decided [s]")
      .def_property_readonly("steps", [](const PuttResult& r) { return r.outcome.steps; }, "Physics steps")
      .def_property_readonly("trajectory", [](const PuttResult& r) { return trajectory(r.outcome); },
                             "Ball samples (N, 7): t [s], x, y, z [m], vx, vy, vz [m/s] (ball-only putts; "
                             "empty for the arm)")
      .def_property_readonly("club", [](const PuttResult& r) { return std::array{r.club.angle, r.club.speed}; },
                             "Arm: club face (angle [rad], speed [m/s]) just before contact")
      .def_property_readonly("launch", [](const PuttResult& r) { return std::array{r.launch.angle, r.launch.speed}; },
                             "Arm: ball launch (angle [rad], speed [m/s])")
      .def("to_dict", &putt_dict, "The keys and values of `minigolf putt --json`")
      .def("__repr__", [](const PuttResult& r) {
        return fmt::format("<minigolf.PuttResult {} on {}: closest approach {:.4f} m>",
                           r.outcome.sunk ? "sunk" : "missed", r.field, r.outcome.closest_approach);
      });

  py::class_<teacher::Example>(m, "Example", "A teacher's example: a sinking putt with a verified neighbourhood.")
      .def_readonly("hole", &teacher::Example::hole, "[m]")
      .def_readonly("found", &teacher::Example::found)
      .def_readonly("angle", &teacher::Example::angle, "Hitting angle [rad]")
      .def_readonly("speed", &teacher::Example::speed, "Club speed [m/s]")
      .def_readonly("margin_angle", &teacher::Example::margin_angle, "[rad] verified: angle +- this sinks")
      .def_readonly("margin_speed", &teacher::Example::margin_speed, "[m/s] verified: speed +- this sinks")
      .def_readonly("launch_angle", &teacher::Example::launch_angle, "[rad]")
      .def_readonly("launch_speed", &teacher::Example::launch_speed, "[m/s]")
      .def_readonly("full_putts", &teacher::Example::full_putts)
      .def_readonly("ball_putts", &teacher::Example::ball_putts);

  py::class_<experiments::Evaluation>(m, "Evaluation", "The robot playing test situations with a learned model.")
      .def_readonly("sunk", &experiments::Evaluation::sunk)
      .def_readonly("success_ratio", &experiments::Evaluation::success_ratio)
      .def_readonly("ci95", &experiments::Evaluation::ci95, "95 % Wilson interval of the success ratio")
      .def_readonly("oracle_found", &experiments::Evaluation::oracle_found)
      .def_readonly("oracle_ceiling", &experiments::Evaluation::oracle_ceiling, "NaN without the oracle")
      .def_property_readonly("holes", [](const experiments::Evaluation& e) {
             std::vector<std::array<double, 2>> h;
             for (const auto& r : e.rows) h.push_back(r.hole);
             return points(h);
           }, "(N, 2) [m]")
      .def_property_readonly("sunk_mask", [](const experiments::Evaluation& e) {
             std::vector<bool> s;
             for (const auto& r : e.rows) s.push_back(r.sunk);
             return s;
           });

  py::class_<system::System>(m, "System",
                             "A ready minigolf system: the field's world with the WAM and club, the ball-only "
                             "world, the hitting model and the control module. Immutable; shared by threads.")
      .def(py::init([](const std::string& field, const std::string& config, const std::string& hitting_model,
                       const std::string& plant) {
             py::gil_scoped_release release;
             return std::make_unique<system::System>(system::load_config(config, field, hitting_model),
                                                     plant.empty() ? plant::Plant{} : plant::load_plant(plant));
           }),
           py::arg("field") = "flat", py::arg("config") = "", py::arg("hitting_model") = "", py::arg("plant") = "",
           "field: shipped name or path; config: module YAML (empty: defaults); hitting_model: DS model file "
           "(empty: the configured default); plant: plant file, the world as it really is (docs/reality.md; "
           "empty: the robot's model)")
      .def_property_readonly("plant", [](const system::System& s) -> py::object {
             if (s.plant().source.empty()) return py::none();
             py::dict d;
             d["path"] = s.plant().source;
             d["hash"] = s.plant().hash;
             return d;
           }, "The plant file's path and content hash, or None")
      .def_property_readonly("field", &system::System::field, py::return_value_policy::reference_internal)
      .def_property_readonly("arm_world", &system::System::arm_world, py::return_value_policy::reference_internal,
                             "Field + WAM + club")
      .def_property_readonly("ball_world", &system::System::ball_world, py::return_value_policy::reference_internal,
                             "Field only")
      .def_property_readonly("envelope", [](const system::System& s) {
             const auto& c = s.config();
             py::dict d;
             d["angle_min"] = c.angle_min, d["angle_max"] = c.angle_max;
             d["speed_min"] = c.speed_min, d["speed_max"] = c.speed_max;
             return d;
           }, "Safe envelope of a hit request: angle [rad], club speed [m/s]")
      .def("make_data", [](const system::System& s) { return std::make_unique<PySystemData>(s); },
           py::keep_alive<0, 1>(), "Per-thread state for putts (reuse it: it caches the arm's approach)")
      .def("putt",
           [](const system::System& s, double angle, double speed, std::optional<std::array<double, 2>> hole,
              bool ball_only, double max_duration, double record_interval, PySystemData* data) {
             return do_putt(s, data, angle, speed, hole, ball_only, max_duration, record_interval);
           },
           py::arg("angle"), py::arg("speed"), py::arg("hole") = py::none(), py::arg("ball_only") = false,
           py::arg("max_duration") = 30.0, py::arg("record_interval") = 0.01, py::arg("data") = py::none(),
           "One putt. Arm (default): hitting angle `angle` [rad] and club speed `speed` [m/s] within the safe "
           "envelope. ball_only: the ball launched from the tee at `angle` [rad], `speed` [m/s]. hole: (x, y) "
           "[m] (default: the field's). max_duration [s]; record_interval: trajectory spacing [s] (0: none; "
           "time from the launch, with the arm from the club's first contact). data: a SystemData of this "
           "System (default: a fresh one). Releases the GIL.")
      .def("teach",
           [](const system::System& s, std::array<double, 2> hole, const std::string& strategy, int max_full_putts,
              int max_ball_putts, double margin_angle, double margin_speed, PySystemData* data) {
             const auto t = teacher_options(s, strategy, max_full_putts, max_ball_putts, margin_angle, margin_speed);
             Lease lease(data);
             std::optional<system::SystemData> local;
             py::gil_scoped_release release;
             return teacher::teach(s, data ? data->data : local.emplace(s), hole, t);
           },
           py::arg("hole"), py::arg("strategy") = "", py::arg("max_full_putts") = kTeacherDefaults.max_full_putts,
           py::arg("max_ball_putts") = kTeacherDefaults.max_ball_putts,
           py::arg("margin_angle") = kTeacherDefaults.margin_angle,
           py::arg("margin_speed") = kTeacherDefaults.margin_speed, py::arg("data") = py::none(),
           "The automated teacher finds a sinking putt for the hole (x, y) [m]. strategy: 'min-speed' | "
           "'min-angle' (default: the field's). Margins [rad], [m/s]. Releases the GIL.")
      .def("sweep",
           [](const system::System& s, std::vector<double> angles, std::vector<double> speeds,
              std::optional<std::array<double, 2>> hole, bool ball_only, int threads) {
             experiments::SweepOptions o;
             o.angles = std::move(angles);
             o.speeds = std::move(speeds);
             o.ball_only = ball_only;
             o.threads = threads;
             o.hole = hole ? *hole : s.field().hole.position;
             if (!ball_only)
               for (double a : o.angles)
                 for (double v : o.speeds) s.check_request(a, v, "sweep");
             std::vector<experiments::SweepCell> cells;
             {
               py::gil_scoped_release release;
               cells = experiments::run_sweep(s, o);
             }
             const py::ssize_t na = static_cast<py::ssize_t>(o.angles.size()), ns = static_cast<py::ssize_t>(o.speeds.size());
             py::array_t<bool> sunk({na, ns}), hit({na, ns});
             py::array_t<double> closest({na, ns}), la({na, ns}), ls({na, ns});
             for (py::ssize_t i = 0; i < na * ns; ++i) {
               const auto& c = cells[static_cast<std::size_t>(i)];
               sunk.mutable_data()[i] = c.outcome.sunk;
               hit.mutable_data()[i] = c.hit;
               closest.mutable_data()[i] = c.outcome.closest_approach;
               la.mutable_data()[i] = c.launch_angle;
               ls.mutable_data()[i] = c.launch_speed;
             }
             py::dict d;
             d["sunk"] = sunk, d["hit"] = hit, d["closest_approach"] = closest, d["launch_angle"] = la,
             d["launch_speed"] = ls, d["csv"] = experiments::sweep_csv(cells);
             return d;
           },
           py::arg("angles"), py::arg("speeds"), py::arg("hole") = py::none(), py::arg("ball_only") = false,
           py::arg("threads") = 0,
           "The outcome of every (angle [rad], speed [m/s]) cell: dict of (len(angles), len(speeds)) arrays "
           "(sunk, hit, closest_approach [m], launch_angle [rad], launch_speed [m/s]) and the CSV `minigolf "
           "sweep` writes. threads: 0 = all cores. Releases the GIL.")
      .def("collect",
           [](const system::System& s, const std::string& out, const std::string& situations,
              const std::string& strategy, int max_full_putts, std::uint64_t seed, int threads, bool resume) {
             const field::Situations region = field::region_from_spec(s.field(), situations);
             experiments::CollectOptions o;
             o.teacher = teacher::options_for(region, strategy);
             o.teacher.max_full_putts = max_full_putts;
             o.teacher.validate();
             o.seed = seed;
             o.threads = threads;
             o.resume = resume;
             const auto holes = region.collection_points();
             py::gil_scoped_release release;
             return experiments::collect(s, holes, o, out).examples;
           },
           py::arg("out"), py::arg("situations") = "", py::arg("strategy") = "",
           py::arg("max_full_putts") = kTeacherDefaults.max_full_putts,
           py::arg("seed") = 1, py::arg("threads") = 0, py::arg("resume") = false,
           "The teacher collects a data set at the region's collection points (or a --situations spec) into "
           "the CSV `out`, as `minigolf collect` does (resumable); returns the examples in index order. "
           "Releases the GIL.")
      .def("evaluate",
           [](const system::System& s, const learning::Model& model, int situations, std::uint64_t seed, int threads,
              bool oracle, const std::string& region_spec) {
             experiments::check_playable_model(model, "model", &s);
             experiments::EvaluateOptions o;
             o.situations = situations;
             o.seed = seed;
             o.threads = threads;
             o.oracle = oracle;
             const auto region = field::region_from_spec(s.field(), region_spec);
             o.teacher = teacher::options_for(region);
             py::gil_scoped_release release;
             return experiments::evaluate_model(s, model, region, o);
           },
           py::arg("model"), py::arg("situations") = 30, py::arg("seed") = 1, py::arg("threads") = 0,
           py::arg("oracle") = true, py::arg("region") = "",
           "The robot plays `situations` random test situations of the field's region (or a --situations spec) "
           "with the learned model; oracle: also run the teacher on each. Releases the GIL.");

  // ---------------------------------------------------------------- learners
  py::class_<learning::Model>(m, "Model", "A trained hitting-parameter learner (GPR, GMR or joint GMR).")
      .def_static("load", [](const std::string& path) { return learning::load_model(path); }, py::arg("path"))
      .def("save", [](const learning::Model& mm, const std::string& path) { learning::save_model(mm, path); },
           py::arg("path"), "Writes the model file (JSON, atomically)")
      .def_property_readonly("method", [](const learning::Model& mm) { return std::string(learning::method_name(mm.method)); })
      .def_readonly("input_names", &learning::Model::input_names)
      .def_readonly("output_names", &learning::Model::output_names)
      .def_readonly("fixed", &learning::Model::fixed, "Constant quantities not learned: (name, value) pairs")
      .def("predict", [](const learning::Model& mm, const Array& x) {
             const Eigen::MatrixXd q = to_matrix(x, "predict");
             if (q.cols() != mm.num_inputs())
               throw InputError(fmt::format("predict: expected {} input columns ({}), got {}", mm.num_inputs(),
                                            fmt::join(mm.input_names, ","), q.cols()));
             learning::Predictions p;
             {
               py::gil_scoped_release release;
               p = learning::predict(mm, q);
             }
             return py::make_tuple(matrix(p.mean), matrix(p.std));
           }, py::arg("x"), "Predictive (mean, std), each (N, O), for inputs (N, I) in the model's units");

  m.def("train",
        [](const Array& x, const Array& y, const std::string& method, std::vector<std::string> input_names,
           std::vector<std::string> output_names, int num_gaussians, const std::string& selection, int max_gaussians,
           int restarts, std::uint64_t seed, double reg_covar, std::vector<std::pair<std::string, double>> fixed) {
          learning::Dataset d;
          d.source = "train";
          d.inputs = to_matrix(x, "train: x");
          d.outputs = to_matrix(y, "train: y");
          if (d.inputs.rows() != d.outputs.rows())
            throw InputError(fmt::format("train: x has {} rows, y has {}", d.inputs.rows(), d.outputs.rows()));
          d.input_names = input_names.empty() ? default_names(static_cast<int>(d.inputs.cols()), learning::kDefaultInputs, "x")
                                              : std::move(input_names);
          d.output_names = output_names.empty() ? default_names(static_cast<int>(d.outputs.cols()), learning::kDefaultOutputs, "y")
                                                : std::move(output_names);
          if (static_cast<int>(d.input_names.size()) != d.inputs.cols() ||
              static_cast<int>(d.output_names.size()) != d.outputs.cols())
            throw InputError("train: the names do not match the columns of x and y");
          learning::TrainOptions o;
          o.method = learning::parse_method(method);
          o.num_gaussians = num_gaussians;
          o.selection = learning::parse_selection(selection);
          o.max_gaussians = max_gaussians;
          o.restarts = restarts;
          o.seed = seed;
          o.em.reg_covar = reg_covar;
          o.validate();
          for (const auto& [name, value] : fixed)
            if (!std::isfinite(value)) throw InputError(fmt::format("train: fixed '{}': expected a finite value, got {}", name, value));
          py::gil_scoped_release release;
          learning::Model model = learning::train(d, o);
          model.fixed = std::move(fixed);
          return model;
        },
        py::arg("x"), py::arg("y"), py::arg("method") = "gpr", py::arg("input_names") = std::vector<std::string>{},
        py::arg("output_names") = std::vector<std::string>{}, py::arg("num_gaussians") = 0,
        py::arg("selection") = "bic", py::arg("max_gaussians") = 5, py::arg("restarts") = 10, py::arg("seed") = 1,
        py::arg("reg_covar") = 1e-2, py::arg("fixed") = std::vector<std::pair<std::string, double>>{},
        "Trains a learner on inputs x (N, I) and outputs y (N, O). method: 'gpr' | 'gmr' | 'joint-gmr'. Names "
        "default to xi_x, xi_y [m] and angle [rad], speed [m/s]. num_gaussians 0: chosen by `selection` "
        "('bic' | 'cv') up to max_gaussians. reg_covar: EM covariance regularisation (standardised units). "
        "fixed: constant quantities a player uses as they are, e.g. [('speed', 1.2)] for an angle-only data set "
        "(what `minigolf train` records from a constant column). Releases the GIL.");
  m.def("load_dataset",
        [](const std::string& path, std::vector<std::string> inputs, std::vector<std::string> outputs) {
          const learning::Dataset d = learning::load_dataset(path, inputs, outputs);
          return py::make_tuple(matrix(d.inputs), matrix(d.outputs));
        },
        py::arg("path"), py::arg("inputs") = learning::kDefaultInputs, py::arg("outputs") = learning::kDefaultOutputs,
        "Reads a data set CSV: (x (N, I), y (N, O)) of the named columns");

  // ---------------------------------------------------------------- the hitting DS
  py::class_<ds::HittingModel>(m, "HittingModel", "The hitting DS model (SEDS + strength GMM).")
      .def_static("load", [](const std::string& path) { return ds::read_hitting_model(system::resolve_data_path(path)); },
                  py::arg("path") = "data/models/hitting-default.json")
      .def_property_readonly("x_star", [](const ds::HittingModel& h) { return std::array{h.x_star()[0], h.x_star()[1], h.x_star()[2]}; },
                             "Ball contact point x* [m, world]")
      .def_property_readonly("default_speed", &ds::HittingModel::default_speed, "v(x*) [m/s]")
      .def("rollout",
           [](const ds::HittingModel& h, double angle, double speed, std::array<double, 3> start,
              const std::string& modulator, double dt, double max_duration) {
             ds::HittingCommand c;
             c.angle = angle;
             c.speed = speed;
             c.modulator = ds::parse_modulator(modulator);
             c.start = Eigen::Vector3d(start[0], start[1], start[2]);
             ds::RolloutOptions o;
             o.dt = dt;
             o.max_duration = max_duration;
             o.validate();
             ds::RolloutResult r;
             {
               py::gil_scoped_release release;
               r = ds::rollout(h, c, o);
             }
             const auto n = static_cast<py::ssize_t>(r.t.size());
             py::array_t<double> t(n), x({n, py::ssize_t{3}}), xd({n, py::ssize_t{3}});
             for (py::ssize_t i = 0; i < n; ++i) {
               t.mutable_data()[i] = r.t[static_cast<std::size_t>(i)];
               for (int j = 0; j < 3; ++j) {
                 x.mutable_data()[i * 3 + j] = r.x[static_cast<std::size_t>(i)][j];
                 xd.mutable_data()[i * 3 + j] = r.xdot[static_cast<std::size_t>(i)][j];
               }
             }
             py::dict d;
             d["reached"] = r.reached, d["stop_reason"] = r.stop_reason, d["position_error"] = r.position_error;
             d["duration"] = r.duration, d["steps"] = r.steps, d["t"] = t, d["x"] = x, d["xdot"] = xd;
             return d;
           },
           py::arg("angle"), py::arg("speed"), py::arg("start"), py::arg("modulator") = "constant",
           py::arg("dt") = 0.002, py::arg("max_duration") = 20.0,
           "Integrates the DS (RK4, step dt [s]) from `start` [m, world] for hitting angle [rad] and speed [m/s] "
           "until the ball is reached: dict with reached, stop_reason, position_error [m], duration [s], t (N,) [s], "
           "x (N, 3) [m], xdot (N, 3) [m/s]. Releases the GIL.");

  python::bind_render(m);
}
