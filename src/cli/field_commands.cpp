#include "cli/commands.hpp"
namespace mg::cli {
void add_field_commands(CLI::App& /*app*/) {}
}  // namespace mg::cli
