// What the Python round environment (minigolf.env.RoundEnv) and the fast putt environment need of
// game/ and sim/: a course's holes, the round's rules after a stroke (game::end_of_stroke), the
// robot's planner (game::plan_stroke), its launch skill (game::LaunchSkill) and the planning
// path's ball-only putt (sim::fast_putt). Long calls release the GIL.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/check.hpp"
#include "core/error.hpp"
#include "core/rng.hpp"
#include "game/course.hpp"
#include "game/lane_region.hpp"
#include "game/launch.hpp"
#include "game/planner.hpp"
#include "game/round.hpp"
#include "game/skill.hpp"
#include "python/bindings.hpp"
#include "sim/fast_putt.hpp"
#include "sim/putt.hpp"
#include "system/observe.hpp"
#include "system/system.hpp"

namespace mg::python {
namespace {

std::vector<std::array<double, 2>> path_of(const Array& a, const char* what) {
  if (a.size() == 0) return {};
  if (a.ndim() != 2 || a.shape(1) < 2)
    throw InputError(fmt::format("{}: expected an (N, 2) array of x, y [m]", what));
  std::vector<std::array<double, 2>> p(static_cast<std::size_t>(a.shape(0)));
  auto r = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i) p[static_cast<std::size_t>(i)] = {r(i, 0), r(i, 1)};
  return p;
}

sim::PuttEnd parse_end(const std::string& end) {
  for (sim::PuttEnd e : {sim::PuttEnd::kSunk, sim::PuttEnd::kAtRest, sim::PuttEnd::kTimeOut,
                         sim::PuttEnd::kLeftLane})
    if (end == sim::to_string(e)) return e;
  throw InputError(
      fmt::format("end: expected 'sunk', 'at_rest', 'time_out' or 'left_lane', got '{}'", end));
}

sim::ClubLaunch club_of(const py::object& o) {
  sim::ClubLaunch c;
  if (o.is_none()) return c;
  const auto t = o.cast<std::array<double, 6>>();
  c.advance = t[0], c.lift = t[1], c.vertical_speed = t[2], c.spin = {t[3], t[4], t[5]};
  return c;
}

py::tuple club_tuple(const sim::ClubLaunch& c) {
  return py::make_tuple(c.advance, c.lift, c.vertical_speed, c.spin[0], c.spin[1], c.spin[2]);
}

}  // namespace

void bind_round(py::module_& m) {
  m.def(
      "load_course",
      [](const std::string& name) {
        game::Course c;
        {
          py::gil_scoped_release release;
          c = game::load_course(name);
        }
        py::list holes;
        for (const auto& h : c.holes) {
          py::dict d;
          d["field"] = h.field.source.empty() ? h.field_name : h.field.source;
          d["field_name"] = h.field.name;
          d["tee"] = h.field.tee;
          d["hole"] = h.field.hole.position;
          d["par"] = h.par;
          holes.append(d);
        }
        py::dict d;
        d["name"] = c.name;
        d["source"] = c.source;
        d["max_strokes"] = c.max_strokes;
        d["holes"] = holes;
        return d;
      },
      py::arg("name"),
      "A course (shipped name or path) as a dict: name, source, max_strokes, holes (each: field "
      "file, field_name, tee, hole [m], par)");

  py::class_<game::LaneRegion>(
      m, "LaneRegion",
      "The playable part of a lane for a hole: where a ball can lie and still roll to it "
      "(docs/round.md, 'A ball out of play')")
      .def(py::init<const field::Field&, std::array<double, 2>, double>(), py::arg("field"),
           py::arg("hole"), py::arg("cell") = 0.01, "Flood fill from `hole` [m] over cells [m]")
      .def("contains", &game::LaneRegion::contains, py::arg("p"),
           "True if a ball resting at p (x, y) [m] is in play")
      .def(
          "last_in_play",
          [](const game::LaneRegion& r, const Array& path, std::array<double, 2> fallback) {
            return r.last_in_play(path_of(path, "path"), fallback);
          },
          py::arg("path"), py::arg("fallback"),
          "The last point of `path` (N, 2) [m] in play; `fallback` if none");

  m.def(
      "end_of_stroke",
      [](const field::Field& field, const game::LaneRegion& region, std::array<double, 2> cup,
         std::array<double, 2> from, const std::string& end, std::array<double, 2> rest,
         const Array& path) {
        const auto e = game::end_of_stroke(field, region, cup, from, parse_end(end), rest,
                                           path_of(path, "path"));
        return py::make_tuple(e.left_lane, e.next);
      },
      py::arg("field"), py::arg("region"), py::arg("cup"), py::arg("start"), py::arg("end"),
      py::arg("rest"), py::arg("path"),
      "The round's rules after a stroke that did not sink (game::end_of_stroke, as `minigolf "
      "play`): (left_lane, next ball (x, y) [m]). left_lane: out of play, a penalty stroke "
      "follows. cup: where the hole really is (real_hole); start: where the stroke was played "
      "from; end: the putt's end; rest, path (N, 2): where it stopped and its path [m]");

  m.def(
      "club_speed_range",
      [](const system::System& s) {
        const auto& mc = s.module().config();
        return std::array<double, 2>{mc.speed_min, std::min(mc.speed_max, mc.arm_speed_cap)};
      },
      py::arg("system"),
      "The club speeds the arm really gives [m/s]: the envelope's, capped by the arm's top speed "
      "(as `minigolf play` calibrates and plays)");

  m.def(
      "line_blocked",
      [](const field::Field& f, std::array<double, 2> a, std::array<double, 2> b,
         double clearance) { return field::line_blocked(f, a, b, clearance); },
      py::arg("field"), py::arg("a"), py::arg("b"), py::arg("clearance") = 0.0,
      "True if the segment a -> b [m] passes within `clearance` [m] of an obstacle (the "
      "planner's strokes-to-go test uses the ball's radius)");

  m.def(
      "real_hole",
      [](const system::System& s, std::array<double, 2> hole) {
        return system::real_hole(s, hole);
      },
      py::arg("system"), py::arg("hole"),
      "Where the ball really drops for a hole seen at `hole` [m] (the plant's hole offset)");

  py::class_<game::ImaginedCache>(m, "ImaginedCache",
                                  "Memo of the planner's imagined putts (thread-safe)")
      .def(py::init<>());

  m.def(
      "plan_stroke",
      [](const system::System& s, std::array<double, 2> ball, std::array<double, 2> hole,
         double angle_error, double speed_error, double speed_min, double speed_max, int threads,
         game::ImaginedCache* cache, const game::LaunchSkill* skill) {
        game::PlannerOptions po;
        po.speed_min = speed_min;
        po.speed_max = speed_max;
        po.threads = threads;
        if (skill != nullptr) po.club_launch = [skill](double u) { return skill->club_launch(u); };
        po.validate();
        game::StrokePlan p;
        {
          py::gil_scoped_release release;
          p = game::plan_stroke(s, ball, hole, {angle_error, speed_error}, po, cache);
        }
        py::dict d;
        d["angle"] = p.angle;
        d["speed"] = p.speed;
        d["sink_probability"] = p.sink_probability;
        d["expected_strokes"] = p.expected_strokes;
        d["bank"] = p.bank;
        d["imagined_putts"] = p.imagined_putts;
        return d;
      },
      py::arg("system"), py::arg("ball"), py::arg("hole"), py::arg("angle_error") = 0.0005,
      py::arg("speed_error") = 0.007, py::arg("speed_min") = game::PlannerOptions{}.speed_min,
      py::arg("speed_max") = game::PlannerOptions{}.speed_max, py::arg("threads") = 0,
      py::arg("cache") = py::none(), py::arg("skill") = py::none(),
      "The round's planner (game::plan_stroke): the best ball launch from `ball` to `hole` [m] "
      "in `system`'s ball world under a launch error (angle std [rad], relative speed std [-]; "
      "default: the oracle's, the arm's measured precision). Launch speeds searched in "
      "[speed_min, speed_max] [m/s]; skill: imagined putts leave the club as that skill says. "
      "Returns a dict: angle [rad, world], speed [m/s], sink_probability, expected_strokes, "
      "bank, imagined_putts. Releases the GIL.");

  py::class_<game::LaunchSkill>(
      m, "LaunchSkill",
      "The robot's launch skill (game/skill.hpp): club speed -> launch speed, angle offset and "
      "how the ball leaves the club, learned from its own putts")
      .def(py::init<>())
      .def("size", &game::LaunchSkill::size)
      .def("launch_speed", &game::LaunchSkill::launch_speed, py::arg("club_speed"),
           "[m/s] predicted launch speed for a club speed [m/s]")
      .def("angle_offset", &game::LaunchSkill::angle_offset, py::arg("club_speed"),
           "[rad] predicted launch angle minus hitting angle")
      .def("club_for", &game::LaunchSkill::club_for, py::arg("launch_speed"), py::arg("lo"),
           py::arg("hi"), "The club speed in [lo, hi] [m/s] nearest a launch speed [m/s]")
      .def(
          "club_launch",
          [](const game::LaunchSkill& s, double u) { return club_tuple(s.club_launch(u)); },
          py::arg("launch_speed"),
          "How the ball leaves the club at a launch speed: (advance [m], lift [m], vertical "
          "speed [m/s], spin x, y, z [rad/s]) (fast_putt's `club`)")
      .def_property_readonly("angle_std", &game::LaunchSkill::angle_std, "[rad]")
      .def_property_readonly("speed_std", &game::LaunchSkill::speed_std, "[-] relative");

  m.def(
      "calibrate_launch_skill",
      [](const system::System& s, int putts, std::uint64_t seed, double vision_noise) {
        if (putts < 1 || putts > 50)
          throw InputError(fmt::format("putts: expected 1..50, got {}", putts));
        require_in_range("vision_noise", vision_noise, 0.0, 0.05);
        game::LaunchSkill skill;
        {
          py::gil_scoped_release release;
          // The round's calibration (game/round.cpp): putts from the tee at a ladder of club
          // speeds over the envelope, each with its own view of the ball.
          system::SystemData data(s);
          const auto& mc = s.module().config();
          const double lo = mc.speed_min, hi = std::min(mc.speed_max, mc.arm_speed_cap);
          Rng rng(derive_seed(seed, 1000));
          std::normal_distribution<double> normal(0.0, 1.0);
          const auto hole = s.field().hole.position;
          for (int k = 0; k < putts; ++k) {
            const double u = putts > 1 ? static_cast<double>(k) / (putts - 1) : 0.5;
            control::FullPuttOptions o;
            o.seed = derive_seed(seed, 2000 + static_cast<std::uint64_t>(k));
            control::PlantEffectValues seen;
            if (vision_noise > 0.0)
              seen.perceived_ball_offset = {vision_noise * normal(rng), vision_noise * normal(rng)};
            // Cameras of its own read the launch from the path they saw.
            if (system::paths_seen_by_perception(s)) o.record_interval = 0.01;
            auto r =
                system::arm_putt(s, data, hole, 0.0, lo + (hi - lo) * (0.02 + 0.96 * u), o, seen);
            if (r.hit_refused || !r.hit) continue;
            system::perceive_putt(s, data, r);
            const game::ArmLaunch a = game::arm_launch(s.field(), r.ball_start, r.launch_state);
            if (!std::isfinite(a.speed)) continue;  // the cameras did not see the launch
            skill.add(lo + (hi - lo) * (0.02 + 0.96 * u), 0.0, a.angle, a.speed, a.club);
          }
        }
        if (skill.size() == 0)
          throw NumericalError(fmt::format("{}: no calibration putt hit the ball", s.field().name));
        return skill;
      },
      py::arg("system"), py::arg("putts") = 10, py::arg("seed") = 0,
      py::arg("vision_noise") = 0.002,
      "The robot's launch skill from `putts` arm putts from the tee at a ladder of club speeds "
      "(as `minigolf play` calibrates it). Releases the GIL.");

  m.def(
      "fast_putt",
      [](const system::System& s, double angle, double speed,
         std::optional<std::array<double, 2>> hole, std::optional<std::array<double, 2>> ball,
         const py::object& club, double max_duration, double record_interval, PySystemData* pdata) {
        check_owner(s, pdata);
        Lease lease(pdata);
        std::optional<system::SystemData> local;
        sim::PuttOutcome out;
        const sim::ClubLaunch launch = club_of(club);
        {
          py::gil_scoped_release release;
          std::array<double, 2> h = hole.value_or(s.field().hole.position);
          field::check_hole_position(s.field(), h);
          if (ball) system::check_ball_position(s.field(), *ball, "ball");
          if (!s.plant().empty()) {  // as system::ball_putt: where the ball really drops
            h = system::real_hole(s, h);
            field::check_hole_position(s.ball_world().field(), h);
          }
          sim::PuttRequest r;
          r.angle = angle;
          r.speed = speed;
          r.start = ball;
          r.club = launch;
          r.max_duration = max_duration;
          r.record_interval = record_interval;
          system::SystemData& data = pdata ? pdata->data : local.emplace(s);
          out = sim::fast_putt(s.ball_world(), data.ball.get(), h, r);
        }
        py::array_t<double> traj({static_cast<py::ssize_t>(out.trajectory.size()), py::ssize_t{3}});
        auto t = traj.mutable_unchecked<2>();
        for (std::size_t i = 0; i < out.trajectory.size(); ++i) {
          const auto& p = out.trajectory[i];
          t(i, 0) = p.t, t(i, 1) = p.x, t(i, 2) = p.y;
        }
        return py::make_tuple(out.sunk, sim::to_string(out.end), out.rest_position,
                              out.closest_approach, traj);
      },
      py::arg("system"), py::arg("angle"), py::arg("speed"), py::arg("hole") = py::none(),
      py::arg("ball") = py::none(), py::arg("club") = py::none(), py::arg("max_duration") = 30.0,
      py::arg("record_interval") = 0.0, py::arg("data") = py::none(),
      "A ball-only putt on the planning path (sim::fast_putt: MuJoCo's outcome at ~10x its "
      "speed; docs/physics.md): launch `angle` [rad, world], `speed` [m/s] from `ball` (default: "
      "the tee) to `hole` (default: the field's) [m], as System.putt(ball_only=True). club: how "
      "the ball leaves the club (LaunchSkill.club_launch; default: a plain launch). Returns "
      "(sunk, end, rest (x, y) [m], closest_approach [m], path (N, 3): t [s], x, y [m], every "
      "record_interval [s]). data: a SystemData of this System. Releases the GIL.");
}

}  // namespace mg::python
