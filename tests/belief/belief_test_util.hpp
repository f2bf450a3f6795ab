#pragma once
// Helpers shared by the belief tests.
#include <cmath>

#include "core/rng.hpp"

namespace mg::belief::test {

/// A Gaussian draw (Box-Muller on 53-bit uniforms: the same on every platform).
inline double gaussian(Rng& rng) {
  const double u1 = (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53;
  const double u2 = static_cast<double>(rng() >> 11) * 0x1.0p-53;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * 3.14159265358979323846 * u2);
}

}  // namespace mg::belief::test
