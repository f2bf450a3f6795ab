#include "game/round.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include <fmt/format.h>

#include "core/check.hpp"
#include "core/error.hpp"
#include "core/rng.hpp"
#include "sim/putt.hpp"

namespace mg::game {
namespace {

constexpr double kPathInterval = 0.01;  // [s] between recorded path points

/// The robot's launch skill: launch speed = gain * club speed + offset, launch angle = hitting
/// angle + angle_offset (the stance's frame), fitted by least squares to every putt it has seen.
struct LaunchSkill {
  std::vector<double> club, launch, angle_residual;
  double gain = 1.6, offset = 0.0, angle_offset = 0.0;
  double angle_std = 0.0, speed_std = 0.0;  ///< [rad], [-] of the fit's residuals

  void add(double club_speed, double hitting_angle, const control::AngleSpeed& got) {
    club.push_back(club_speed);
    launch.push_back(got.speed);
    angle_residual.push_back(got.angle - hitting_angle);
    fit();
  }
  void fit() {
    const auto n = static_cast<double>(club.size());
    double sx = 0, sy = 0, sxx = 0, sxy = 0, sa = 0;
    for (std::size_t i = 0; i < club.size(); ++i) {
      sx += club[i], sy += launch[i], sxx += club[i] * club[i], sxy += club[i] * launch[i];
      sa += angle_residual[i];
    }
    const double det = n * sxx - sx * sx;
    if (club.size() >= 2 && det > 1e-9 * n * sxx) {
      gain = (n * sxy - sx * sy) / det;
      offset = (sy - gain * sx) / n;
    } else if (sxx > 0) {
      gain = sxy / sxx, offset = 0.0;
    }
    angle_offset = sa / n;
    double ea = 0, es = 0;
    for (std::size_t i = 0; i < club.size(); ++i) {
      ea += std::pow(angle_residual[i] - angle_offset, 2);
      es += std::pow((launch[i] - gain * club[i] - offset) / launch[i], 2);
    }
    angle_std = club.size() > 2 ? std::sqrt(ea / (n - 2)) : 0.0;
    speed_std = club.size() > 2 ? std::sqrt(es / (n - 2)) : 0.0;
  }
  double club_for(double launch_speed) const { return (launch_speed - offset) / gain; }
  double launch_for(double club_speed) const { return gain * club_speed + offset; }
};

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
    case Player::kGreedy:
      return "greedy";
  }
  return "?";
}

Player parse_player(const std::string& text, const std::string& what) {
  for (Player p : {Player::kRobot, Player::kOracle, Player::kGreedy})
    if (text == to_string(p)) return p;
  throw InputError(
      fmt::format("{}: unknown player '{}' (expected robot, oracle or greedy)", what, text));
}

void RoundOptions::validate() const {
  if (calibration_putts < 1 || calibration_putts > 50)
    throw InputError(
        fmt::format("budget: expected 1..50 learning putts per field, got {}", calibration_putts));
  require_in_range("vision_noise", vision_noise, 0.0, 0.05);
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

RoundResult play_round(const Course& course, const control::ModuleConfig& config,
                       const plant::Plant& plant, const RoundOptions& options, ImaginedCache* cache,
                       const std::function<void(int, const StrokeRecord&)>& on_stroke) {
  options.validate();
  RoundResult result;
  result.course = course.name;
  result.player = options.player;
  for (std::size_t h = 0; h < course.holes.size(); ++h) {
    const CourseHole& ch = course.holes[h];
    HoleWorlds w;
    w.belief = std::make_unique<system::System>(config, ch.field);
    w.truth = std::make_unique<system::System>(config, ch.field, plant);
    w.data = std::make_unique<system::SystemData>(*w.truth);
    const field::Field& field = w.belief->field();
    const auto hole = field.hole.position;
    const control::ModuleConfig& mc = w.belief->module().config();
    const double club_min = mc.speed_min, club_max = std::min(mc.speed_max, mc.arm_speed_cap);
    Rng rng(derive_seed(options.seed, 1000 + h));
    std::normal_distribution<double> normal(0.0, 1.0);

    // The robot's skill on this field: its own putts from the tee at a ladder of club speeds.
    LaunchSkill skill;
    const bool uses_arm = options.player != Player::kOracle;
    if (uses_arm) {
      for (int k = 0; k < options.calibration_putts; ++k) {
        const double u = options.calibration_putts > 1
                             ? static_cast<double>(k) / (options.calibration_putts - 1)
                             : 0.5;
        const double club = club_min + (club_max - club_min) * (0.1 + 0.8 * u);
        control::FullPuttOptions o;
        o.seed = derive_seed(options.seed, 2000 + h * 64 + k);
        const auto r = system::arm_putt(*w.truth, *w.data, hole, 0.0, club, o);
        if (r.hit_refused || !r.hit) continue;
        skill.add(club, 0.0, r.launch);
        ++result.learning_putts;
      }
      if (skill.club.empty())
        throw NumericalError(fmt::format("{}: no calibration putt hit the ball", field.name));
    }
    PlannerOptions po = options.planner;
    if (uses_arm) {  // only the launches the arm can give
      po.speed_min = std::max(po.speed_min, skill.launch_for(club_min * 1.02));
      po.speed_max = std::min(po.speed_max, skill.launch_for(club_max * 0.98));
      if (!(po.speed_max > po.speed_min)) po.speed_max = po.speed_min * 1.5;
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
      if (options.player == Player::kGreedy) {
        const double direct = std::atan2(hole[1] - seen[1], hole[0] - seen[0]);
        std::vector<std::array<double, 2>> launches;
        const double q = std::pow(po.speed_max / po.speed_min, 1.0 / (po.speeds - 1));
        for (int j = 0; j < po.speeds; ++j)
          launches.push_back({direct, po.speed_min * std::pow(q, j)});
        int n = 0;
        const auto out = imagine(*w.belief, seen, hole, launches, po.threads, cache, &n);
        result.imagined_putts += n;
        double best = 1e9;
        for (std::size_t j = 0; j < out.size(); ++j) {
          const double e =
              out[j].sunk ? -1.0 : std::hypot(out[j].rest[0] - hole[0], out[j].rest[1] - hole[1]);
          if (e < best) best = e, plan.angle = direct, plan.speed = launches[j][1];
        }
      } else {
        const bool oracle = options.player == Player::kOracle;
        LaunchError err;
        if (!oracle) err = {std::max(0.004, skill.angle_std), std::max(0.02, skill.speed_std)};
        plan = plan_stroke(oracle ? *w.truth : *w.belief, seen, hole, err, po, cache);
        result.imagined_putts += plan.imagined_putts;
      }
      s.angle = plan.angle;
      s.speed = plan.speed;
      s.sink_probability = plan.sink_probability;
      s.bank = plan.bank;

      sim::PuttOutcome out;
      if (!uses_arm) {
        out =
            system::ball_putt(*w.truth, *w.data, hole, plan.angle, plan.speed, kPathInterval, ball);
      } else {
        control::FullPuttOptions o;
        o.seed = derive_seed(options.seed, 3000 + h * 64 + static_cast<std::uint64_t>(hr.strokes));
        o.record_interval = kPathInterval;
        o.stance = system::stance_for(*w.truth, ball, plan.angle);
        // The robot walks to the ball it saw: the module sees it off by the vision error.
        o.perceived_ball_offset = {seen[0] - ball[0], seen[1] - ball[1]};
        const double hitting = -skill.angle_offset;
        const double club = std::clamp(skill.club_for(plan.speed), club_min, club_max);
        const auto r = system::arm_putt(*w.truth, *w.data, hole, hitting, club, o);
        if (r.hit_refused || !r.hit) {
          // Braked, the ball untouched: the stroke counts (a whiff), the ball stays.
          out.rest_position = ball;
          out.end = sim::PuttEnd::kAtRest;
        } else {
          out = r.outcome;
          skill.add(club, hitting, r.launch);  // every stroke played refines the skill
        }
      }
      ++hr.strokes;
      s.sunk = out.sunk;
      s.rest = out.rest_position;
      s.left_lane = out.end == sim::PuttEnd::kLeftLane || !on_lane(field, out.rest_position);
      for (const auto& p : out.trajectory) s.path.push_back({p.x, p.y});
      hr.sunk = out.sunk;
      if (!hr.sunk) {
        ball = out.rest_position;
        if (s.left_lane) {
          ball = replace_ball(field, ball);
          ++hr.strokes;  // the penalty stroke
        } else {
          try {
            system::check_ball_position(field, ball, "ball");
          } catch (const InputError&) {
            ball = replace_ball(field, ball);  // resting against a border or wall: 1 cm off it
          }
        }
        // A ball resting over the cup's rim but not in: nudge it off the rim onto the lane.
        const double gap = std::hypot(ball[0] - hole[0], ball[1] - hole[1]);
        const double need = 0.5 * field.hole.diameter + field.ball.radius + 1e-3;
        if (gap < need) {
          const double ux = gap > 1e-9 ? (ball[0] - hole[0]) / gap : 1.0;
          const double uy = gap > 1e-9 ? (ball[1] - hole[1]) / gap : 0.0;
          ball = replace_ball(field, {hole[0] + ux * need, hole[1] + uy * need});
        }
      }
      hr.putts.push_back(s);
      if (on_stroke) on_stroke(static_cast<int>(h), hr.putts.back());
    }
    hr.strokes = std::min(hr.strokes, course.max_strokes);
    result.total_strokes += hr.strokes;
    result.total_par += hr.par;
    result.holes.push_back(std::move(hr));
  }
  return result;
}

}  // namespace mg::game
