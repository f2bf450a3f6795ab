// console: the minigolf module's user interface (thesis 4.2.2, RobotToolKit-like).
//
//   minigolf console [--config FILE] [--realtime] [--field F] [--mode simulator|normal]
//                    [--vision-sim] [--script FILE] [--echo] [--seed N]
//
// Reads commands from the terminal or a script on standard input (or --script FILE); `help`
// lists them. Bad commands are answered and never end the session.
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include <fmt/format.h>

#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "control/module_config.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "system/session.hpp"

namespace mg::cli {

void add_console_command(CLI::App& app) {
  struct Options {
    std::string config;
    std::string field;
    std::string mode;
    std::string script;
    bool realtime = false;
    bool vision_sim = false;
    bool echo = false;
    std::uint64_t seed = 1;
    std::string plant;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "console", "Run the arm and the minigolf module interactively (commands on standard input)");
  cmd->add_option("--config", o->config, "Module config YAML (docs/control.md: Config)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--field", o->field, "Shipped field name or path (overrides the config)");
  cmd->add_option("--mode", o->mode, "simulator | normal (overrides the config)");
  cmd->add_flag("--realtime", o->realtime,
                "Three threads paced at 500 Hz by the wall clock (default: lockstep, fast)");
  cmd->add_flag("--vision-sim", o->vision_sim,
                "Normal mode: publish the simulated ball and hole over loopback UDP to the feed");
  cmd->add_option("--script", o->script, "Read commands from this file instead of standard input")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--echo", o->echo, "Print every command before its answer");
  cmd->add_option("--seed", o->seed, "Seed of the vision simulator's noise")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option(
      "--plant", o->plant,
      "Plant file: the lane and the arm's friction and club as they really are (docs/reality.md)");
  cmd->callback([o] {
    control::ModuleConfig config =
        o->config.empty() ? control::ModuleConfig{} : control::load_module_config(o->config);
    if (!o->field.empty()) config.field = o->field;
    if (!o->mode.empty()) config.mode = control::parse_module_mode(o->mode);
    config.validate();
    std::istringstream script;  // read whole and bounded: a FIFO or /dev/zero is refused
    if (!o->script.empty()) script.str(read_text_file(o->script));
    system::SessionOptions options;
    options.realtime = o->realtime;
    options.vision_sim = o->vision_sim;
    options.echo = o->echo;
    options.seed = o->seed;
    options.plant = load_plant_arg(o->plant);
    // Ctrl-C (or kill, or a closed terminal) ends the session as `quit` does: the recording is
    // kept.
    defer_termination_signals();
    std::string unwritten;  // why the recording at the end was not written
    {
      system::Session session(config, options, std::cout);
      const bool interactive = o->script.empty() && isatty(STDIN_FILENO) != 0;
      session.run(o->script.empty() ? std::cin : script, interactive);
      if (!session.close()) unwritten = session.recording_error();
    }
    if (const int sig = termination_signal()) terminate_by_signal(sig);
    // The session answered and ended; the program does not end as a success.
    if (!unwritten.empty())
      throw IoError(fmt::format("console: the recording was not written: {}", unwritten));
  });
}

}  // namespace mg::cli
