#pragma once
/// Obstacles on a lane (field file section `obstacles:`, docs/fields.md): walls and blocks the ball
/// bounces off as it does off the borders. Both are vertical prisms over an oriented rectangle
/// (the footprint), from below the ground to `height` above the highest ground under them.
#include <array>
#include <cstddef>
#include <string>

namespace mg::field {

inline constexpr std::size_t kMaxObstacles = 64;
/// The most restitution a border or obstacle may have (sim/walls resolves any value in 0..1 without
/// gaining energy; a livelier wall than this is not a minigolf border).
inline constexpr double kMaxWallRestitution = 0.95;

enum class ObstacleType { kWall, kBlock };
std::string to_string(ObstacleType type);

/// An oriented rectangle in the horizontal plane.
struct Footprint {
  std::array<double, 2> center{0, 0};  ///< [m]
  std::array<double, 2> half{0, 0};    ///< [m] half lengths along its own x and y
  double yaw = 0.0;                    ///< [rad] of its own x axis from world +x
};

struct Obstacle {
  ObstacleType type = ObstacleType::kWall;
  // A wall: the segment from -> to is its centre line; `thickness` across it.
  std::array<double, 2> from{0, 0}, to{0, 0};  ///< [m]
  double thickness = 0.04;                     ///< [m]
  // A block: centre, full lengths along its own x and y, yaw.
  std::array<double, 2> center{0, 0};  ///< [m]
  std::array<double, 2> size{0, 0};    ///< [m]
  double yaw = 0.0;                    ///< [rad]
  // Both.
  double height = 0.06;      ///< [m] above the highest ground under the footprint
  double restitution = 0.6;  ///< [-] normal speed after / before a head-on bounce

  /// The footprint (a wall: along from -> to, length |to - from|, width `thickness`).
  Footprint footprint() const;
  /// [m] signed horizontal distance from `p` to the footprint (negative inside).
  double distance(std::array<double, 2> p) const;
};

}  // namespace mg::field
