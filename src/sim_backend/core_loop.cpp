#include "sim_backend/core_loop.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <exception>

#include "sim_backend/mujoco_arm.hpp"

namespace mg::control {

namespace {

using Clock = std::chrono::steady_clock;

std::int64_t since(Clock::time_point t0, Clock::time_point t1) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count();
}

// Single writer: a relaxed load and store (no locked read-modify-write on the hot path).
template <class T, class U>
void bump(std::atomic<T>& a, U by) noexcept {
  a.store(a.load(std::memory_order_relaxed) + static_cast<T>(by), std::memory_order_relaxed);
}

}  // namespace

// ---- timing ----

int TimingHistogram::bin_of(std::int64_t ns) noexcept {
  if (ns < kLinear) return static_cast<int>(std::max<std::int64_t>(ns, 0));
  const auto v = static_cast<std::uint64_t>(ns);
  const int octave = std::bit_width(v) - 9;  // 0 for [256, 512)
  if (octave >= kOctaves) return kBins - 1;
  const auto sub = static_cast<int>(v >> (octave + 1)) - kSub;  // [0, 128)
  return kLinear + octave * kSub + sub;
}

std::int64_t TimingHistogram::bin_lower(int b) noexcept {
  if (b < kLinear) return b;
  const int octave = (b - kLinear) / kSub;
  const int sub = (b - kLinear) % kSub;
  return static_cast<std::int64_t>(kSub + sub) << (octave + 1);
}

std::int64_t TimingHistogram::bin_width(int b) noexcept {
  if (b < kLinear) return 1;
  return std::int64_t{1} << ((b - kLinear) / kSub + 1);
}

void TimingHistogram::add(std::int64_t ns, std::int64_t budget_ns) noexcept {
  bump(bins_[static_cast<std::size_t>(bin_of(ns))], 1);
  bump(count_, 1);
  if (ns > budget_ns) bump(over_budget_, 1);
  bump(sum_ns_, ns);
  if (ns > max_ns_.load(std::memory_order_relaxed)) max_ns_.store(ns, std::memory_order_relaxed);
}

void TimingHistogram::clear() noexcept {
  for (auto& b : bins_) b.store(0, std::memory_order_relaxed);
  count_.store(0, std::memory_order_relaxed);
  over_budget_.store(0, std::memory_order_relaxed);
  sum_ns_.store(0, std::memory_order_relaxed);
  max_ns_.store(0, std::memory_order_relaxed);
}

CoreTiming TimingHistogram::summary() const noexcept {
  CoreTiming t;
  const std::uint64_t n = count_.load(std::memory_order_relaxed);
  t.ticks = static_cast<int>(n);
  if (n == 0) return t;
  // The sample of rank floor(0.99 n) (0-based), as a sorted list of the samples would give it.
  const std::uint64_t rank =
      std::min(n - 1, static_cast<std::uint64_t>(0.99 * static_cast<double>(n)));
  std::uint64_t seen = 0;
  for (int b = 0; b < kBins; ++b) {
    seen += bins_[static_cast<std::size_t>(b)].load(std::memory_order_relaxed);
    if (seen > rank) {
      t.core_update_p99_us = static_cast<double>(bin_lower(b) + bin_width(b)) * 1e-3;
      break;
    }
  }
  t.overruns = static_cast<int>(over_budget_.load(std::memory_order_relaxed));
  t.core_update_max_us = static_cast<double>(max_ns_.load(std::memory_order_relaxed)) * 1e-3;
  // Read during a run, the count may be ahead of the bins: the 99th percentile is then the max.
  if (t.core_update_p99_us == 0.0) t.core_update_p99_us = t.core_update_max_us;
  t.core_update_mean_us =
      static_cast<double>(sum_ns_.load(std::memory_order_relaxed)) * 1e-3 / static_cast<double>(n);
  return t;
}

// ---- the loop ----

CoreLoop::CoreLoop(const sim::World& world, const ModuleModel& model, mjData* d,
                   CoreLoopOptions options)
    : CoreLoop(world, find_sim_ids(world), model, d, options) {}

CoreLoop::CoreLoop(const sim::World& world, const SimIds& ids, const ModuleModel& model, mjData* d,
                   CoreLoopOptions options)
    : world_(&world),
      model_(&model),
      d_(d),
      options_(options),
      ids_(ids),
      sim_arm_(ids_.arm, d),
      arm_(&sim_arm_),
      own_(std::make_unique<ModuleData>(model)),
      data_(own_.get()),
      truth_(world, d),
      perception_(&truth_) {
  steps_per_tick_ = std::max(
      1, static_cast<int>(std::lround(model.config().core_period() / world.model()->opt.timestep)));
  budget_ns_ = static_cast<std::int64_t>(std::llround(model.config().core_period() * 1e9));
  module_reset(model, *data_, ids_.arm, d);
}

void CoreLoop::set_perception(perception::Perception* perception) {
  perception_ = perception != nullptr ? perception : &truth_;
}

void CoreLoop::caught(const char* what) noexcept {
  data_->hook_fault = true;  // the module observes a fault at its next update: a moving arm brakes
  ++fault_.count;
  fault_.time = d_->time;
  std::strncpy(fault_.what.data(), what != nullptr ? what : "", fault_.what.size() - 1);
  fault_.what.back() = '\0';
}

// Calls a hook; an exception becomes a fault of the module (never std::terminate).
template <class Call>
void CoreLoop::call_hook(Call&& call) noexcept {
  if (hooks_ == nullptr) return;
  try {
    call(*hooks_);
  } catch (const std::exception& e) {
    caught(e.what());
  } catch (...) {
    caught("an exception of unknown type");
  }
}

void CoreLoop::module_tick() noexcept {
  ModuleData& data = *data_;
  const MeasuredState measured = arm_->read();
  if (data.tick % model_->config().robot_update_divider == 0) {
    robot_update(*model_, data, perception_->perceive(measured.time));
    call_hook([&](CoreHooks& h) { h.after_robot_update(measured, data); });
  }
  // Timed: the module's update and the write (the read is a copy of 15 numbers; the robot
  // update and the hooks are not the core update's).
  const ModuleState before = data.state;
  const Clock::time_point t0 = Clock::now();
  const ModuleCommand command = module_update(*model_, data, measured);
  arm_->write(command);
  timing_.add(since(t0, Clock::now()), budget_ns_);
  ticks_.store(ticks_.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  call_hook([&](CoreHooks& h) { h.after_tick(command, before); });
}

void CoreLoop::physics() noexcept {
  if (options_.fine_impact)
    physics_step(*world_, ids_, d_);
  else
    world_->step(d_);
}

void CoreLoop::step() noexcept {
  if (steps_ % steps_per_tick_ == 0) module_tick();
  call_hook([&](CoreHooks& h) { h.before_step(steps_); });
  physics();
  ++steps_;
  call_hook([&](CoreHooks& h) { h.after_step(steps_ - 1); });
}

void CoreLoop::tick() noexcept {
  do {
    step();
  } while (steps_ % steps_per_tick_ != 0);
}

void CoreLoop::tick_without_physics() noexcept {
  if (steps_ % steps_per_tick_ == 0) module_tick();
  const long n = steps_per_tick_ - steps_ % steps_per_tick_;
  d_->time += static_cast<double>(n) * world_->model()->opt.timestep;
  steps_ += n;
}

void CoreLoop::restore(const ModuleData& data, long steps) {
  *data_ = data;
  steps_ = steps;
  timing_.clear();
}

void CoreLoop::replace_module(const ModuleModel& model, ModuleData& data) noexcept {
  model_ = &model;
  data_ = &data;
}

}  // namespace mg::control
