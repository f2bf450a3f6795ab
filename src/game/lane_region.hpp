#pragma once
/// The playable part of a lane: the places a ball can lie from which it can roll to the hole
/// without leaving the ground, i.e. the connected part of the lane, clear of obstacles, that
/// holds the hole. Walls that meet the borders cut a lane in parts (the corner behind the L of
/// data/fields/l-shape.yaml); a ball that hops a wall into such a part is out of play, as one
/// that leaves the lane (docs/round.md, "A ball out of play").
#include <array>
#include <cstdint>
#include <vector>

#include "field/field.hpp"

namespace mg::game {

class LaneRegion {
 public:
  /// Flood fill from `hole` over a grid of `cell` [m]: a cell is open when its centre lies a
  /// ball radius minus `kTouchTolerance` inside the borders and from every obstacle.
  LaneRegion(const field::Field& field, std::array<double, 2> hole, double cell = 0.01);
  /// True if a ball resting at `p` [m] is in play (its cell, or one next to it, is reached).
  bool contains(std::array<double, 2> p) const;
  /// The last point of `path` in play (a ball out of play is put back there); `fallback` if none.
  std::array<double, 2> last_in_play(const std::vector<std::array<double, 2>>& path,
                                     std::array<double, 2> fallback) const;
  double cell() const { return cell_; }

  /// [m] how far inside an open cell's test a resting ball may touch a wall or border.
  static constexpr double kTouchTolerance = 0.005;

 private:
  bool reached(long i, long j) const;
  double x0_ = 0.0, y0_ = 0.0, cell_ = 0.01;
  long nx_ = 0, ny_ = 0;
  std::vector<std::uint8_t> reached_;
};

}  // namespace mg::game
