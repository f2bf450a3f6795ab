// minigolf.Field and minigolf.Situations: the lane, its surface and its regions of situations.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "field/field.hpp"
#include "field/situations.hpp"
#include "python/bindings.hpp"

namespace mg::python {

namespace {

/// (N, 4) array of ball_x, ball_y, hole_x, hole_y.
Array situations_array(const std::vector<field::Situation>& situations) {
  Array out({static_cast<py::ssize_t>(situations.size()), py::ssize_t{4}});
  double* d = out.mutable_data();
  for (const auto& s : situations) {
    *d++ = s.ball[0];
    *d++ = s.ball[1];
    *d++ = s.hole[0];
    *d++ = s.hole[1];
  }
  return out;
}

}  // namespace

void bind_fields(py::module_& m) {
  py::class_<field::Situations>(m, "Situations",
                                "Where the hole may be on a field (the region a learner covers).")
      .def_property_readonly(
          "shape", [](const field::Situations& s) { return field::to_string(s.shape); },
          "'line', 'grid', 'box' or 'list'")
      .def_readonly("learn_speed", &field::Situations::learn_speed,
                    "True: outputs (angle, speed); False: angle only at `speed`")
      .def_readonly("speed", &field::Situations::speed,
                    "Club speed of an angle-only region [m/s] (0 otherwise)")
      .def_readonly("strategy", &field::Situations::strategy, "The teacher's default strategy here")
      .def(
          "collection_points",
          [](const field::Situations& s) { return points(s.collection_points()); },
          "Hole positions a data set is collected at, (N, 2) [m]")
      .def(
          "sample",
          [](const field::Situations& s, int n, std::uint64_t seed) {
            if (n < 0) throw InputError(fmt::format("sample: n: expected >= 0, got {}", n));
            return points(s.sample(n, seed));
          },
          py::arg("n"), py::arg("seed") = 1,
          "`n` test situations drawn uniformly from the region with `seed`, (n, 2) [m]")
      .def_property_readonly(
          "bounds", [](const field::Situations& s) { return s.bounds(); },
          "(x_min, x_max, y_min, y_max) [m] of every hole the region holds or samples")
      .def_property_readonly(
          "ball_bounds",
          [](const field::Situations& s) -> std::optional<std::array<double, 4>> {
            if (!s.balls) return std::nullopt;
            return s.balls->bounds();
          },
          "(x_min, x_max, y_min, y_max) [m] of the ball region, or None (the ball on the tee)")
      .def_property_readonly("learner_inputs", &field::Situations::learner_inputs,
                             "What a learner of this region takes: xi_x, xi_y (hole - ball) or "
                             "one of them, plus ball_x, ball_y on a lane that is not "
                             "translation-invariant with a ball region")
      .def_property_readonly("learner_outputs", &field::Situations::learner_outputs,
                             "['angle', 'speed'] or ['angle']");

  py::class_<field::Field>(m, "Field",
                           "A minigolf lane: bounds, surface, tee, hole, ball, resistances.")
      .def_static(
          "load", [](const std::string& name) { return field::load_field(name); },
          py::arg("name_or_path"),
          "Loads a shipped field by name ('flat') or a field YAML file by path.")
      .def_static("shipped", &field::list_shipped_fields, "Names of the shipped fields")
      .def_readonly("name", &field::Field::name)
      .def_readonly("description", &field::Field::description)
      .def_readonly("source", &field::Field::source, "File the field was read from")
      .def_readonly("bounds", &field::Field::bounds, "Lane (x_min, x_max, y_min, y_max) [m]")
      .def_readonly("tee", &field::Field::tee, "Ball start (x, y) [m]")
      .def_property_readonly(
          "hole_position", [](const field::Field& f) { return f.hole.position; },
          "Default hole centre (x, y) [m]")
      .def_property_readonly(
          "hole_diameter", [](const field::Field& f) { return f.hole.diameter; }, "[m]")
      .def_property_readonly(
          "hole_depth", [](const field::Field& f) { return f.hole.depth; }, "[m]")
      .def_property_readonly(
          "ball_radius", [](const field::Field& f) { return f.ball.radius; }, "[m]")
      .def_property_readonly(
          "ball_mass", [](const field::Field& f) { return f.ball.mass; }, "[kg]")
      .def_readonly("rolling_resistance", &field::Field::rolling_resistance, "Penner's rho [-]")
      .def_readonly("sliding_friction", &field::Field::sliding_friction,
                    "Ball-lane Coulomb friction [-]")
      .def_readonly("situations", &field::Field::situations)
      .def("region", &field::region_from_spec, py::arg("spec") = "", py::arg("balls") = "",
           "The field's region of situations, or the one of `spec` (as `--situations`: "
           "line:X0,Y0:X1,Y1:N, "
           "grid:X0,X1:Y0,Y1:NX,NY, box:..., list:X,Y;X,Y), checked against the lane (ValueError); "
           "`balls`: where the ball lies, in the same grammar (default: the field's, else the tee)")
      .def(
          "collection_situations",
          [](const field::Field& f, const field::Situations& region) {
            return situations_array(region.collection_situations(f));
          },
          py::arg("region"),
          "The (ball, hole) pairs a data set of `region` is collected at, (N, 4) [m]: ball_x, "
          "ball_y, hole_x, hole_y (the ball on the tee without a ball region)")
      .def(
          "sample_situations",
          [](const field::Field& f, const field::Situations& region, int n, std::uint64_t seed) {
            if (n < 0)
              throw InputError(fmt::format("sample_situations: n: expected >= 0, got {}", n));
            return situations_array(region.sample_situations(f, n, seed));
          },
          py::arg("region"), py::arg("n"), py::arg("seed") = 1,
          "`n` test situations of `region` with `seed` (as evaluate draws them), (n, 4) [m]: "
          "ball_x, ball_y, hole_x, hole_y")
      .def(
          "check_hole",
          [](const field::Field& f, std::array<double, 2> hole) {
            field::check_hole_position(f, hole);
          },
          py::arg("hole"),
          "Raises ValueError unless a hole at (x, y) [m] lies on the lane and off the tee")
      .def(
          "height",
          [](const field::Field& f, py::object x, py::object y) -> py::object {
            const py::module_ np = py::module_::import("numpy");
            const py::tuple b = np.attr("broadcast_arrays")(np.attr("asarray")(x, "float64"),
                                                            np.attr("asarray")(y, "float64"));
            const Array bx = np.attr("ascontiguousarray")(b[0]),
                        by = np.attr("ascontiguousarray")(b[1]);
            Array out(std::vector<py::ssize_t>(bx.shape(), bx.shape() + bx.ndim()));
            for (py::ssize_t i = 0; i < bx.size(); ++i) {
              if (!std::isfinite(bx.data()[i]) || !std::isfinite(by.data()[i]))
                throw InputError(
                    fmt::format("Field.height: expected finite x and y, got ({}, {}) at index {}",
                                bx.data()[i], by.data()[i], i));
              out.mutable_data()[i] = f.height(bx.data()[i], by.data()[i]);
            }
            if (bx.ndim() == 0) return py::float_(out.data()[0]);
            return out;
          },
          py::arg("x"), py::arg("y"), "Lane height at (x, y) [m] (arrays broadcast)")
      .def("__repr__",
           [](const field::Field& f) { return fmt::format("<minigolf.Field '{}'>", f.name); });
}

}  // namespace mg::python
