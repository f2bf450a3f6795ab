// train | predict | validate (owned by the learners issue).
#include "cli/commands.hpp"

namespace mg::cli {

void add_learning_commands(CLI::App& /*app*/) {}

}  // namespace mg::cli
