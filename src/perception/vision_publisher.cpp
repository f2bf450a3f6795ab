#include "perception/vision_publisher.hpp"

#include <cmath>
#include <random>

#include <fmt/format.h>

#include "core/error.hpp"
#include "perception/vision_message.hpp"

namespace mg::perception {

void VisionPublisherConfig::validate() const {
  auto bad = [](const char* field, const char* expected, double got) {
    return InputError(
        fmt::format("vision publisher: {}: expected {}, got {}", field, expected, got));
  };
  if (!std::isfinite(rate) || rate < 1.0 || rate > 1000.0) throw bad("rate", "1..1000 Hz", rate);
  if (!std::isfinite(noise) || noise < 0.0 || noise > 0.5) throw bad("noise", "0..0.5 m", noise);
  if (!std::isfinite(latency) || latency < 0.0 || latency > 5.0)
    throw bad("latency", "0..5 s", latency);
  if (!std::isfinite(dropout) || dropout < 0.0 || dropout > 1.0)
    throw bad("dropout", "0..1", dropout);
}

VisionPublisher::VisionPublisher(const std::string& host, std::uint16_t port,
                                 const VisionPublisherConfig& config)
    : sender_(host, port), config_(config), rng_(config.seed) {
  config_.validate();
}

void VisionPublisher::update(double now, const std::array<double, 3>& ball,
                             const std::array<double, 3>& hole) {
  if (now >= next_capture_) {
    next_capture_ = std::max(next_capture_ + 1.0 / config_.rate, now);
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    const bool drop = uniform(rng_) < config_.dropout;
    VisionMessage m;
    m.seq = ++seq_;
    m.stamp = now;
    m.ball = ball;
    m.hole = hole;
    for (int i = 0; i < 3; ++i) {
      m.ball[static_cast<std::size_t>(i)] += config_.noise * gauss(rng_);
      m.hole[static_cast<std::size_t>(i)] += config_.noise * gauss(rng_);
    }
    if (drop)
      ++dropped_;
    else
      pending_.push_back({now + config_.latency, format_vision_message(m)});
  }
  while (!pending_.empty() && pending_.front().due <= now) {
    if (sender_.send(pending_.front().datagram)) ++sent_;
    pending_.pop_front();
  }
}

}  // namespace mg::perception
