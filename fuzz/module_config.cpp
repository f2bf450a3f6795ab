// Module config YAML (control/module_config).
#include <string>

#include "control/module_config.hpp"
#include "harness.hpp"

MG_FUZZ_TARGET({
  (void)mg::control::parse_module_config(std::string(mg::fuzz::as_text(data, size)), "fuzz.yaml");
})
