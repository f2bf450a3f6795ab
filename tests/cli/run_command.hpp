#pragma once
// Runs the minigolf binary with arguments and captures exit code, stdout and stderr.
#include <sys/wait.h>
#include <unistd.h>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace mg::cli::testing {

struct CommandResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

/// Runs the shell command line `command` (stderr captured apart).
inline CommandResult run_command_line(const std::string& command) {
  static int counter = 0;
  const auto err_path =
      std::filesystem::temp_directory_path() /
      ("mg_cli_err_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  const std::string cmd = command + " 2>" + err_path.string();
  CommandResult r;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream err(err_path);
  std::stringstream ss;
  ss << err.rdbuf();
  r.err = ss.str();
  std::filesystem::remove(err_path);
  return r;
}

inline CommandResult run_minigolf(const std::string& args) {
  return run_command_line(std::string(MINIGOLF_BINARY) + " " + args);
}

/// Number of lines in `s` (a trailing newline does not start a new line).
inline int count_lines(const std::string& s) {
  int lines = 0;
  for (char c : s) lines += c == '\n';
  return lines + (!s.empty() && s.back() != '\n');
}

}  // namespace mg::cli::testing
