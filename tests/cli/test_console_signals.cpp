// `minigolf console` keeps its recording when interrupted: SIGINT (Ctrl-C), SIGTERM or SIGHUP
// during `record on FILE` ends the session as `quit` does (the recording written, then the
// process ends by the signal, as a shell expects) - in a long `wait`, while blocked reading the
// terminal, and with the real-time threads running.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>

extern char** environ;

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

std::string read_all(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

/// Runs `command` through /bin/sh (which execs the binary, so the pid is the console's).
pid_t spawn_shell(const std::string& command) {
  pid_t pid = -1;
  const char* argv[] = {"/bin/sh", "-c", command.c_str(), nullptr};
  if (posix_spawn(&pid, "/bin/sh", nullptr, nullptr, const_cast<char**>(argv), environ) != 0)
    return -1;
  return pid;
}

/// Polls until `text` appears in `file` or `timeout` passes.
bool wait_for_text(const fs::path& file, const std::string& text, std::chrono::seconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (read_all(file).find(text) != std::string::npos) return true;
    std::this_thread::sleep_for(20ms);
  }
  return false;
}

/// Waits for `pid` up to `timeout`; kills it (SIGKILL) if it does not end. Returns the status.
int wait_or_kill(pid_t pid, std::chrono::seconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  int status = 0;
  while (std::chrono::steady_clock::now() < end) {
    if (waitpid(pid, &status, WNOHANG) == pid) return status;
    std::this_thread::sleep_for(20ms);
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  ADD_FAILURE() << "the console did not end within the timeout after the signal";
  return status;
}

struct Dir {
  fs::path path;
  explicit Dir(const std::string& name)
      : path(fs::temp_directory_path() / (name + "_" + std::to_string(getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~Dir() { fs::remove_all(path); }
};

/// The recording after the signal: a complete CSV with the header and samples, no temp file left.
void expect_recording_kept(const Dir& dir, const fs::path& rec, const std::string& out, int sig,
                           int status, const char* name) {
  EXPECT_TRUE(WIFSIGNALED(status)) << out;
  if (WIFSIGNALED(status)) {
    EXPECT_EQ(WTERMSIG(status), sig);
  }
  ASSERT_TRUE(fs::exists(rec)) << out;
  const std::string csv = read_all(rec);
  EXPECT_EQ(csv.rfind("t,state,q1", 0), 0u) << csv.substr(0, 80);
  EXPECT_GE(count_lines(csv), 11) << "expected the header and >= 10 samples";
  EXPECT_EQ(csv.back(), '\n');
  EXPECT_NE(out.find("recording written"), std::string::npos) << out;
  EXPECT_NE(out.find(std::string("interrupted by ") + name), std::string::npos) << out;
  for (const auto& e : fs::directory_iterator(dir.path))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
}

class ConsoleSignal : public ::testing::TestWithParam<std::pair<int, const char*>> {};

TEST_P(ConsoleSignal, KeepsTheRecordingDuringALongWait) {
  const auto [sig, name] = GetParam();
  Dir dir(std::string("mg_sig_wait_") + name);
  const fs::path rec = dir.path / "rec.csv", out = dir.path / "out.txt",
                 script = dir.path / "s.txt";
  std::ofstream(script) << "record on " << rec.string() << "\nwait 3600\nquit\n";
  const pid_t pid = spawn_shell(std::string("exec ") + MINIGOLF_BINARY + " console --script " +
                                script.string() + " > " + out.string() + " 2>&1");
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(wait_for_text(out, "recording to", 60s)) << read_all(out);
  std::this_thread::sleep_for(300ms);  // some simulated seconds go by (lockstep: ~30x real time)
  kill(pid, sig);
  const int status = wait_or_kill(pid, 60s);
  expect_recording_kept(dir, rec, read_all(out), sig, status, name);
}

TEST_P(ConsoleSignal, KeepsTheRecordingWhileWaitingForInput) {
  // Standard input stays open with nothing to read: the console is blocked in the read.
  const auto [sig, name] = GetParam();
  Dir dir(std::string("mg_sig_input_") + name);
  const fs::path rec = dir.path / "rec.csv", out = dir.path / "out.txt", fifo = dir.path / "in";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const pid_t pid = spawn_shell(std::string("exec ") + MINIGOLF_BINARY + " console < " +
                                fifo.string() + " > " + out.string() + " 2>&1");
  ASSERT_GT(pid, 0);
  const int w = open(fifo.c_str(), O_WRONLY);  // blocks until the console opens its end
  ASSERT_GE(w, 0);
  const std::string lines = "record on " + rec.string() + "\nwait 1\nstatus\n";
  ASSERT_EQ(write(w, lines.data(), lines.size()), static_cast<ssize_t>(lines.size()));
  ASSERT_TRUE(wait_for_text(out, "recording:", 60s)) << read_all(out);  // the status answer
  std::this_thread::sleep_for(100ms);
  kill(pid, sig);
  const int status = wait_or_kill(pid, 60s);
  close(w);
  expect_recording_kept(dir, rec, read_all(out), sig, status, name);
}

INSTANTIATE_TEST_SUITE_P(Signals, ConsoleSignal,
                         ::testing::Values(std::make_pair(SIGINT, "SIGINT"),
                                           std::make_pair(SIGTERM, "SIGTERM"),
                                           std::make_pair(SIGHUP, "SIGHUP")),
                         [](const auto& info) { return std::string(info.param.second); });

TEST(ConsoleSignalRealtime, KeepsTheRecordingWithTheThreadsRunning) {
  // Three threads: the signal may land on the core or I/O thread; it must still end the wait.
  Dir dir("mg_sig_rt");
  const fs::path rec = dir.path / "rec.csv", out = dir.path / "out.txt",
                 script = dir.path / "s.txt";
  std::ofstream(script) << "record on " << rec.string() << "\nwait 1000\nquit\n";
  const pid_t pid =
      spawn_shell(std::string("exec ") + MINIGOLF_BINARY + " console --realtime --script " +
                  script.string() + " > " + out.string() + " 2>&1");
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(wait_for_text(out, "recording to", 60s)) << read_all(out);
  std::this_thread::sleep_for(500ms);  // 50 robot-update samples
  kill(pid, SIGINT);
  const int status = wait_or_kill(pid, 30s);
  expect_recording_kept(dir, rec, read_all(out), SIGINT, status, "SIGINT");
}

// When the recording could not be written at the end (its folder gone), the
// session said so but the console exited 0. Now the answer stays and the exit is 2 with one line.
TEST(ConsoleRecording, ARecordingNotWrittenAtTheEndIsAnError) {
  Dir dir("mg_rec_lost");
  const fs::path sub = dir.path / "sub", rec = sub / "rec.csv", out = dir.path / "out.txt",
                 err = dir.path / "err.txt", fifo = dir.path / "in";
  fs::create_directories(sub);
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const pid_t pid = spawn_shell(std::string("exec ") + MINIGOLF_BINARY + " console < " +
                                fifo.string() + " > " + out.string() + " 2> " + err.string());
  ASSERT_GT(pid, 0);
  const int w = open(fifo.c_str(), O_WRONLY);
  ASSERT_GE(w, 0);
  const std::string lines = "record on " + rec.string() + "\nwait 0.1\nstatus\n";
  ASSERT_EQ(write(w, lines.data(), lines.size()), static_cast<ssize_t>(lines.size()));
  ASSERT_TRUE(wait_for_text(out, "recording:", 60s)) << read_all(out);
  fs::remove_all(sub);
  close(w);  // end of input: quit, and the recording is due
  const int status = wait_or_kill(pid, 60s);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2) << read_all(out) << read_all(err);
  EXPECT_NE(read_all(out).find("error: "), std::string::npos) << read_all(out);
  const std::string e = read_all(err);
  EXPECT_EQ(e.rfind("minigolf: error: console: the recording was not written: ", 0), 0u) << e;
  EXPECT_EQ(count_lines(e), 1) << e;
}

}  // namespace
