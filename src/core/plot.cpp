#include "core/plot.hpp"

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/io.hpp"

namespace mg {

void run_plot_script(const std::string& args, const std::string& png) {
  namespace fs = std::filesystem;
  check_output_file(png);
  const fs::path script = data_dir().parent_path() / "scripts" / "plots" / "plot.py";
  const std::string command =
      "/usr/bin/python3 " + shell_quote(script.string()) + " " + args + " 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) throw Error("plot: cannot run /usr/bin/python3");
  std::string text;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe)) text += buffer;
  const int status = ::pclose(pipe);
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  if (const auto nl = text.rfind('\n'); nl != std::string::npos) text = text.substr(nl + 1);
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (code == 2) throw InputError(text);
  if (code != 0)
    throw Error(fmt::format("plot: {} failed (exit {}): {}", script.string(), code, text));
  std::error_code ec;
  if (!fs::is_regular_file(png, ec) || fs::file_size(png, ec) == 0)
    throw Error(fmt::format("plot: {} was not written", shown_path(png)));
}

PlotDataDir::PlotDataDir(const std::filesystem::path& keep) {
  if (!keep.empty()) {
    ensure_output_dir(keep);
    path_ = keep;
    return;
  }
  std::string tmpl = (std::filesystem::temp_directory_path() / "minigolf-plot-XXXXXX").string();
  if (!::mkdtemp(tmpl.data())) throw IoError("plot: cannot make a temporary folder");
  path_ = tmpl;
  temporary_ = true;
}

PlotDataDir::~PlotDataDir() {
  std::error_code ec;
  if (temporary_) std::filesystem::remove_all(path_, ec);
}

std::filesystem::path PlotDataDir::write(const std::string& name, const std::string& text) const {
  write_file_atomic(path_ / name, text);
  return path_ / name;
}

}  // namespace mg
