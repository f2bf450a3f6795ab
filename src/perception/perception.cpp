#include "perception/perception.hpp"

namespace mg::perception {

Perceived DelayedPerception::perceive(double now) noexcept {
  head_ = (head_ + 1) % kHistory;
  times_[static_cast<std::size_t>(head_)] = now;
  history_[static_cast<std::size_t>(head_)] = source_->perceive(now);
  count_ = count_ < kHistory ? count_ + 1 : kHistory;
  // The newest answer at least `latency` old; the oldest kept if none is.
  int pick = head_;
  for (int k = 0; k < count_; ++k) {
    pick = (head_ - k + kHistory) % kHistory;
    if (times_[static_cast<std::size_t>(pick)] <= now - latency_) break;
  }
  Perceived p = history_[static_cast<std::size_t>(pick)];
  p.age += now - times_[static_cast<std::size_t>(pick)];
  return p;
}

Perceived OffsetPerception::perceive(double now) noexcept {
  Perceived p = source_->perceive(now);
  p.ball[0] += offset_[0];
  p.ball[1] += offset_[1];
  return p;
}

Perceived StancePerception::perceive(double now) noexcept {
  Perceived p = source_->perceive(now);
  p.ball = stance_.to_local(p.ball);
  p.hole = stance_.to_local(p.hole);
  return p;
}

Perceived NetworkPerception::perceive(double now) noexcept {
  feed_->poll(now);
  Perceived p;
  if (const auto& m = feed_->latest()) {
    p.ball = m->ball;
    p.hole = m->hole;
    p.age = feed_->age(now);
  }
  p.fresh = feed_->fresh(now);
  return p;
}

}  // namespace mg::perception
