// The `minigolf` command: parses, loads, calls the library, prints, maps errors to exit codes.
//
// Exit codes: 0 success; 2 bad input (unknown name, malformed file, bad number, also a number
// or file option that CLI11 rejects); 1 any other failure; CLI11's own codes (>= 100) for other
// malformed command lines (unknown option, missing argument).
#include <cstdio>
#include <exception>

#include <fmt/format.h>

#include "cli/commands.hpp"
#include "core/error.hpp"
#include "sim/mujoco_errors.hpp"
#include "system/distributed.hpp"

namespace {

int run(int argc, char** argv) {
  CLI::App app{"minigolf: a simulated Barrett WAM that learns to putt"};
  app.require_subcommand(1);
  mg::cli::add_field_commands(app);
  mg::cli::add_putt_command(app);
  mg::cli::add_learning_commands(app);
  mg::cli::add_ds_commands(app);
  mg::cli::add_vision_commands(app);
  mg::cli::add_study_commands(app);
  mg::cli::add_console_command(app);
  mg::cli::add_play_commands(app);
  mg::cli::add_selfteach_commands(app);
  mg::cli::add_viz_commands(app);
  mg::cli::add_plot_commands(app);
  mg::cli::add_plant_commands(app);
  mg::cli::add_adaptation_command(app);
  mg::cli::add_round_command(app);
  mg::cli::add_identify_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ConversionError& e) {  // a malformed number: bad input like any other
    fmt::print(stderr, "minigolf: error: {}\n", e.what());
    return 2;
  } catch (const CLI::ValidationError& e) {
    fmt::print(stderr, "minigolf: error: {}\n", e.what());
    return 2;
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const mg::InputError& e) {
    fmt::print(stderr, "minigolf: error: {}\n", e.what());
    return 2;
  } catch (const mg::IoError& e) {
    fmt::print(stderr, "minigolf: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "minigolf: error: {}\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  mg::sim::exit_on_mujoco_error();  // one line and exit 1, not MuJoCo's wait for Enter
  mg::system::ProcessGroup processes(argc, argv);  // an MPI run under mpirun / srun
  return processes.finish(run(argc, argv));
}
