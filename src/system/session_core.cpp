#include "system/session_core.hpp"

#include <algorithm>
#include <cmath>

#include "robot/wam_model.hpp"

namespace mg::system {

using namespace mg::control;  // the module's types, used throughout the core side

namespace {

/// The arm at its default rest posture, the ball on the tee, the field's hole.
sim::DataPtr rest_data(const sim::World& world) {
  sim::DataPtr d = world.make_data();
  world.reset(d.get());
  robot::Vector7 rest;
  for (int j = 0; j < 7; ++j) rest[j] = robot::kDefaultRestPosture[static_cast<std::size_t>(j)];
  robot::set_joint_positions(find_sim_ids(world).arm, d.get(), rest);
  mj_forward(world.model(), d.get());
  return d;
}

/// A snapshot whose pose arrays fit `m` (sized once: publishing copies into them).
Snapshot sized_snapshot(const mjModel* m) {
  Snapshot s;
  s.qpos.resize(static_cast<std::size_t>(m->nq));
  s.mocap_pos.resize(static_cast<std::size_t>(3 * m->nmocap));
  s.mocap_quat.resize(static_cast<std::size_t>(4 * m->nmocap));
  s.userdata.resize(static_cast<std::size_t>(m->nuserdata));
  return s;
}

}  // namespace

perception::Perceived BufferedPerception::perceive(double now) noexcept {
  const StampedPerception& s = buffer_->read();
  perception::Perceived p = s.seen;
  p.age += std::max(0.0, now - s.stamp);  // it was that old when the I/O thread asked
  return p;
}

SessionCore::SessionCore(const sim::World& world, const ModuleModel& model, bool realtime,
                         SessionObserver* observer, const sim::OutcomeTracker* tracker)
    : snapshot(sized_snapshot(world.model())),
      world_(world),
      d_(rest_data(world)),
      loop_(world, model, d_.get(), CoreLoopOptions{.fine_impact = !realtime}),
      truth_(world, d_.get()),
      observer_(observer),
      tracker_proto_(tracker) {
  speed_ = std::clamp(1.0, model.config().speed_min, model.speed_cap());
  loop_.set_hooks(this);
  publish();
}

// ---- channels ----

void SessionCore::push(const Event& e) noexcept {
  if (!events.push(e)) events_lost.fetch_add(1, std::memory_order_relaxed);
}

void SessionCore::reply(Reply r, double a, double b) noexcept {
  Event e;
  e.kind = Event::Kind::kReply;
  e.t = d_->time;
  e.reply = r;
  e.a = a;
  e.b = b;
  push(e);
}

ModuleStatus SessionCore::status() const noexcept {
  const ModuleData& md = loop_.module();
  return ModuleStatus{md.state, md.ball_hit, md.at_rest_pose, md.overrun_fault || md.hook_fault,
                      md.tick};
}

SessionView SessionCore::view() const {
  return SessionView{world_,
                     d_.get(),
                     loop_.model(),
                     status(),
                     angle_,
                     speed_,
                     hit_when_at_rest_,
                     tracker_.has_value(),
                     last_outcome_ ? &*last_outcome_ : nullptr};
}

void SessionCore::publish() noexcept {
  const mjModel* m = world_.model();
  const mjData* d = d_.get();
  const ModuleData& md = loop_.module();
  Snapshot& s = snapshot.back();
  s.time = d->time;
  s.ticks = loop_.ticks();
  s.module = status();
  s.model = &loop_.model();
  s.angle = angle_;
  s.speed = speed_;
  s.hit_armed = hit_when_at_rest_;
  s.ball_rolling = tracker_.has_value();
  s.recording = recording_;
  const perception::Perceived truth = truth_.perceive(d->time);
  s.ball = truth.ball;
  s.hole = truth.hole;
  s.seen = md.seen;
  s.fresh = perception_fresh(loop_.model(), md);
  s.last_outcome = last_outcome_;  // an empty trajectory: no allocation
  std::copy_n(d->qpos, m->nq, s.qpos.begin());
  std::copy_n(d->mocap_pos, 3 * m->nmocap, s.mocap_pos.begin());
  std::copy_n(d->mocap_quat, 4 * m->nmocap, s.mocap_quat.begin());
  std::copy_n(d->userdata, m->nuserdata, s.userdata.begin());
  snapshot.publish();
}

// ---- commands ----

void SessionCore::apply(const CoreCommand& c) noexcept {
  using Kind = CoreCommand::Kind;
  ModuleData& md = loop_.module();
  const ModuleModel& model = loop_.model();
  switch (c.kind) {
    case Kind::kIdle:
      hit_when_at_rest_ = false;
      request_idle(md);
      // `idle` at standstill acknowledges an overrun-streak or a hook fault.
      if (md.state == ModuleState::kIdle && (md.overrun_fault || md.hook_fault)) {
        reply(Reply::kFaultCleared, md.overrun_fault ? 1.0 : 0.0, md.hook_fault ? 1.0 : 0.0);
        md.overrun_fault = false;
        md.hook_fault = false;
      }
      break;
    case Kind::kRest:
      request_rest(model, md, angle_);
      break;
    case Kind::kHit:
      if (md.state == ModuleState::kRest && md.at_rest_pose && md.pending == Command::kNone &&
          md.angle == angle_) {
        if (!request_hit(model, md, angle_, speed_))
          reply(Reply::kHitRefusedEnvelope, angle_, speed_);
      } else if (md.state == ModuleState::kHitting || md.state == ModuleState::kBraking) {
        reply(Reply::kHitAlreadyRunning);
      } else {
        if (md.state != ModuleState::kRest || md.angle != angle_) request_rest(model, md, angle_);
        hit_when_at_rest_ = true;
        reply(Reply::kGoingToRestFirst);
      }
      break;
    case Kind::kAngle:
    case Kind::kAngleSpeed:
      angle_ = c.a;
      if (c.kind == Kind::kAngleSpeed)
        speed_ = c.b;
      else
        reply(Reply::kAngle, angle_);
      // At (or on the way to) the rest pose: turn to the new hitting direction.
      if (md.state == ModuleState::kRest) request_rest(model, md, angle_);
      break;
    case Kind::kSpeed:
      speed_ = c.a;
      reply(Reply::kSpeed, speed_);
      break;
    case Kind::kHole:
      try {  // checked by the session before: this does not throw
        world_.set_hole(d_.get(), {c.a, c.b});
        tracker_proto_ = c.tracker;
        reply(Reply::kHole, c.a, c.b);
      } catch (...) {
        Event e;
        e.t = d_->time;
        e.note = "hole refused by the simulation";
        push(e);
      }
      break;
    case Kind::kReset:
      if (md.state == ModuleState::kHitting) {
        reply(Reply::kResetRefusedHitting);
      } else {
        const auto& tee = world_.field().tee;
        world_.place_ball(d_.get(), {tee[0], tee[1]});
        tracker_.reset();
        reply(Reply::kReset, tee[0], tee[1]);
      }
      break;
    case Kind::kLoad:
      if (md.state != ModuleState::kIdle) {
        reply(Reply::kLoadRefusedNotIdle);
      } else {
        // Perception stale until the next robot update.
        module_reset(*c.model, *c.data, loop_.ids().arm, d_.get());
        loop_.replace_module(*c.model, *c.data);
        reply(Reply::kLoaded);
      }
      break;
    case Kind::kRecord:
      recording_ = c.on;
      break;
  }
}

void SessionCore::apply_queued() noexcept {
  CoreCommand c;
  std::uint64_t last = 0;
  while (commands.pop(c)) {
    apply(c);
    last = c.seq;
  }
  if (last == 0) return;
  publish();
  applied.store(last, std::memory_order_release);
}

// ---- the tick ----

void SessionCore::tick() noexcept {
  loop_.tick();
  const CoreFault& fault = loop_.fault();
  if (fault.count != faults_reported_) {
    faults_reported_ = fault.count;
    Event e;
    e.kind = Event::Kind::kHookFault;
    e.t = fault.time;
    e.what = fault.what;
    push(e);
  }
  publish();
}

void SessionCore::overrun_streak() noexcept {
  ModuleData& md = loop_.module();
  if (md.overrun_fault) return;
  md.overrun_fault = true;
  Event e;
  e.t = d_->time;
  e.note = "overrun streak: the core update missed its deadline too often (fault)";
  push(e);
}

void SessionCore::after_robot_update(const MeasuredState& measured, ModuleData& md) {
  const ModuleModel& model = loop_.model();
  if (recording_) {
    // From what the arm measured (q, qd, t), what the module did and saw, and the simulated ball.
    RecordSample s;
    s.t = measured.time;
    s.state = static_cast<int>(md.state);
    for (int j = 0; j < 7; ++j) {
      const auto i = static_cast<std::size_t>(j);
      s.q[i] = measured.q[j];
      s.qd[i] = measured.qd[j];
      s.tau[i] = md.tau[j];
    }
    const Eigen::Vector3d face = robot::dh_club_pose(model.arm(), measured.q).translation();
    s.face = {face.x(), face.y(), face.z()};
    s.ball = truth_.perceive(measured.time).ball;
    s.seen_ball = md.seen.ball;
    s.seen_hole = {md.seen.hole[0], md.seen.hole[1]};
    s.fresh = perception_fresh(model, md);
    s.angle = angle_;
    s.speed = speed_;
    if (!samples.push(s)) samples_lost.fetch_add(1, std::memory_order_relaxed);
  }
  // `hit` from Idle or on the way to the rest pose: hit once the rest pose is reached.
  if (hit_when_at_rest_) {
    if (md.state != ModuleState::kRest && md.pending != Command::kRest) {
      hit_when_at_rest_ = false;  // idled, braked or faulted on the way
    } else if (md.at_rest_pose && md.pending == Command::kNone) {
      hit_when_at_rest_ = false;
      request_hit(model, md, angle_, speed_);
    }
  }
}

void SessionCore::after_tick(const ModuleCommand& command, ModuleState before) {
  const mjData* d = d_.get();
  const Reason reason = command.status.reason;
  if (command.state != before) {
    Event e;
    e.kind = Event::Kind::kTransition;
    e.t = d->time;
    e.from = before;
    e.to = command.state;
    e.reason = reason;
    push(e);
    if (before == ModuleState::kHitting && reason == Reason::kBallHit &&
        tracker_proto_ != nullptr) {
      // A copy of the tracker prepared for this hole (no field evaluation, no allocation).
      tracker_.emplace(*tracker_proto_);
      tracker_->restart(d);
      hit_time_ = d->time;
    }
  } else if (reason != Reason::kNoChange && reason != Reason::kFault) {
    Event e;
    e.kind = Event::Kind::kRefused;
    e.t = d->time;
    e.from = e.to = before;
    e.reason = reason;
    push(e);
  }
}

void SessionCore::after_step(long /*step*/) {
  const mjData* d = d_.get();
  if (tracker_ && tracker_->update(d)) {
    const sim::PuttOutcome o = tracker_->outcome();
    const auto hole = world_.hole_position(d);
    Event e;
    e.kind = Event::Kind::kOutcome;
    e.t = d->time;
    e.end = o.end;
    e.sunk = o.sunk;
    e.x = o.rest_position[0];
    e.y = o.rest_position[1];
    e.distance = std::hypot(o.rest_position[0] - hole[0], o.rest_position[1] - hole[1]);
    e.duration = d->time - hit_time_;
    push(e);
    last_outcome_ = o;
    tracker_.reset();
  }
  if (observer_ != nullptr) observer_->after_step(view());
}

}  // namespace mg::system
