// Plant YAML (src/plant): the world as it really is.
#include <string>

#include "field/field.hpp"
#include "harness.hpp"
#include "plant/plant.hpp"

MG_FUZZ_TARGET({
  const auto p = mg::plant::parse_plant(mg::fuzz::as_text(data, size), "fuzz.yaml");
  (void)mg::plant::plant_to_yaml(p);
  static const mg::field::Field flat = mg::field::load_field("flat");
  (void)mg::plant::true_field(flat, p).height(1.0, 0.1);
})
