#pragma once
/// Registration of the `minigolf` subcommands; one function per command group, one file each.
#include <CLI/CLI.hpp>

namespace mg::cli {

void add_field_commands(CLI::App& app);      // field list | field show
void add_putt_command(CLI::App& app);        // putt
void add_learning_commands(CLI::App& app);   // train | predict | validate
void add_ds_commands(CLI::App& app);         // ds fit | ds check | ds rollout
void add_vision_commands(CLI::App& app);     // vision-sim
void add_study_commands(CLI::App& app);      // study launch-error
void add_console_command(CLI::App& app);     // console
void add_play_commands(CLI::App& app);       // sweep | collect | evaluate | reproduce
void add_selfteach_commands(CLI::App& app);  // self-teach | curves
void add_viz_commands(CLI::App& app);        // view | render
void add_plot_commands(CLI::App& app);       // plot ds | strength | field | model
void add_plant_commands(CLI::App& app);      // plant random | show
void add_adaptation_command(CLI::App& app);  // study adaptation (after add_study_commands)
void add_round_command(CLI::App& app);       // play
void add_identify_command(CLI::App& app);    // identify
void add_camera_commands(CLI::App& app);     // vision calibrate | vision measure
void add_vision_cam_command(CLI::App& app);  // vision-cam

}  // namespace mg::cli
