#pragma once
/// The resolved field as JSON (for `minigolf field show --json`).
#include <nlohmann/json.hpp>

#include "field/field.hpp"

namespace mg::field {

nlohmann::json field_to_json(const Field& field);

}  // namespace mg::field
