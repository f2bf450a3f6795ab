#pragma once
/// Where the control module gets ball and hole positions: from the simulator (simulation mode)
/// or from the stereo-vision feed over the network (normal mode, thesis 4.2.1).
///
/// Both sources answer `perceive(now)` the same way, never throw, and say whether the answer is
/// fresh enough to act on; the control module decides what to do with a stale answer (hold,
/// never hit). No simulator here: the simulator's ground truth is
/// sim_backend/simulator_perception.hpp.
#include <array>
#include <limits>

#include "perception/vision_feed.hpp"
#include "robot/wam_model.hpp"

namespace mg::perception {

/// What a perception source knows at one instant.
struct Perceived {
  bool fresh = false;                   ///< safe to act on (see each source)
  std::array<double, 3> ball{0, 0, 0};  ///< ball centre [m], world frame
  std::array<double, 3> hole{0, 0, 0};  ///< hole centre on the surface [m], world frame
  /// [s] since the positions were observed; infinity when nothing was ever observed.
  double age = std::numeric_limits<double>::infinity();
};

class Perception {
 public:
  virtual ~Perception() = default;
  /// The current ball and hole at `now` [s, caller's monotonic clock]. Never throws.
  virtual Perceived perceive(double now) noexcept = 0;
};

/// A perception that changes what another one perceives: one effect of a plant's vision (late,
/// off). The caller of a putt builds it before the perception it wraps exists, and the harness
/// binds it (`wrap`) once per putt, ros2_control's wrapped sensor interface. Real-time safe.
class PerceptionWrapper : public Perception {
 public:
  /// Wraps `inner` (not owned; must outlive the use) and starts afresh: the same answers as a
  /// wrapper made now.
  virtual void wrap(Perception& inner) noexcept = 0;
  /// It answers what `inner` answers, bit for bit: the harness leaves it out of the chain (and
  /// may cache the approach, which depends on what the module perceives).
  virtual bool identity() const noexcept = 0;
};

/// A source as a plant's vision really is (plant/plant.hpp): what `source` perceived `latency`
/// seconds ago (the oldest answer it has until then). A fixed history, no allocation.
class DelayedPerception final : public PerceptionWrapper {
 public:
  /// Unbound: `wrap` before the first `perceive`.
  explicit DelayedPerception(double latency) : latency_(latency) {}
  DelayedPerception(Perception& source, double latency) : latency_(latency) { wrap(source); }
  void wrap(Perception& inner) noexcept override {
    source_ = &inner;
    head_ = count_ = 0;
  }
  bool identity() const noexcept override { return !(latency_ > 0.0); }
  Perceived perceive(double now) noexcept override;
  static constexpr int kHistory = 128;  ///< answers kept (robot updates: 1.28 s at 100 Hz)

 private:
  Perception* source_ = nullptr;
  double latency_;
  std::array<double, kHistory> times_{};
  std::array<Perceived, kHistory> history_{};
  int head_ = 0, count_ = 0;
};

/// A source that sees the ball moved by a constant `ball_offset` [m] (the error of this putt's
/// estimate; the hole as the source sees it).
class OffsetPerception final : public PerceptionWrapper {
 public:
  /// Unbound: `wrap` before the first `perceive`.
  explicit OffsetPerception(std::array<double, 2> ball_offset) : offset_(ball_offset) {}
  OffsetPerception(Perception& source, std::array<double, 2> ball_offset) : offset_(ball_offset) {
    wrap(source);
  }
  void wrap(Perception& inner) noexcept override { source_ = &inner; }
  bool identity() const noexcept override { return offset_[0] == 0.0 && offset_[1] == 0.0; }
  Perceived perceive(double now) noexcept override;

 private:
  Perception* source_ = nullptr;
  std::array<double, 2> offset_;
};

/// `source` seen from a mobile base's own frame (robot::Stance): ball and hole taken from the
/// world into the robot's frame, as a robot localised in the world does. Real-time safe.
class StancePerception final : public Perception {
 public:
  StancePerception(Perception& source, const robot::Stance& stance)
      : source_(&source), stance_(stance) {}
  Perceived perceive(double now) noexcept override;

 private:
  Perception* source_;
  robot::Stance stance_;
};

/// The network vision feed: polls it (draining pending datagrams), then reports its latest
/// message. Fresh while the last accepted message arrived less than `max_age` ago. Holds a
/// reference: `feed` must outlive it.
class NetworkPerception final : public Perception {
 public:
  explicit NetworkPerception(VisionFeed& feed) : feed_(&feed) {}
  Perceived perceive(double now) noexcept override;

 private:
  VisionFeed* feed_;
};

}  // namespace mg::perception
