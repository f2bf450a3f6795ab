// minigolf.PuttResult and System.putt's run: system::putt (as `minigolf putt`), its report and
// its `--json` object.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "python/bindings.hpp"
#include "sim/putt.hpp"

namespace mg::python {
namespace {

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

}  // namespace

PuttResult putt(const system::System& sys, PySystemData* pdata, const system::PuttSpec& spec) {
  PuttResult r{spec, {}, {}};
  check_owner(sys, pdata);
  Lease lease(pdata);
  std::optional<system::SystemData> local;
  {
    py::gil_scoped_release release;
    system::SystemData& data = pdata ? pdata->data : local.emplace(sys);
    r.report = system::putt(sys, data, spec);
    r.json = system::putt_json(sys, spec, r.report);
  }
  return r;
}

void bind_putts(py::module_& m) {
  py::class_<PuttResult>(m, "PuttResult", "The outcome of one putt.")
      .def_property_readonly(
          "field", [](const PuttResult& r) { return r.json.at("field").get<std::string>(); })
      .def_property_readonly("ball_only", [](const PuttResult& r) { return r.spec.ball_only; })
      .def_property_readonly(
          "hole", [](const PuttResult& r) { return r.report.hole; }, "Hole centre (x, y) [m]")
      .def_property_readonly(
          "ball", [](const PuttResult& r) { return r.report.ball; },
          "Where the ball lay (x, y) [m]")
      .def_property_readonly(
          "aim", [](const PuttResult& r) { return r.report.aim; },
          "The base's facing [rad, world] (arm putts; 0 ball-only)")
      .def_property_readonly(
          "angle", [](const PuttResult& r) { return r.spec.angle; },
          "Requested angle [rad] (club hitting angle, or ball launch angle)")
      .def_property_readonly(
          "speed", [](const PuttResult& r) { return r.spec.speed; },
          "Requested speed [m/s] (club speed, or ball launch speed)")
      .def_property_readonly("sunk", [](const PuttResult& r) { return r.report.outcome.sunk; })
      .def_property_readonly(
          "end", [](const PuttResult& r) { return sim::to_string(r.report.outcome.end); },
          "How the run ended: 'sunk', 'at rest', 'time out' or 'left the lane'")
      .def_property_readonly(
          "rest_position", [](const PuttResult& r) { return r.report.outcome.rest_position; },
          "Ball (x, y) when the run ended [m]")
      .def_property_readonly(
          "closest_approach", [](const PuttResult& r) { return r.report.outcome.closest_approach; },
          "Minimum horizontal distance ball centre - hole centre [m]")
      .def_property_readonly(
          "approach_speed", [](const PuttResult& r) { return r.report.outcome.approach_speed; },
          "Ball speed where it met the hole (or at its closest approach) [m/s]")
      .def_property_readonly(
          "duration", [](const PuttResult& r) { return r.report.outcome.duration; },
          "Simulated time until the outcome was decided [s]")
      .def_property_readonly(
          "steps", [](const PuttResult& r) { return r.report.outcome.steps; }, "Physics steps")
      .def_property_readonly(
          "trajectory", [](const PuttResult& r) { return trajectory(r.report.outcome); },
          "Ball samples (N, 7): t [s], x, y, z [m], vx, vy, vz [m/s] (ball-only putts; "
          "empty for the arm)")
      .def_property_readonly(
          "club",
          [](const PuttResult& r) {
            return std::array{r.report.club.angle, r.report.club.speed};
          },
          "Arm: club face (angle [rad], speed [m/s]) just before contact")
      .def_property_readonly(
          "launch",
          [](const PuttResult& r) {
            return std::array{r.report.launch.angle, r.report.launch.speed};
          },
          "Arm: ball launch (angle [rad], speed [m/s])")
      .def(
          "to_dict",
          [](const PuttResult& r) {
            // through JSON text, as the CLI prints it: the same floats, lists for pairs
            return py::module_::import("json").attr("loads")(r.json.dump());
          },
          "The keys and values of `minigolf putt --json`")
      .def("__repr__", [](const PuttResult& r) {
        return fmt::format("<minigolf.PuttResult {} on {}: closest approach {:.4f} m>",
                           r.report.outcome.sunk ? "sunk" : "missed",
                           r.json.at("field").get<std::string>(),
                           r.report.outcome.closest_approach);
      });
}

}  // namespace mg::python
