#include "sim/fast_putt.hpp"

#include <algorithm>
#include <cmath>
#include <variant>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"
#include "sim/ground_step.hpp"

namespace mg::sim {

namespace {

using namespace ground;

// ---------------------------------------------------------------------------------------------
// Where the ball may touch something besides the ground.

/// An obstacle's footprint: centre and half lengths [m], its yaw's cosine and sine.
struct Box2 {
  double cx, cy, hx, hy, cos_yaw, sin_yaw;
};

/// Lane borders, obstacles and the cup, as reach of the ball's centre.
struct Obstacles {
  double x0 = 0.0, x1 = 0.0, y0 = 0.0, y1 = 0.0;  ///< centre beyond these: at a border [m]
  int count = 0;
  std::array<Box2, field::kMaxObstacles> boxes{};
  double reach = 0.0;                                   ///< ... closer than this to an obstacle [m]
  double hole_x = 0.0, hole_y = 0.0, hole_reach = 0.0;  ///< ... or to the hole's centre [m]
};

double dot3(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Contacts start at zero distance: this much more covers rounding in MuJoCo's geometry [m].
constexpr double kSafety = 1e-5;

Obstacles obstacles_of(const World& world, std::array<double, 2> hole) {
  const field::Field& f = world.field();
  const mjModel* m = world.model();
  Obstacles o;
  const double r = f.ball.radius, reach = r + kSafety;
  o.x0 = f.bounds[0] + reach;
  o.x1 = f.bounds[1] - reach;
  o.y0 = f.bounds[2] + reach;
  o.y1 = f.bounds[3] - reach;
  for (const field::Obstacle& ob : f.obstacles) {  // at most kMaxObstacles (model_fits)
    const field::Footprint fp = ob.footprint();
    o.boxes[static_cast<std::size_t>(o.count++)] = {
        fp.center[0], fp.center[1], fp.half[0], fp.half[1], std::cos(fp.yaw), std::sin(fp.yaw)};
  }
  o.reach = reach;
  // The cup's wall boxes reach out to hypot(R + thickness, half length); a cup tilted with a
  // sloped hole shifts them by up to (depth + its lowering) times the slope.
  const mjtNum* size = m->geom_size + 3 * world.ids().first_wall_geom;
  const double hole_r = 0.5 * f.hole.diameter;
  const auto g = f.surface.gradient(hole[0], hole[1]);
  const double tilt = std::hypot(g[0], g[1]) * (f.hole.depth + hole_r * std::hypot(g[0], g[1]));
  o.hole_x = hole[0];
  o.hole_y = hole[1];
  o.hole_reach = std::hypot(hole_r + 2.0 * size[0], size[1]) + tilt + reach;
  return o;
}

// Horizontal distance [m] the ball's centre may move before it can touch a border, an obstacle or
// the cup (<= 0: it may touch one now).
double clearance(const Obstacles& o, const Vec3& c) {
  double free = std::min({c[0] - o.x0, o.x1 - c[0], c[1] - o.y0, o.y1 - c[1]});
  for (int i = 0; i < o.count; ++i) {
    const Box2& b = o.boxes[static_cast<std::size_t>(i)];
    const double rx = c[0] - b.cx, ry = c[1] - b.cy;
    const double qx = std::abs(b.cos_yaw * rx + b.sin_yaw * ry) - b.hx;
    const double qy = std::abs(-b.sin_yaw * rx + b.cos_yaw * ry) - b.hy;
    const double outside = std::hypot(std::max(qx, 0.0), std::max(qy, 0.0));
    free = std::min(free, outside + std::min(std::max(qx, qy), 0.0) - o.reach);
  }
  return std::min(free, std::hypot(c[0] - o.hole_x, c[1] - o.hole_y) - o.hole_reach);
}

// ---------------------------------------------------------------------------------------------
// Hand-offs between the closed form and the MuJoCo world.

void to_mujoco(const World& world, mjData* d, const Ball& b, double time) {
  BallState s;
  for (int k = 0; k < 3; ++k) {
    s.qpos[k] = b.c[k];
    s.qvel[k] = b.v[k];
    s.qvel[k + 3] = b.w[k];  // identity orientation: body = world
    s.qacc_warmstart[k] = b.a[k];
    s.qacc_warmstart[k + 3] = b.alpha[k];
  }
  s.qpos[3] = 1.0;  // a sphere's orientation does not change its motion
  s.ground_normal = b.normal;
  s.time = time;
  world.set_ball_state(d, s);
}

Ball from_mujoco(const World& world, const mjData* d) {
  const BallState s = world.ball_state(d);
  Ball b;
  mjtNum w[3];
  mju_rotVecQuat(w, s.qvel.data() + 3, s.qpos.data() + 3);
  mjtNum a[3];
  mju_rotVecQuat(a, s.qacc_warmstart.data() + 3, s.qpos.data() + 3);
  for (int k = 0; k < 3; ++k) {
    b.c[k] = s.qpos[k];
    b.v[k] = s.qvel[k];
    b.w[k] = w[k];
    b.a[k] = s.qacc_warmstart[k];
    b.alpha[k] = a[k];
  }
  b.normal = s.ground_normal;
  return b;
}

// simulate_putt's start (checks, launch, the same bits in `d`), and the ball it launched.
Ball started(const World& world, mjData* d, std::array<double, 2> hole,
             const PuttRequest& request) {
  start_putt(world, d, hole, request);
  return from_mujoco(world, d);
}

/// What the ball touched in `d`'s last step.
struct Touching {
  bool ground = false;  ///< the ground or the cup floor
  bool wall = false;    ///< a border, an obstacle or a cup wall
};

Touching touching(const World& world, const mjData* d) {
  Touching t;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    if (c.dist >= 0.0) continue;
    (world.is_ball_ground(c) ? t.ground : t.wall) = true;
  }
  t.wall = t.wall || world.wall_impact(d) > 0.0;  // borders and obstacles: sim/walls
  return t;
}

// ---------------------------------------------------------------------------------------------
// The hybrid run.

constexpr double kNever = 1e300;       // [s] a time not reached
constexpr double kCalmRollTime = 0.1;  // [s] on the ground this long before a replay ends

class HybridPutt {
 public:
  HybridPutt(const World& world, mjData* d, std::array<double, 2> hole, const PuttRequest& request,
             const OutcomeRules& rules, const FastPuttOptions& options)
      : world_(world),
        d_(d),
        hole_(hole),
        request_(request),
        rules_(rules),
        options_(options),
        gm_(ground_model(world)),
        surface_(compile_surface(world.field().surface)),
        obstacles_(obstacles_of(world, hole)),
        ball_(started(world, d, hole, request)),
        tracker_(world, d, rules) {
    const double h = gm_.timestep;
    record_every_ = request.record_interval > 0.0
                        ? std::max(1, static_cast<int>(std::lround(request.record_interval / h)))
                        : 0;
    max_steps_ = static_cast<int>(std::ceil(request.max_duration / h));
    if (record_every_) {
      trajectory_.reserve(static_cast<std::size_t>(max_steps_ / record_every_ + 2));
      record();
    }
  }

  PuttOutcome run() {
    bool decided = false;
    while (steps_ < max_steps_ && !decided) {
      if (!in_mujoco_ && !exact_ && free_path_ <= next_travel()) {
        free_path_ = clearance(obstacles_, ball_.c);
        in_mujoco_ = free_path_ <= next_travel();
        if (in_mujoco_) to_mujoco(world_, d_, ball_, t_);
      }
      if (in_mujoco_ || exact_ || !step_ground()) step_mujoco();
      ++steps_;
      decided = tracker_.update(t_, ball_.c.data(), ball_.v.data());
      if (record_every_ && (steps_ % record_every_ == 0 || decided)) record();
      if (exact_ && steps_ >= exact_until_ && calm()) {
        exact_ = false;
        airtime_ = 0.0;
        wall_hits_ = 0;
      }
      if (!decided && !exact_ && chaotic()) replay();
    }
    PuttOutcome out = tracker_.outcome();
    out.steps = mujoco_steps_;
    if (!decided) out.end = PuttEnd::kTimeOut;
    out.trajectory = std::move(trajectory_);
    return out;
  }

 private:
  // A closed-form step; false (nothing done) when MuJoCo must take it.
  bool step_ground() {
    const GroundStep result = ground_step(gm_, surface_, ball_);
    if (result == GroundStep::kTooDeep) {
      to_mujoco(world_, d_, ball_, t_);
      return false;
    }
    t_ += gm_.timestep;
    track_contact(result == GroundStep::kTouching);
    at_wall_ = false;
    free_path_ -= gm_.timestep * std::sqrt(ball_.v[0] * ball_.v[0] + ball_.v[1] * ball_.v[1]);
    return true;
  }

  // [m] How far the ball may move in the next step (and a little more): the World resolves a
  // border or obstacle at the end of the step that reaches it (sim/walls), so that step is
  // MuJoCo's.
  double next_travel() const {
    return 1.01 * gm_.timestep * std::sqrt(dot3(ball_.v, ball_.v)) + 1e-6;
  }

  void track_contact(bool touching) {
    if (!touching) airtime_ += gm_.timestep;
    grounded_since_ = touching ? std::min(grounded_since_, t_) : kNever;
  }

  void step_mujoco() {
    world_.step(d_);
    ++mujoco_steps_;
    ball_ = from_mujoco(world_, d_);
    t_ = d_->time;
    const Touching now = touching(world_, d_);
    track_contact(now.ground);
    if (now.wall && !at_wall_ && std::hypot(ball_.v[0], ball_.v[1]) > options_.wall_hit_speed)
      ++wall_hits_;
    at_wall_ = now.wall;
    free_path_ = clearance(obstacles_, ball_.c);
    in_mujoco_ = free_path_ <= next_travel();
  }

  // Starts over in MuJoCo exactly as simulate_putt does (the same bits) and stays there until
  // the ball is past this step and calm: hops off walls make MuJoCo's own putts chaotic (a
  // rounding-level difference grows ~10x per hop), so only its own steps reproduce them.
  void replay() {
    exact_until_ = steps_;
    start_putt(world_, d_, hole_, request_);
    tracker_ = OutcomeTracker(world_, d_, rules_);
    ball_ = from_mujoco(world_, d_);
    t_ = d_->time;
    steps_ = 0;
    grounded_since_ = kNever;
    exact_ = in_mujoco_ = true;
    trajectory_.clear();
    if (record_every_) record();
  }

  // Hopping off walls for long enough that MuJoCo's own putt is chaotic (FastPuttOptions).
  bool chaotic() const {
    if (options_.replay_airtime <= 0.0) return false;
    const double hits = options_.replay_wall_hits > 0
                            ? static_cast<double>(wall_hits_) / options_.replay_wall_hits
                            : 0.0;
    return airtime_ / options_.replay_airtime + hits >= 1.0;
  }

  // Rolling (on the ground for a while) and too slow to hop off a wall again.
  bool calm() const {
    return std::hypot(ball_.v[0], ball_.v[1]) < options_.calm_speed &&
           t_ - grounded_since_ >= kCalmRollTime;
  }

  void record() {
    trajectory_.push_back(
        {t_, ball_.c[0], ball_.c[1], ball_.c[2], ball_.v[0], ball_.v[1], ball_.v[2]});
  }

  const World& world_;
  mjData* d_;
  std::array<double, 2> hole_;
  const PuttRequest& request_;
  OutcomeRules rules_;
  FastPuttOptions options_;
  GroundModel gm_;
  CompiledSurface surface_;
  Obstacles obstacles_;
  Ball ball_;
  OutcomeTracker tracker_;
  std::vector<BallSample> trajectory_;
  int record_every_ = 0, max_steps_ = 0, steps_ = 0, mujoco_steps_ = 0, exact_until_ = 0;
  int wall_hits_ = 0;     ///< fast hits of walls (since the start or the last calm)
  bool at_wall_ = false;  ///< touching a wall in the last MuJoCo step
  double t_ = 0.0;        ///< [s]
  double airtime_ = 0.0;  ///< [s] without ground contact (since the start or the last calm)
  double grounded_since_ = kNever;  ///< [s] on the ground since (kNever: in the air)
  double free_path_ = 0.0;          ///< [m] the ball may move this far before clearance is checked
  bool in_mujoco_ = false;  ///< the MuJoCo world steps the ball (it may touch more than ground)
  bool exact_ = false;      ///< replaying in MuJoCo from the start (see replay)
};

}  // namespace

bool fast_putt_applies(const World& world) { return model_fits(world); }

PuttOutcome fast_putt(const World& world, mjData* d, std::array<double, 2> hole,
                      const PuttRequest& request, const OutcomeRules& rules,
                      const FastPuttOptions& options) {
  if (!model_fits(world)) return simulate_putt(world, d, hole, request, rules);
  return HybridPutt(world, d, hole, request, rules, options).run();
}

}  // namespace mg::sim
