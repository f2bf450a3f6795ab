#pragma once
/// The one runner of the figure scripts (scripts/plots/plot.py, Debian's /usr/bin/python3 with
/// matplotlib), used by `plot`, `sweep --plot` and `reproduce`.
#include <filesystem>
#include <string>

namespace mg {

/// Runs scripts/plots/plot.py with `args` (already shell-quoted) to draw `png`. Checks the
/// target first (`check_output_file`); plot.py's one-line error becomes ours: its exit 2 (an input
/// problem) an InputError, any other failure an Error, a PNG that was not written an Error.
void run_plot_script(const std::string& args, const std::string& png);

/// Where a figure's CSV files go: `keep` (made if missing, the files kept), or, when it is empty,
/// a temporary folder removed with this object.
class PlotDataDir {
 public:
  explicit PlotDataDir(const std::filesystem::path& keep);
  ~PlotDataDir();
  PlotDataDir(const PlotDataDir&) = delete;
  PlotDataDir& operator=(const PlotDataDir&) = delete;
  /// Writes `name` there (atomically) and returns its path.
  std::filesystem::path write(const std::string& name, const std::string& text) const;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  bool temporary_ = false;
};

}  // namespace mg
