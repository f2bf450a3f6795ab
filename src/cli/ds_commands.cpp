// ds fit | ds check | ds rollout (owned by the hitting-motion issue).
#include "cli/commands.hpp"

namespace mg::cli {

void add_ds_commands(CLI::App& /*app*/) {}

}  // namespace mg::cli
