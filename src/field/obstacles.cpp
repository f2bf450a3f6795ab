#include "field/obstacles.hpp"

#include <algorithm>
#include <cmath>

namespace mg::field {

std::string to_string(ObstacleType type) { return type == ObstacleType::kWall ? "wall" : "block"; }

Footprint Obstacle::footprint() const {
  Footprint f;
  if (type == ObstacleType::kWall) {
    const double dx = to[0] - from[0], dy = to[1] - from[1];
    f.center = {0.5 * (from[0] + to[0]), 0.5 * (from[1] + to[1])};
    f.half = {0.5 * std::hypot(dx, dy), 0.5 * thickness};
    f.yaw = std::atan2(dy, dx);
  } else {
    f.center = center;
    f.half = {0.5 * size[0], 0.5 * size[1]};
    f.yaw = yaw;
  }
  return f;
}

double Obstacle::distance(std::array<double, 2> p) const {
  const Footprint f = footprint();
  const double c = std::cos(f.yaw), s = std::sin(f.yaw);
  const double rx = p[0] - f.center[0], ry = p[1] - f.center[1];
  // The point in the footprint's own frame, then the box's signed distance.
  const double qx = std::abs(c * rx + s * ry) - f.half[0];
  const double qy = std::abs(-s * rx + c * ry) - f.half[1];
  const double outside = std::hypot(std::max(qx, 0.0), std::max(qy, 0.0));
  return outside + std::min(std::max(qx, qy), 0.0);
}

}  // namespace mg::field
