// minigolf.System: putts (arm and ball only), the teacher, sweeps, data collection and evaluation,
// as the CLI's commands run them. Long calls release the GIL.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "control/full_system.hpp"
#include "experiments/collect.hpp"
#include "experiments/evaluate.hpp"
#include "experiments/sweep.hpp"
#include "field/situations.hpp"
#include "learning/learner.hpp"
#include "python/bindings.hpp"
#include "sim/putt.hpp"
#include "system/distributed.hpp"
#include "teacher/teacher.hpp"

namespace mg::python {
namespace {

// ---- putts

struct PuttResult {
  std::string field;
  bool ball_only = true;
  std::array<double, 2> hole{0, 0};
  std::array<double, 2> ball{0, 0};  ///< where it lay
  double aim = 0;                    ///< the base's facing (arm putts) [rad]
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
  d["ball"] = py::make_tuple(r.ball[0], r.ball[1]);
  if (!r.ball_only) d["aim"] = r.aim;
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
                   std::optional<std::array<double, 2>> hole_opt, bool ball_only,
                   double max_duration, double record_interval,
                   std::optional<std::array<double, 2>> ball, std::optional<double> aim) {
  PuttResult r;
  r.field = sys.field().name;
  r.ball_only = ball_only;
  r.angle = angle;
  r.speed = speed;
  r.hole = hole_opt ? *hole_opt : sys.field().hole.position;
  r.plant_path = sys.plant().source;
  r.plant_hash = sys.plant().hash;
  r.ball = ball ? *ball : sys.field().tee;
  if (ball_only && aim)
    throw InputError("aim: only with the arm (a ball-only putt's angle is its aim)");
  if (ball) system::check_ball_position(sys.field(), *ball, "ball");
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
    request.start = ball;
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
  if (ball || aim) options.stance = system::putt_stance(sys, r.ball, r.hole, aim);
  r.aim = options.stance.yaw;
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

/// The teacher's options for the field's region, with the Python arguments' budgets and margins.
teacher::TeacherOptions teacher_options(const system::System& sys, const std::string& strategy,
                                        int max_full_putts, int max_ball_putts, double margin_angle,
                                        double margin_speed) {
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

void bind_system(py::module_& m) {
  py::class_<PySystemData>(
      m, "SystemData",
      "Per-thread mutable state for putts on one System (its mjData's). One per thread.")
      .def_property_readonly("arm",
                             py::cpp_function(
                                 [](PySystemData& s) {
                                   Data d;
                                   d.world = &s.system->arm_world();
                                   d.d = s.data.arm.get();
                                   return d;
                                 },
                                 py::keep_alive<0, 1>()),
                             "The arm world's mjData (live views; full-system putts)")
      .def_property_readonly("ball",
                             py::cpp_function(
                                 [](PySystemData& s) {
                                   Data d;
                                   d.world = &s.system->ball_world();
                                   d.d = s.data.ball.get();
                                   return d;
                                 },
                                 py::keep_alive<0, 1>()),
                             "The ball-only world's mjData (live views; ball-only putts)");

  py::class_<PuttResult>(m, "PuttResult", "The outcome of one putt.")
      .def_readonly("field", &PuttResult::field)
      .def_readonly("ball_only", &PuttResult::ball_only)
      .def_readonly("hole", &PuttResult::hole, "Hole centre (x, y) [m]")
      .def_readonly("ball", &PuttResult::ball, "Where the ball lay (x, y) [m]")
      .def_readonly("aim", &PuttResult::aim,
                    "The base's facing [rad, world] (arm putts; 0 ball-only)")
      .def_readonly("angle", &PuttResult::angle,
                    "Requested angle [rad] (club hitting angle, or ball launch angle)")
      .def_readonly("speed", &PuttResult::speed,
                    "Requested speed [m/s] (club speed, or ball launch speed)")
      .def_property_readonly("sunk", [](const PuttResult& r) { return r.outcome.sunk; })
      .def_property_readonly(
          "end", [](const PuttResult& r) { return sim::to_string(r.outcome.end); },
          "How the run ended: 'sunk', 'at rest', 'time out' or 'left the lane'")
      .def_property_readonly(
          "rest_position", [](const PuttResult& r) { return r.outcome.rest_position; },
          "Ball (x, y) when the run ended [m]")
      .def_property_readonly(
          "closest_approach", [](const PuttResult& r) { return r.outcome.closest_approach; },
          "Minimum horizontal distance ball centre - hole centre [m]")
      .def_property_readonly(
          "approach_speed", [](const PuttResult& r) { return r.outcome.approach_speed; },
          "Ball speed where it met the hole (or at its closest approach) [m/s]")
      .def_property_readonly(
          "duration", [](const PuttResult& r) { return r.outcome.duration; },
          "Simulated time until the outcome was decided [s]")
      .def_property_readonly(
          "steps", [](const PuttResult& r) { return r.outcome.steps; }, "Physics steps")
      .def_property_readonly(
          "trajectory", [](const PuttResult& r) { return trajectory(r.outcome); },
          "Ball samples (N, 7): t [s], x, y, z [m], vx, vy, vz [m/s] (ball-only putts; "
          "empty for the arm)")
      .def_property_readonly(
          "club",
          [](const PuttResult& r) {
            return std::array{r.club.angle, r.club.speed};
          },
          "Arm: club face (angle [rad], speed [m/s]) just before contact")
      .def_property_readonly(
          "launch",
          [](const PuttResult& r) {
            return std::array{r.launch.angle, r.launch.speed};
          },
          "Arm: ball launch (angle [rad], speed [m/s])")
      .def("to_dict", &putt_dict, "The keys and values of `minigolf putt --json`")
      .def("__repr__", [](const PuttResult& r) {
        return fmt::format("<minigolf.PuttResult {} on {}: closest approach {:.4f} m>",
                           r.outcome.sunk ? "sunk" : "missed", r.field, r.outcome.closest_approach);
      });

  py::class_<teacher::Example>(m, "Example",
                               "A teacher's example: a sinking putt with a verified neighbourhood.")
      .def_readonly("hole", &teacher::Example::hole, "[m]")
      .def_readonly("found", &teacher::Example::found)
      .def_readonly("angle", &teacher::Example::angle, "Hitting angle [rad]")
      .def_readonly("speed", &teacher::Example::speed, "Club speed [m/s]")
      .def_readonly("margin_angle", &teacher::Example::margin_angle,
                    "[rad] verified: angle +- this sinks")
      .def_readonly("margin_speed", &teacher::Example::margin_speed,
                    "[m/s] verified: speed +- this sinks")
      .def_readonly("launch_angle", &teacher::Example::launch_angle, "[rad]")
      .def_readonly("launch_speed", &teacher::Example::launch_speed, "[m/s]")
      .def_readonly("full_putts", &teacher::Example::full_putts)
      .def_readonly("ball_putts", &teacher::Example::ball_putts);

  py::class_<experiments::Evaluation>(m, "Evaluation",
                                      "The robot playing test situations with a learned model.")
      .def_readonly("sunk", &experiments::Evaluation::sunk)
      .def_readonly("success_ratio", &experiments::Evaluation::success_ratio)
      .def_readonly("ci95", &experiments::Evaluation::ci95,
                    "95 % Wilson interval of the success ratio")
      .def_readonly("oracle_found", &experiments::Evaluation::oracle_found)
      .def_readonly("oracle_ceiling", &experiments::Evaluation::oracle_ceiling,
                    "NaN without the oracle")
      .def_property_readonly(
          "holes",
          [](const experiments::Evaluation& e) {
            std::vector<std::array<double, 2>> h;
            for (const auto& r : e.rows) h.push_back(r.hole);
            return points(h);
          },
          "(N, 2) [m]")
      .def_property_readonly("sunk_mask", [](const experiments::Evaluation& e) {
        std::vector<bool> s;
        for (const auto& r : e.rows) s.push_back(r.sunk);
        return s;
      });

  py::class_<system::System>(
      m, "System",
      "A ready minigolf system: the field's world with the WAM and club, the ball-only "
      "world, the hitting model and the control module. Immutable; shared by threads.")
      .def(py::init([](const std::string& field, const std::string& config,
                       const std::string& hitting_model, const std::string& plant) {
             py::gil_scoped_release release;
             return std::make_unique<system::System>(
                 system::load_config(config, field, hitting_model),
                 plant.empty() ? plant::Plant{} : plant::load_plant(plant));
           }),
           py::arg("field") = "flat", py::arg("config") = "", py::arg("hitting_model") = "",
           py::arg("plant") = "",
           "field: shipped name or path; config: module YAML (empty: defaults); hitting_model: DS "
           "model file "
           "(empty: the configured default); plant: plant file, the world as it really is "
           "(docs/reality.md; "
           "empty: the robot's model)")
      .def_property_readonly(
          "plant",
          [](const system::System& s) -> py::object {
            if (s.plant().source.empty()) return py::none();
            py::dict d;
            d["path"] = s.plant().source;
            d["hash"] = s.plant().hash;
            return d;
          },
          "The plant file's path and content hash, or None")
      .def_property_readonly("field", &system::System::field,
                             py::return_value_policy::reference_internal)
      .def_property_readonly("arm_world", &system::System::arm_world,
                             py::return_value_policy::reference_internal, "Field + WAM + club")
      .def_property_readonly("ball_world", &system::System::ball_world,
                             py::return_value_policy::reference_internal, "Field only")
      .def_property_readonly(
          "envelope",
          [](const system::System& s) {
            const auto& c = s.config();
            py::dict d;
            d["angle_min"] = c.angle_min, d["angle_max"] = c.angle_max;
            d["speed_min"] = c.speed_min, d["speed_max"] = c.speed_max;
            return d;
          },
          "Safe envelope of a hit request: angle [rad], club speed [m/s]")
      .def(
          "make_data", [](const system::System& s) { return std::make_unique<PySystemData>(s); },
          py::keep_alive<0, 1>(),
          "Per-thread state for putts (reuse it: it caches the arm's approach)")
      .def(
          "putt",
          [](const system::System& s, double angle, double speed,
             std::optional<std::array<double, 2>> hole, bool ball_only, double max_duration,
             double record_interval, PySystemData* data, std::optional<std::array<double, 2>> ball,
             std::optional<double> aim) {
            return do_putt(s, data, angle, speed, hole, ball_only, max_duration, record_interval,
                           ball, aim);
          },
          py::arg("angle"), py::arg("speed"), py::arg("hole") = py::none(),
          py::arg("ball_only") = false, py::arg("max_duration") = 30.0,
          py::arg("record_interval") = 0.01, py::arg("data") = py::none(),
          py::arg("ball") = py::none(), py::arg("aim") = py::none(),
          "One putt. Arm (default): hitting angle `angle` [rad] and club speed `speed` [m/s] "
          "within the safe "
          "envelope. ball_only: the ball launched from the tee at `angle` [rad], `speed` [m/s]. "
          "hole: (x, y) "
          "[m] (default: the field's). max_duration [s]; record_interval: trajectory spacing [s] "
          "(0: none; "
          "time from the launch, with the arm from the club's first contact). data: a SystemData "
          "of this "
          "System (default: a fresh one). ball: where the ball lies (x, y) [m] (default: the tee); "
          "with the arm the base stands beside it facing `aim` [rad, world] (default: the hole) "
          "and `angle` is in its frame. Releases the GIL.")
      .def(
          "teach",
          [](const system::System& s, std::array<double, 2> hole, const std::string& strategy,
             int max_full_putts, int max_ball_putts, double margin_angle, double margin_speed,
             PySystemData* data) {
            const auto t = teacher_options(s, strategy, max_full_putts, max_ball_putts,
                                           margin_angle, margin_speed);
            Lease lease(data);
            std::optional<system::SystemData> local;
            py::gil_scoped_release release;
            return teacher::teach(s, data ? data->data : local.emplace(s), hole, t);
          },
          py::arg("hole"), py::arg("strategy") = "",
          py::arg("max_full_putts") = kTeacherDefaults.max_full_putts,
          py::arg("max_ball_putts") = kTeacherDefaults.max_ball_putts,
          py::arg("margin_angle") = kTeacherDefaults.margin_angle,
          py::arg("margin_speed") = kTeacherDefaults.margin_speed, py::arg("data") = py::none(),
          "The automated teacher finds a sinking putt for the hole (x, y) [m]. strategy: "
          "'min-speed' | "
          "'min-angle' (default: the field's). Margins [rad], [m/s]. Releases the GIL.")
      .def(
          "sweep",
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
            const py::ssize_t na = static_cast<py::ssize_t>(o.angles.size()),
                              ns = static_cast<py::ssize_t>(o.speeds.size());
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
            d["sunk"] = sunk, d["hit"] = hit, d["closest_approach"] = closest,
            d["launch_angle"] = la, d["launch_speed"] = ls,
            d["csv"] = experiments::sweep_csv(cells);
            return d;
          },
          py::arg("angles"), py::arg("speeds"), py::arg("hole") = py::none(),
          py::arg("ball_only") = false, py::arg("threads") = 0,
          "The outcome of every (angle [rad], speed [m/s]) cell: dict of (len(angles), "
          "len(speeds)) arrays "
          "(sunk, hit, closest_approach [m], launch_angle [rad], launch_speed [m/s]) and the CSV "
          "`minigolf "
          "sweep` writes. threads: 0 = all cores. Releases the GIL.")
      .def(
          "collect",
          [](const system::System& s, const std::string& out, const std::string& situations,
             const std::string& strategy, int max_full_putts, std::uint64_t seed, int threads,
             bool resume) {
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
          py::arg("max_full_putts") = kTeacherDefaults.max_full_putts, py::arg("seed") = 1,
          py::arg("threads") = 0, py::arg("resume") = false,
          "The teacher collects a data set at the region's collection points (or a --situations "
          "spec) into "
          "the CSV `out`, as `minigolf collect` does (resumable); returns the examples in index "
          "order. "
          "Releases the GIL.")
      .def(
          "evaluate",
          [](const system::System& s, const learning::Model& model, int situations,
             std::uint64_t seed, int threads, bool oracle, const std::string& region_spec) {
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
          "The robot plays `situations` random test situations of the field's region (or a "
          "--situations spec) "
          "with the learned model; oracle: also run the teacher on each. Releases the GIL.");
}

}  // namespace mg::python
