#include "game/lane_region.hpp"

#include <cmath>
#include <deque>

#include "core/error.hpp"

namespace mg::game {

LaneRegion::LaneRegion(const field::Field& field, std::array<double, 2> hole, double cell)
    : cell_(cell) {
  const auto& b = field.bounds;
  x0_ = b[0], y0_ = b[2];
  nx_ = static_cast<long>(std::ceil((b[1] - b[0]) / cell));
  ny_ = static_cast<long>(std::ceil((b[3] - b[2]) / cell));
  if (!(cell > 0.0) || nx_ <= 0 || ny_ <= 0 || nx_ * ny_ > 50'000'000)
    throw InputError("lane region: lane bounds too large for the grid");
  const double clear = field.ball.radius - kTouchTolerance;
  std::vector<std::uint8_t> open(static_cast<std::size_t>(nx_ * ny_), 0);
  for (long i = 0; i < nx_; ++i)
    for (long j = 0; j < ny_; ++j) {
      const std::array<double, 2> p{x0_ + (i + 0.5) * cell, y0_ + (j + 0.5) * cell};
      bool ok = p[0] >= b[0] + clear && p[0] <= b[1] - clear && p[1] >= b[2] + clear &&
                p[1] <= b[3] - clear;
      for (const auto& o : field.obstacles) ok = ok && o.distance(p) >= clear;
      open[static_cast<std::size_t>(i * ny_ + j)] = ok ? 1 : 0;
    }
  reached_.assign(open.size(), 0);
  const auto& h = hole;
  const long hi = std::lround((h[0] - x0_) / cell - 0.5),
             hj = std::lround((h[1] - y0_) / cell - 0.5);
  std::deque<std::pair<long, long>> todo;
  const auto visit = [&](long i, long j) {
    if (i < 0 || j < 0 || i >= nx_ || j >= ny_) return;
    const auto k = static_cast<std::size_t>(i * ny_ + j);
    if (open[k] == 0 || reached_[k] != 0) return;
    reached_[k] = 1;
    todo.emplace_back(i, j);
  };
  visit(hi, hj);
  while (!todo.empty()) {
    const auto [i, j] = todo.front();
    todo.pop_front();
    visit(i + 1, j), visit(i - 1, j), visit(i, j + 1), visit(i, j - 1);
  }
}

bool LaneRegion::reached(long i, long j) const {
  if (i < 0 || j < 0 || i >= nx_ || j >= ny_) return false;
  return reached_[static_cast<std::size_t>(i * ny_ + j)] != 0;
}

bool LaneRegion::contains(std::array<double, 2> p) const {
  if (!std::isfinite(p[0]) || !std::isfinite(p[1])) return false;
  const long i = static_cast<long>(std::floor((p[0] - x0_) / cell_));
  const long j = static_cast<long>(std::floor((p[1] - y0_) / cell_));
  for (long di = -1; di <= 1; ++di)
    for (long dj = -1; dj <= 1; ++dj)
      if (reached(i + di, j + dj)) return true;
  return false;
}

std::array<double, 2> LaneRegion::last_in_play(const std::vector<std::array<double, 2>>& path,
                                               std::array<double, 2> fallback) const {
  for (auto it = path.rbegin(); it != path.rend(); ++it)
    if (contains(*it)) return *it;
  return fallback;
}

}  // namespace mg::game
