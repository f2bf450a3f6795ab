#pragma once
/// The one runner of the figure scripts (scripts/plots/plot.py, Debian's /usr/bin/python3 with
/// matplotlib), used by `plot`, `sweep --plot` and `reproduce`.
#include <string>

namespace mg {

/// Runs scripts/plots/plot.py with `args` (already shell-quoted) to draw `png`. Checks the
/// target first (`check_output_file`); plot.py's one-line error becomes ours: its exit 2 (an input
/// problem) an InputError, any other failure an Error, a PNG that was not written an Error.
void run_plot_script(const std::string& args, const std::string& png);

}  // namespace mg
