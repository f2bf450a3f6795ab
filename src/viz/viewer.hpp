#pragma once
/// `minigolf view`: a MuJoCo window on the live console session. The session (system::Session)
/// runs the module and its scheduler exactly as `minigolf console` does — the viewer is another
/// thin user of it: commands come from the terminal or a script on a command thread, and the
/// window's thread copies the pose under the session mutex (Session::inspect) and draws it in the
/// renderer's own mjData. A session observer keeps the ball's path after each hit.
///
/// Lockstep sessions are paced (`wait S` takes S seconds), so the hit can be watched; the bits are
/// the console's. Mouse: left drag rotates, right drag moves, scroll zooms (MuJoCo's `basic`
/// sample); Esc or closing the window ends the session.
#include <filesystem>
#include <string>

#include "control/module_config.hpp"

namespace mg::viz {

struct ViewerOptions {
  bool realtime = false;
  bool echo = false;
  std::string script;                ///< commands from this file (empty: standard input)
  std::filesystem::path screenshot;  ///< write the last frame here (PNG) when the session ends
  int width = 1280, height = 800;
  std::string camera = "overview";
};

/// Runs until `quit`, the end of the input, or the window is closed. Throws Error (one line) when
/// no window can be opened, InputError/IoError for bad configuration or script.
void run_viewer(const control::ModuleConfig& config, const ViewerOptions& options);

}  // namespace mg::viz
