// minigolf.System: putts (arm and ball only: putt_bindings.cpp), the teacher, sweeps, data
// collection and evaluation, as the CLI's commands run them. Long calls release the GIL.
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

#include "belief/belief.hpp"
#include "experiments/collect.hpp"
#include "experiments/evaluate.hpp"
#include "experiments/sweep.hpp"
#include "field/situations.hpp"
#include "learning/learner.hpp"
#include "python/bindings.hpp"
#include "sim/putt.hpp"
#include "system/distributed.hpp"
#include "system/parallel.hpp"
#include "teacher/teacher.hpp"
#include "vision/camera_perception.hpp"

namespace mg::python {
namespace {

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

// The library's defaults, in one place.
const teacher::TeacherOptions kTeacherDefaults{};
const system::PuttSpec kPuttDefaults{};
const experiments::EvaluateOptions kEvaluateDefaults{};
const experiments::CollectOptions kCollectDefaults{};

}  // namespace

void bind_system(py::module_& m) {
  m.def(
      "read_plant_file",
      [](const std::string& path) {
        std::string text;
        {
          py::gil_scoped_release release;
          text = plant::read_plant_file(path);
        }
        return py::bytes(text);
      },
      py::arg("path"),
      "The bytes of a plant file (checked as System(plant=) reads it), for System(plant_text=): "
      "what a pickled PuttEnv keeps, so a clone plays the same world");
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

  py::class_<teacher::Example>(m, "Example",
                               "A teacher's example: a sinking putt with a verified neighbourhood.")
      .def_readonly("hole", &teacher::Example::hole, "[m]")
      .def_readonly("ball", &teacher::Example::ball, "Where the ball lay [m] (the tee by default)")
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
      .def_property_readonly(
          "balls",
          [](const experiments::Evaluation& e) {
            std::vector<std::array<double, 2>> b;
            for (const auto& r : e.rows) b.push_back(r.ball);
            return points(b);
          },
          "(N, 2) [m] where each ball lay (the tee unless a ball region)")
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
                       const std::string& hitting_model, const std::string& plant,
                       std::optional<py::bytes> plant_text, const std::string& belief,
                       const std::string& perception, std::optional<std::string> rig,
                       std::optional<std::string> calibration) {
             if (plant_text && plant.empty())
               throw InputError("plant_text: needs plant (the name its errors and hash carry)");
             if (perception != "truth" && perception != "camera") {
               std::string shown = perception.substr(0, 80);
               for (char& ch : shown)
                 if (static_cast<unsigned char>(ch) < 0x20) ch = '?';  // one line
               throw InputError(
                   fmt::format("perception: expected 'truth' or 'camera', got '{}'", shown));
             }
             if (perception != "camera" && (rig || calibration))
               throw InputError(
                   fmt::format("{}: only with perception='camera'", rig ? "rig" : "calibration"));
             // Held as a std::string before the GIL is released.
             const std::optional<std::string> text =
                 plant_text ? std::optional<std::string>(std::string(*plant_text)) : std::nullopt;
             py::gil_scoped_release release;
             plant::Plant p;
             if (text)
               p = plant::parse_plant(*text, plant);
             else if (!plant.empty())
               p = plant::load_plant(plant);
             plant::Plant b =
                 belief.empty() ? plant::Plant{} : belief::load_belief(belief).estimate;
             const control::ModuleConfig c = system::load_config(config, field, hitting_model);
             field::Field lane = field::load_field(c.field);
             system::PerceptionFactory eyes;
             if (perception == "camera") {
               vision::Cameras cameras = vision::load_cameras(rig.value_or(vision::kDefaultRig),
                                                              calibration.value_or(""));
               vision::check_rig_sees_field(cameras.rig, plant::true_field(lane, p));
               eyes = vision::camera_perception(std::move(cameras));
             }
             return std::make_unique<system::System>(c, std::move(lane), std::move(p), std::move(b),
                                                     std::move(eyes));
           }),
           py::arg("field") = "flat", py::arg("config") = "", py::arg("hitting_model") = "",
           py::arg("plant") = "", py::arg("plant_text") = py::none(), py::arg("belief") = "",
           py::arg("perception") = "truth", py::arg("rig") = py::none(),
           py::arg("calibration") = py::none(),
           "field: shipped name or path; config: module YAML (empty: defaults); hitting_model: DS "
           "model file (empty: the configured default); plant: plant file, the world as it "
           "really is (docs/reality.md; empty: the robot's model); plant_text: the plant file's "
           "bytes, read earlier (read_plant_file), parsed instead of reading `plant` again; "
           "belief: belief file, what the robot believes beyond its field file (docs/belief.md; "
           "`field` is then the field file with it applied); perception: what the module sees, "
           "'truth' (the simulator's) or 'camera' (the rig's cameras render the simulation: a "
           "display or xvfb-run; each SystemData owns its cameras); rig: rig file or shipped "
           "name (default 'stereo'), calibration: calibration file (default: the rig's exact "
           "cameras), both only with perception='camera'")
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
             std::optional<double> aim, bool world) {
            system::PuttSpec spec;
            spec.angle = angle;
            spec.speed = speed;
            spec.hole = hole;
            spec.ball = ball;
            spec.aim = aim;
            spec.world = world;
            spec.ball_only = ball_only;
            spec.max_duration = max_duration;
            spec.record_interval = record_interval;
            return putt(s, data, spec);
          },
          py::arg("angle"), py::arg("speed"), py::arg("hole") = py::none(),
          py::arg("ball_only") = false, py::arg("max_duration") = kPuttDefaults.max_duration,
          py::arg("record_interval") = system::kTrajectoryInterval, py::arg("data") = py::none(),
          py::arg("ball") = py::none(), py::arg("aim") = py::none(), py::arg("world") = false,
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
          "and `angle` is in its frame. world: `angle` is a world direction and the base "
          "stands by the stance rule of learned hits (facing +x when the fixed arm can make the "
          "hit, else turned to it; not with aim); club and launch angles are then world angles. "
          "Releases the GIL.")
      .def(
          "teach",
          [](const system::System& s, std::array<double, 2> hole, const std::string& strategy,
             int max_full_putts, int max_ball_putts, double margin_angle, double margin_speed,
             PySystemData* data, std::optional<std::array<double, 2>> ball) {
            const auto t = teacher_options(s, strategy, max_full_putts, max_ball_putts,
                                           margin_angle, margin_speed);
            check_owner(s, data);
            Lease lease(data);
            std::optional<system::SystemData> local;
            const field::Situation situation{ball.value_or(s.field().tee), hole};
            py::gil_scoped_release release;
            return teacher::teach(s, data ? data->data : local.emplace(s), situation, t);
          },
          py::arg("hole"), py::arg("strategy") = "",
          py::arg("max_full_putts") = kTeacherDefaults.max_full_putts,
          py::arg("max_ball_putts") = kTeacherDefaults.max_ball_putts,
          py::arg("margin_angle") = kTeacherDefaults.margin_angle,
          py::arg("margin_speed") = kTeacherDefaults.margin_speed, py::arg("data") = py::none(),
          py::arg("ball") = py::none(),
          "The automated teacher finds a sinking putt for the hole (x, y) [m] from the ball at "
          "`ball` (default: the tee; the base stands beside it facing as at the tee, so the "
          "angle is a world angle). strategy: 'min-speed' | 'min-angle' (default: the field's). "
          "Margins [rad], [m/s]. Releases the GIL.")
      .def(
          "sweep",
          [](const system::System& s, std::vector<double> angles, std::vector<double> speeds,
             std::optional<std::array<double, 2>> hole, bool ball_only, int threads) {
            system::check_threads(threads);
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
             bool resume, const std::string& balls) {
            system::check_threads(threads);
            const field::Situations region = field::region_from_spec(s.field(), situations, balls);
            experiments::CollectOptions o;
            o.teacher = teacher::options_for(region, strategy);
            o.teacher.max_full_putts = max_full_putts;
            o.teacher.validate();
            o.seed = seed;
            o.threads = threads;
            o.resume = resume;
            const auto pairs = region.collection_situations(s.field());
            py::gil_scoped_release release;
            return experiments::collect(s, pairs, o, out).examples;
          },
          py::arg("out"), py::arg("situations") = "", py::arg("strategy") = "",
          py::arg("max_full_putts") = kTeacherDefaults.max_full_putts,
          py::arg("seed") = kCollectDefaults.seed, py::arg("threads") = 0,
          py::arg("resume") = false, py::arg("balls") = "",
          "The teacher collects a data set at the region's collection situations (or a "
          "--situations spec; `balls`: where the ball lies, as --balls) into "
          "the CSV `out`, as `minigolf collect` does (resumable); returns the examples in index "
          "order. "
          "Releases the GIL.")
      .def(
          "evaluate",
          [](const system::System& s, const learning::Model& model, int situations,
             std::uint64_t seed, int threads, bool oracle, const std::string& region_spec,
             const std::string& balls_spec) {
            system::check_threads(threads);
            experiments::check_playable_model(model, "model", &s);
            experiments::EvaluateOptions o;
            o.situations = situations;
            o.seed = seed;
            o.threads = threads;
            o.oracle = oracle;
            const auto region = field::region_from_spec(s.field(), region_spec, balls_spec);
            o.teacher = teacher::options_for(region);
            py::gil_scoped_release release;
            return experiments::evaluate_model(s, model, region, o);
          },
          py::arg("model"), py::arg("situations") = kEvaluateDefaults.situations,
          py::arg("seed") = kEvaluateDefaults.seed, py::arg("threads") = 0,
          py::arg("oracle") = true, py::arg("region") = "", py::arg("balls") = "",
          "The robot plays `situations` random test situations of the field's region (or a "
          "--situations spec; `balls`: where the ball lies, as --balls) "
          "with the learned model; oracle: also run the teacher on each. Releases the GIL.");
}

}  // namespace mg::python
