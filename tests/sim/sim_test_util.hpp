#pragma once
// Tiny fields for the physics tests, written inline as YAML.
#include <string>

#include <fmt/format.h>

#include "field/field.hpp"

namespace mg::sim::testing {

/// A plane lane 4 m x 1.2 m with the given slopes, resistance and hole depth.
inline field::Field plane_field(double slope_x = 0.0, double slope_y = 0.0, double rho = 0.131,
                                double hole_depth = 0.06, double mu = 0.3) {
  return field::parse_field(fmt::format(R"(
format_version: 1
name: plane
lane: {{bounds: [-0.3, 3.7, -0.6, 0.6], cell_size: 0.05}}
tee: [0.0, 0.0]
hole: {{position: [3.4, 0.45], depth: {}}}
rolling_resistance: {}
sliding_friction: {}
surface:
  - {{type: plane, slope_x: {}, slope_y: {}}}
)",
                                        hole_depth, rho, mu, slope_x, slope_y),
                            "plane.yaml", ".");
}

}  // namespace mg::sim::testing
