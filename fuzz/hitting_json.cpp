// Hitting model JSON (core/json_io + ds/hitting_model).
#include "core/json_io.hpp"
#include "ds/hitting_model.hpp"
#include "harness.hpp"

MG_FUZZ_TARGET({
  const auto m = mg::ds::hitting_model_from_json(
      mg::parse_json(std::string(mg::fuzz::as_text(data, size)), "fuzz.json"), "fuzz.json");
  (void)m.default_speed();
})
