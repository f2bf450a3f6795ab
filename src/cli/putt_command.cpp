#include "cli/commands.hpp"
namespace mg::cli {
void add_putt_command(CLI::App& /*app*/) {}
}  // namespace mg::cli
