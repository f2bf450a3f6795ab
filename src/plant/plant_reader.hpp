#pragma once
/// The plant file's sections as one reader (internal to the plant and belief readers: a belief
/// file's `std` has the same sections).
#include "field/map_reader.hpp"
#include "plant/plant.hpp"

namespace mg::plant {

/// Reads the `field`, `arm` and `perception` sections present under `r` into `p` (keys absent
/// keep p's values; unknown keys in a section are InputErrors naming it). Does not finish `r`.
void read_plant_sections(field::MapReader& r, Plant& p);

}  // namespace mg::plant
