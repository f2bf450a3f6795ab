// The `minigolf` command: parses, loads, calls the library, prints, maps errors to exit codes.
//
// Exit codes: 0 success (also --help); 2 bad input: a malformed command line (unknown, missing,
// repeated or empty option, bad number), an unknown name, a malformed or unusable file; 1 any
// other failure. Every error is one line on stderr: "minigolf: error: ...".
#include <cstdio>
#include <exception>
#include <string_view>

#include <fmt/format.h>

#include "cli/cli_util.hpp"
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
  mg::cli::add_camera_commands(app);
  mg::cli::add_vision_cam_command(app);
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
  mg::cli::refuse_empty_values(app);
  const auto fail = [](std::string_view message, int code) {
    fmt::print(stderr, "minigolf: error: {}\n", mg::cli::one_line(message));
    return code;
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are ParseErrors with exit code 0: print what was asked for.
    if (e.get_exit_code() == 0) return app.exit(e);
    // Everything else CLI11 refuses (unknown, missing or repeated options, a bad number, an empty
    // value) is bad input: one line, exit 2 (not CLI11's two lines and codes >= 100).
    return fail(e.what(), 2);
  } catch (const mg::InputError& e) {
    return fail(e.what(), 2);
  } catch (const mg::IoError& e) {
    return fail(e.what(), 2);
  } catch (const std::exception& e) {
    return fail(e.what(), 1);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  mg::sim::exit_on_mujoco_error();   // one line and exit 1, not MuJoCo's wait for Enter
  mg::sim::print_mujoco_warnings();  // on stderr, not stdout (a JSON answer) or a log file
  mg::system::ProcessGroup processes(argc, argv);  // an MPI run under mpirun / srun
  return processes.finish(run(argc, argv));
}
