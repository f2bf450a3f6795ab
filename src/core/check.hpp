#pragma once
/// Validation helpers that throw `mg::InputError` with a message naming the quantity.
#include <cmath>
#include <string_view>

#include <fmt/format.h>

#include "core/error.hpp"

namespace mg {

/// Throws unless `value` is finite.
inline void require_finite(std::string_view name, double value) {
  if (!std::isfinite(value))
    throw InputError(fmt::format("{}: expected a finite number, got {}", name, value));
}

/// Throws unless `lo <= value <= hi` (and finite).
inline void require_in_range(std::string_view name, double value, double lo, double hi) {
  require_finite(name, value);
  if (value < lo || value > hi)
    throw InputError(fmt::format("{}: expected a value in [{}, {}], got {}", name, lo, hi, value));
}

/// Throws unless `value > 0` (and finite).
inline void require_positive(std::string_view name, double value) {
  require_finite(name, value);
  if (!(value > 0.0))
    throw InputError(fmt::format("{}: expected a positive number, got {}", name, value));
}

/// Throws unless `value >= 0` (and finite).
inline void require_non_negative(std::string_view name, double value) {
  require_finite(name, value);
  if (value < 0.0)
    throw InputError(fmt::format("{}: expected a non-negative number, got {}", name, value));
}

}  // namespace mg
