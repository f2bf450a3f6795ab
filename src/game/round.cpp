#include "game/round.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <random>

#include <fmt/format.h>

#include "core/check.hpp"
#include "core/error.hpp"
#include "core/rng.hpp"
#include "game/green_belief.hpp"
#include "game/lane_region.hpp"
#include "game/launch.hpp"
#include "game/skill.hpp"
#include "sim/putt.hpp"
#include "system/observe.hpp"

namespace mg::game {
namespace {

constexpr double kPathInterval = 0.01;  // [s] between recorded path points
constexpr double kPi = 3.14159265358979323846;

/// Per field: the belief (the robot's model: the field file, no plant), the truth, the skill.
struct HoleWorlds {
  std::unique_ptr<system::System> belief, truth;
  std::unique_ptr<system::SystemData> data;  // of truth
};

bool on_lane(const field::Field& f, std::array<double, 2> p) {
  const auto& b = f.bounds;
  return p[0] >= b[0] && p[0] <= b[1] && p[1] >= b[2] && p[1] <= b[3];
}

}  // namespace

std::string to_string(Player player) {
  switch (player) {
    case Player::kRobot:
      return "robot";
    case Player::kOracle:
      return "oracle";
    case Player::kExactOracle:
      return "exact-oracle";
    case Player::kGreedy:
      return "greedy";
  }
  return "?";
}

Player parse_player(const std::string& text, const std::string& what) {
  for (Player p : {Player::kRobot, Player::kOracle, Player::kExactOracle, Player::kGreedy})
    if (text == to_string(p)) return p;
  throw InputError(fmt::format(
      "{}: unknown player '{}' (expected robot, oracle, exact-oracle or greedy)", what, text));
}

void RoundOptions::validate() const {
  if (calibration_putts < 1 || calibration_putts > 50)
    throw InputError(
        fmt::format("budget: expected 1..50 learning putts per field, got {}", calibration_putts));
  require_in_range("vision_noise", vision_noise, 0.0, 0.05);
  require_in_range("min_angle_error", min_angle_error, 0.0, 0.5);
  require_in_range("min_speed_error", min_speed_error, 0.0, 0.5);
  require_in_range("oracle_error.angle", oracle_error.angle, 0.0, 0.5);
  require_in_range("oracle_error.speed", oracle_error.speed, 0.0, 0.5);
  planner.validate();
}

std::array<double, 2> replace_ball(const field::Field& field, std::array<double, 2> p) {
  const auto& b = field.bounds;
  const double m = field.ball.radius + 0.01;
  if (!std::isfinite(p[0]) || !std::isfinite(p[1])) p = field.tee;
  p = {std::clamp(p[0], b[0] + m, b[1] - m), std::clamp(p[1], b[2] + m, b[3] - m)};
  // Off an obstacle: step along the distance's numerical gradient until clear.
  for (int it = 0; it < 200; ++it) {
    double worst = 1e9;
    const field::Obstacle* o = nullptr;
    for (const auto& ob : field.obstacles) {
      const double d = ob.distance(p);
      if (d < worst) worst = d, o = &ob;
    }
    if (o == nullptr || worst >= m) break;
    const double h = 1e-4;
    double gx = o->distance({p[0] + h, p[1]}) - o->distance({p[0] - h, p[1]});
    double gy = o->distance({p[0], p[1] + h}) - o->distance({p[0], p[1] - h});
    const double g = std::hypot(gx, gy);
    if (!(g > 0))
      gx = 1.0, gy = 0.0;
    else
      gx /= g, gy /= g;
    p = {std::clamp(p[0] + gx * (m - worst + 1e-3), b[0] + m, b[1] - m),
         std::clamp(p[1] + gy * (m - worst + 1e-3), b[2] + m, b[3] - m)};
  }
  return p;
}

StrokeEnd end_of_stroke(const field::Field& field, const LaneRegion& region,
                        std::array<double, 2> cup, std::array<double, 2> from, sim::PuttEnd end,
                        std::array<double, 2> rest,
                        const std::vector<std::array<double, 2>>& path) {
  StrokeEnd e;
  e.left_lane = end == sim::PuttEnd::kLeftLane || !on_lane(field, rest) || !region.contains(rest);
  std::array<double, 2> ball = rest;
  if (e.left_lane) {
    ball = replace_ball(field, region.last_in_play(path, from));
    if (!region.contains(ball)) ball = from;  // put back where it was played from
  } else {
    try {
      system::check_ball_position(field, ball, "ball");
    } catch (const InputError&) {
      ball = replace_ball(field, ball);  // resting against a border or wall: 1 cm off it
    }
  }
  // A ball resting over the cup's rim but not in: nudge it off the rim onto the lane. The cup is
  // where the world has it (the plant's hole offset), not where the robot sees it.
  const double gap = std::hypot(ball[0] - cup[0], ball[1] - cup[1]);
  const double need = 0.5 * field.hole.diameter + field.ball.radius + 1e-3;
  if (gap < need) {
    const double ux = gap > 1e-9 ? (ball[0] - cup[0]) / gap : 1.0;
    const double uy = gap > 1e-9 ? (ball[1] - cup[1]) / gap : 0.0;
    ball = replace_ball(field, {cup[0] + ux * need, cup[1] + uy * need});
  }
  e.next = ball;
  return e;
}

RoundResult play_round(const Course& course, const control::ModuleConfig& config,
                       const plant::Plant& plant, const RoundOptions& options, ImaginedCache* cache,
                       const std::function<void(int, const StrokeRecord&)>& on_stroke) {
  options.validate();
  // Where the plant puts every hole, before the first stroke (not at hole 7 after six were played).
  for (std::size_t h = 0; h < course.holes.size(); ++h)
    system::check_real_holes(course.holes[h].field, plant, {course.holes[h].field.hole.position},
                             fmt::format("{}: hole {}", course.name, h + 1));
  RoundResult result;
  result.course = course.name;
  result.player = options.player;
  std::optional<GreenBelief> green;  // the robot's, revised from what it watches
  const bool revising = options.player == Player::kRobot && options.revise;
  for (std::size_t h = 0; h < course.holes.size(); ++h) {
    const CourseHole& ch = course.holes[h];
    if (revising && !green) green.emplace(options.belief, ch.field, options.vision_noise);
    // The robot's model of this lane: its field file as it now believes it to be.
    const auto believed = [&] {
      return std::make_unique<system::System>(
          config, plant::true_field(ch.field, green ? green->plant() : options.belief));
    };
    Rng watch_rng(derive_seed(options.seed, 7000 + h));  // its vision of the paths it watches
    const auto watch = [&](const std::vector<sim::BallSample>& path) {
      return green && green->watch(ch.field, ch.field.hole.position, path, watch_rng);
    };
    HoleWorlds w;
    w.belief = believed();
    const bool arm_player =
        options.player != Player::kOracle && options.player != Player::kExactOracle;
    w.truth = std::make_unique<system::System>(
        config, ch.field, plant, plant::Plant{},
        arm_player ? options.perception : system::PerceptionFactory{});
    w.data = std::make_unique<system::SystemData>(*w.truth);
    const field::Field& field = ch.field;  // its geometry: the same in every belief
    const auto hole = field.hole.position;
    const auto cup = system::real_hole(*w.truth, hole);  // where the ball really drops
    const LaneRegion region(field, hole);
    const control::ControllerConfig mc = w.belief->module().config();
    const double club_min = mc.speed_min, club_max = std::min(mc.speed_max, mc.arm_speed_cap);
    Rng rng(derive_seed(options.seed, 1000 + h));
    std::normal_distribution<double> normal(0.0, 1.0);

    // The robot's skill on this field: its own putts from the tee at a ladder of club speeds.
    LaunchSkill skill;
    const bool oracle = options.player == Player::kOracle || options.player == Player::kExactOracle;
    const bool uses_arm = !oracle;
    // With cameras of its own the robot learns from what they saw of each roll (its launch
    // included), which they read from a recorded path.
    const bool cameras = uses_arm && system::paths_seen_by_perception(*w.truth);
    if (uses_arm) {
      for (int k = 0; k < options.calibration_putts; ++k) {
        const double u = options.calibration_putts > 1
                             ? static_cast<double>(k) / (options.calibration_putts - 1)
                             : 0.5;
        const double club = club_min + (club_max - club_min) * (0.02 + 0.96 * u);
        control::FullPuttOptions o;
        o.seed = derive_seed(options.seed, 2000 + h * 64 + k);
        // It sees the ball on the tee as it will see it everywhere: its skill knows that error.
        control::PlantEffectValues seen;
        if (options.vision_noise > 0.0)
          seen.perceived_ball_offset = {options.vision_noise * normal(rng),
                                        options.vision_noise * normal(rng)};
        if (revising || cameras) o.record_interval = kPathInterval;
        auto r = system::arm_putt(*w.truth, *w.data, hole, 0.0, club, o, seen);
        if (r.hit_refused || !r.hit) continue;
        system::perceive_putt(*w.truth, *w.data, r);
        watch(r.outcome.trajectory);
        const ArmLaunch a = arm_launch(field, r.ball_start, r.launch_state);
        if (!std::isfinite(a.speed)) continue;           // the cameras did not see the launch
        skill.add(club, 0.0, a.angle, a.speed, a.club);  // the identity stance: world = robot
        ++result.learning_putts;
      }
      if (skill.size() == 0)
        throw NumericalError(fmt::format("{}: no calibration putt hit the ball", field.name));
      if (green && green->paths() > 0) w.belief = believed();
    }
    const auto model_it = options.models.find(field.name);
    const HitModel* model =
        options.player == Player::kRobot && model_it != options.models.end() && model_it->second
            ? &model_it->second
            : nullptr;
    PlannerOptions po = options.planner;
    if (uses_arm) {  // only the launches the arm can give
      po.speed_min = std::max(po.speed_min, skill.launch_speed(club_min * 1.02));
      po.speed_max = std::min(po.speed_max, skill.launch_speed(club_max * 0.98));
      if (!(po.speed_max > po.speed_min)) po.speed_max = po.speed_min * 1.5;
      po.club_launch = [&skill](double u) { return skill.club_launch(u); };
    }

    HoleResult hr;
    hr.field = field.name;
    hr.par = ch.par;
    std::array<double, 2> ball = field.tee;
    while (hr.strokes < course.max_strokes && !hr.sunk) {
      StrokeRecord s;
      s.ball = ball;
      // What the player sees of the ball (the robot's vision error; the oracle sees the truth).
      std::array<double, 2> seen = ball;
      if (uses_arm && options.vision_noise > 0.0)
        seen = {ball[0] + options.vision_noise * normal(rng),
                ball[1] + options.vision_noise * normal(rng)};
      seen = replace_ball(field, seen);
      StrokePlan plan;
      std::optional<ModelHit> model_hit;  // the learned model's hit, when it plays this stroke
      if (options.player == Player::kGreedy) {
        const double direct = std::atan2(hole[1] - seen[1], hole[0] - seen[0]);
        std::vector<std::array<double, 2>> launches;
        const double q = std::pow(po.speed_max / po.speed_min, 1.0 / (po.speeds - 1));
        for (int j = 0; j < po.speeds; ++j)
          launches.push_back({direct, po.speed_min * std::pow(q, j)});
        int n = 0;
        const auto out = imagine(*w.belief, region, seen, hole, launches, po, cache, &n);
        result.imagined_putts += n;
        double best = 1e9;
        for (std::size_t j = 0; j < out.size(); ++j) {
          const double e =
              out[j].sunk ? -1.0 : std::hypot(out[j].rest[0] - hole[0], out[j].rest[1] - hole[1]);
          if (e < best) best = e, plan.angle = direct, plan.speed = launches[j][1];
        }
      } else {
        LaunchError err;
        if (options.player == Player::kOracle)
          err = options.oracle_error;
        else if (!oracle)
          err = {std::max(options.min_angle_error, skill.angle_std()),
                 std::max(options.min_speed_error, skill.speed_std())};
        std::optional<ModelHit> by_model;
        LaunchJudgement judged;
        if (model != nullptr) {
          by_model = (*model)(seen, hole);
          if (by_model && !(by_model->club_speed >= club_min && by_model->club_speed <= club_max))
            by_model.reset();  // outside the arm's envelope: not a hit the module takes
          if (by_model) {
            const double c = by_model->club_speed;
            judged = judge_launch(*w.belief, seen, hole, by_model->angle + skill.angle_offset(c),
                                  skill.launch_speed(c), err, po, cache);
            result.imagined_putts += judged.imagined_putts;
          }
        }
        if (by_model && judged.sink_probability >= po.accept_probability) {
          model_hit = by_model;
        } else {
          plan = plan_stroke(oracle ? *w.truth : *w.belief, seen, hole, err, po, cache);
          result.imagined_putts += plan.imagined_putts;
          if (by_model && judged.expected_strokes <= plan.expected_strokes) model_hit = by_model;
        }
        if (model_hit) {
          const double c = model_hit->club_speed;
          plan.angle = std::remainder(model_hit->angle + skill.angle_offset(c), 2.0 * kPi);
          plan.speed = skill.launch_speed(c);
          plan.sink_probability = judged.sink_probability;
          plan.bank = false;
        }
      }
      s.angle = plan.angle;
      s.speed = plan.speed;
      s.sink_probability = plan.sink_probability;
      s.bank = plan.bank;
      s.model = model_hit.has_value();

      sim::PuttOutcome out;
      if (!uses_arm) {
        // The oracle's launch error: drawn after planning, so its plans do not depend on it.
        const auto& e = options.player == Player::kOracle ? options.oracle_error : LaunchError{};
        const double angle = plan.angle + e.angle * normal(rng);
        const double speed = plan.speed * std::exp(e.speed * normal(rng));
        out = system::ball_putt(*w.truth, *w.data, hole, angle, speed, kPathInterval, ball);
        s.launch = {angle, speed};
      } else {
        control::FullPuttOptions o;
        o.seed = derive_seed(options.seed, 3000 + h * 64 + static_cast<std::uint64_t>(hr.strokes));
        o.record_interval = kPathInterval;
        // The model's hits stand as its data were collected (system::hit_pose: facing +x
        // unless the fixed arm cannot reach them); the planner's face the launch.
        const system::HitPose pose =
            model_hit ? system::hit_pose(*w.truth, ball, model_hit->angle, model_hit->club_speed)
                      : system::HitPose{system::stance_for(*w.truth, ball, plan.angle), 0.0, true};
        o.stance = pose.stance;
        // The robot walks to the ball it saw: the module sees it off by the vision error.
        control::PlantEffectValues view;
        view.perceived_ball_offset = {seen[0] - ball[0], seen[1] - ball[1]};
        const double club =
            model_hit ? model_hit->club_speed : skill.club_for(plan.speed, club_min, club_max);
        const double hitting = model_hit ? pose.angle : -skill.angle_offset(club);
        const auto r = system::arm_putt(*w.truth, *w.data, hole, hitting, club, o, view);
        if (r.hit_refused || !r.hit) {
          // Braked, the ball untouched: the stroke counts (a whiff), the ball stays.
          out.rest_position = ball;
          out.end = sim::PuttEnd::kAtRest;
        } else {
          out = r.outcome;  // the referee's: where the ball went
          const ArmLaunch a = arm_launch(field, r.ball_start, r.launch_state);
          s.launch = {a.angle, a.speed};
          // What the robot saw of it (the same result without cameras of its own).
          const control::FullPuttResult* seen = &r;
          std::optional<control::FullPuttResult> by_cameras;
          if (cameras) {
            by_cameras = r;
            system::perceive_putt(*w.truth, *w.data, *by_cameras);
            seen = &*by_cameras;
          }
          const ArmLaunch sa =
              cameras ? arm_launch(field, seen->ball_start, seen->launch_state) : a;
          // Every stroke played refines the skill (angles in the robot's frame).
          if (std::isfinite(sa.speed))
            skill.add(club, hitting, std::remainder(sa.angle - o.stance.yaw, 2.0 * kPi), sa.speed,
                      sa.club);
          if (watch(seen->outcome.trajectory)) w.belief = believed();
        }
      }
      ++hr.strokes;
      s.sunk = out.sunk;
      s.rest = out.rest_position;
      for (const auto& p : out.trajectory) s.path.push_back({p.x, p.y});
      hr.sunk = out.sunk;
      if (!hr.sunk) {
        const StrokeEnd e =
            end_of_stroke(field, region, cup, s.ball, out.end, out.rest_position, s.path);
        s.left_lane = e.left_lane;
        ball = e.next;
        if (s.left_lane) ++hr.strokes;  // the penalty stroke
      }
      hr.putts.push_back(s);
      if (on_stroke) on_stroke(static_cast<int>(h), hr.putts.back());
    }
    if (green) {
      const auto& b = green->plant().field;
      result.believed_green = {b.rolling_resistance_scale.value_or(1.0), b.extra_slope[0],
                               b.extra_slope[1]};
      result.believed_green_std = green->std();
      result.belief_paths = green->paths();
    }
    hr.strokes = std::min(hr.strokes, course.max_strokes);
    result.total_strokes += hr.strokes;
    result.total_par += hr.par;
    result.holes.push_back(std::move(hr));
  }
  return result;
}

}  // namespace mg::game
