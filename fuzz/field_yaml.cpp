// Field YAML (src/field): lane, hole, surface terms.
#include <filesystem>
#include <string>

#include "field/field.hpp"
#include "harness.hpp"

MG_FUZZ_TARGET({
  const auto f =
      mg::field::parse_field(mg::fuzz::as_text(data, size), "fuzz.yaml",
                             std::filesystem::temp_directory_path() / "mg_fuzz_no_such_dir");
  (void)f.height(0.0, 0.0);
})
