#include "core/io.hpp"

#include <filesystem>

#include <gtest/gtest.h>

#include <pthread.h>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <thread>

#include "core/error.hpp"

namespace mg {
namespace {

TEST(Io, AtomicWriteReplacesAndReadsBack) {
  const auto path = std::filesystem::temp_directory_path() / "mg_io_test.txt";
  write_file_atomic(path, "first");
  write_file_atomic(path, "second");
  EXPECT_EQ(read_text_file(path), "second");
  std::filesystem::remove(path);
}

TEST(Io, MissingFileIsIoError) {
  EXPECT_THROW(read_text_file("/nonexistent/dir/file.txt"), IoError);
  EXPECT_THROW(write_file_atomic("/nonexistent/dir/file.txt", "x"), IoError);
}

// Found by fuzzing: the atomic writer replaced FIFOs, links and device nodes.
TEST(Io, AtomicWriteNeverReplacesWhatIsNotARegularFile) {
  const auto dir = std::filesystem::temp_directory_path() / ("mg_io_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto fifo = dir / "fifo", link = dir / "link", target = dir / "target";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  write_file_atomic(target, "kept\n");
  std::filesystem::create_symlink(target, link);
  EXPECT_THROW(write_file_atomic(fifo, "x"), IoError);
  EXPECT_THROW(write_file_atomic(link, "x"), IoError);
  EXPECT_THROW(write_file_atomic(dir, "x"), IoError);
  EXPECT_TRUE(std::filesystem::is_fifo(std::filesystem::symlink_status(fifo)));
  EXPECT_TRUE(std::filesystem::is_symlink(std::filesystem::symlink_status(link)));
  EXPECT_EQ(read_text_file(target), "kept\n");
  for (const auto& e : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
  std::filesystem::remove_all(dir);
}

// Input files are regular and bounded; FIFOs, devices and huge files are refused at
// once (a FIFO with no writer would block forever, /dev/zero would exhaust memory).
TEST(Io, InputsMustBeRegularBoundedFiles) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("mg_io_in_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto fifo = dir / "fifo", big = dir / "big", ok = dir / "ok";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  write_file_atomic(ok, "0123456789");
  write_file_atomic(big, std::string(2048, 'x'));
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_THROW(read_text_file(fifo), IoError);  // no writer: must not block
  EXPECT_THROW(read_text_file("/dev/zero"), IoError);
  EXPECT_THROW(read_text_file(dir), IoError);
  EXPECT_THROW(read_text_file(big, 1024), IoError);
  EXPECT_THROW(read_text_file(dir / std::string(5000, 'x')), IoError);  // name too long
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
  EXPECT_EQ(read_text_file("/dev/null"), "");  // the empty file, allowed
  EXPECT_EQ(read_text_file(ok, 10), "0123456789");
  EXPECT_EQ(check_input_file(ok), 10u);
  try {
    read_text_file("/dev/zero");
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("regular files"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

TEST(Io, OutputTargetsAreCheckedBeforeTheWork) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("mg_io_out_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto fifo = dir / "fifo", link = dir / "link";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  write_file_atomic(dir / "target", "kept");
  std::filesystem::create_symlink(dir / "target", link);
  EXPECT_NO_THROW(check_output_file(dir / "new.png"));
  EXPECT_NO_THROW(check_output_file(dir / "target"));
  for (const auto& bad :
       {fifo, link, dir, std::filesystem::path("/dev/full"), std::filesystem::path("/dev/null"),
        dir / "missing" / "x.png", dir / "target" / "x.png"})
    EXPECT_THROW(check_output_file(bad), IoError) << bad;
  EXPECT_THROW(ensure_output_dir(dir / "target"), IoError);
  EXPECT_THROW(ensure_output_dir(link), IoError);
  EXPECT_NO_THROW(ensure_output_dir(dir / "made" / "here"));
  EXPECT_TRUE(std::filesystem::is_directory(dir / "made" / "here"));
  EXPECT_EQ(read_text_file(dir / "target"), "kept");
  EXPECT_LE(shown_path(std::string(5000, 'y')).size(), 200u);
  std::filesystem::remove_all(dir);
}

// A write killed by SIGTERM leaves no temporary file (the handler removes it).
TEST(Io, AKilledWriteLeavesNoTemporaryFile) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("mg_io_kill_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    std::string big(std::size_t{1} << 29, 'x');  // 512 MiB: long enough to be killed while writing
    write_file_atomic(dir / "big.csv", big);
    ::_exit(0);
  }
  bool seen = false;
  for (int i = 0; i < 400 && !seen; ++i) {
    for (const auto& e : std::filesystem::directory_iterator(dir))
      seen = seen || e.path().extension() == ".tmp";
    if (!seen) ::usleep(10000);
  }
  ::kill(child, SIGTERM);
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(seen) << "the write finished before it could be killed";
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
  int left = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    ++left;
    ADD_FAILURE() << "left behind: " << e.path();
  }
  EXPECT_EQ(left, 0);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace mg

namespace mg {
namespace {

// Deferred termination (the console's recording on Ctrl-C): each case in its own process.
TEST(IoSignals, FirstSignalIsDeferredAndRecorded) {
  EXPECT_EXIT(
      {
        defer_termination_signals();
        std::raise(SIGHUP);
        std::_Exit(termination_signal() == SIGHUP ? 3 : 4);
      },
      ::testing::ExitedWithCode(3), "");
}

TEST(IoSignals, SecondSignalEndsTheProcess) {
  EXPECT_EXIT(
      {
        defer_termination_signals();
        std::raise(SIGTERM);
        std::raise(SIGTERM);
        std::_Exit(5);
      },
      ::testing::KilledBySignal(SIGTERM), "");
}

TEST(IoSignals, TerminateBySignalEndsByThatSignal) {
  EXPECT_EXIT(
      {
        defer_termination_signals();
        std::raise(SIGINT);
        terminate_by_signal(termination_signal());
      },
      ::testing::KilledBySignal(SIGINT), "");
}

TEST(IoSignals, ASignalOnAnotherThreadReachesTheInputThread) {
  // The input thread blocks in a read; the signal is sent to another thread: the read must be
  // interrupted (forwarded), so the console can quit and write its recording.
  EXPECT_EXIT(
      {
        int fds[2];
        if (::pipe(fds) != 0) std::_Exit(10);
        defer_termination_signals();
        std::thread other([] {
          std::this_thread::sleep_for(std::chrono::milliseconds(100));
          pthread_kill(pthread_self(), SIGINT);  // delivered to this thread, not the reader
        });
        char c;
        const ssize_t n = ::read(fds[0], &c, 1);  // nothing comes: only the signal ends it
        other.join();
        std::_Exit(n < 0 && errno == EINTR && termination_signal() == SIGINT ? 6 : 7);
      },
      ::testing::ExitedWithCode(6), "");
}

}  // namespace
}  // namespace mg
