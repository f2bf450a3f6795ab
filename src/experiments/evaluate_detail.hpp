#pragma once
/// What evaluate.cpp and evaluate_learning.cpp share (internal to src/experiments).
#include <string_view>
#include <vector>

#include "field/situations.hpp"
#include "learning/learner.hpp"
#include "system/system.hpp"

namespace mg::experiments::detail {

/// The column of output `name` in `m`, -1 if it has none.
int output_index(const learning::Model& m, std::string_view name);

/// The plant's real holes of every test situation, checked before the first putt (not found
/// after others ran). Throws InputError.
void check_plant_holes(const system::System& system,
                       const std::vector<field::Situation>& situations);

}  // namespace mg::experiments::detail
