// Driver for the default (gcc) build: replays a seed corpus through a harness, then N seeded
// random mutations of it (bit flips, byte edits, cut/duplicate, and tokens that broke parsers
// before: 1e999, -1, 2^64, NaN). A real coverage-guided run uses libFuzzer (MG_FUZZ=ON, clang;
// scripts/fuzz.sh). Exit 0 when every input ends in success or an mg::Error within the time limit.
//
// usage: fuzz_NAME CORPUS_DIR [RUNS] [SEED] [MAX_MS_PER_INPUT]
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

// The input being run, so a crash leaves it behind (written from the signal handler).
const std::string* g_current = nullptr;
char g_crash_path[512] = "fuzz-crash-input";

extern "C" void on_crash(int sig) {
  if (g_current) {
    const int fd = ::open(g_crash_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      [[maybe_unused]] auto n = ::write(fd, g_current->data(), g_current->size());
      ::close(fd);
    }
    const char msg[] = "fuzz: crash; input written to ";
    [[maybe_unused]] auto a = ::write(2, msg, sizeof msg - 1);
    [[maybe_unused]] auto b = ::write(2, g_crash_path, std::strlen(g_crash_path));
    [[maybe_unused]] auto c = ::write(2, "\n", 1);
  }
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

const char* const kTokens[] = {"1e999",
                               "-1e999",
                               "1e308",
                               "-1",
                               "0",
                               "nan",
                               "inf",
                               "18446744073709551615",
                               "9223372036854775808",
                               "1e200",
                               "-0",
                               "\n",
                               ",",
                               ":",
                               "{",
                               "}",
                               "[",
                               "]",
                               "\"",
                               "null",
                               "true",
                               "  ",
                               "\t",
                               "#",
                               "- ",
                               "0x10",
                               "1e-320",
                               ".",
                               "e",
                               "%"};

std::string mutate(std::string s, std::mt19937_64& rng) {
  auto pick = [&](std::size_t n) {
    return n == 0 ? std::size_t{0} : static_cast<std::size_t>(rng() % n);
  };
  const int edits = 1 + static_cast<int>(rng() % 4);
  for (int e = 0; e < edits; ++e) {
    switch (rng() % 7) {
      case 0:
        if (!s.empty()) s[pick(s.size())] ^= static_cast<char>(1u << (rng() % 8));
        break;
      case 1:
        if (!s.empty()) s[pick(s.size())] = static_cast<char>(rng() & 0xff);
        break;
      case 2:
        s.insert(pick(s.size() + 1), 1, static_cast<char>(rng() & 0xff));
        break;
      case 3:
        if (!s.empty()) {
          const std::size_t at = pick(s.size());
          s.erase(at, 1 + pick(std::min<std::size_t>(16, s.size() - at)));
        }
        break;
      case 4:
        if (!s.empty() && s.size() < 1 << 16) {
          const std::size_t at = pick(s.size());
          const std::size_t len = 1 + pick(std::min<std::size_t>(64, s.size() - at));
          s.insert(pick(s.size() + 1), s.substr(at, len));
        }
        break;
      case 5: {
        // Replace a run of digits (a number) by a token.
        const std::size_t at = pick(s.size() + 1);
        std::size_t end = at;
        while (end < s.size() && (std::isdigit(static_cast<unsigned char>(s[end])) ||
                                  s[end] == '.' || s[end] == 'e' || s[end] == '-'))
          ++end;
        s.replace(at, end - at, kTokens[pick(std::size(kTokens))]);
        break;
      }
      default:
        s.insert(pick(s.size() + 1), kTokens[pick(std::size(kTokens))]);
    }
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR [RUNS] [SEED] [MAX_MS_PER_INPUT]\n", argv[0]);
    return 2;
  }
  const long runs = argc > 2 ? std::atol(argv[2]) : 2000;
  const std::uint64_t seed = argc > 3 ? std::strtoull(argv[3], nullptr, 10) : 1;
  const double max_ms = argc > 4 ? std::atof(argv[4]) : 2000.0;
  std::snprintf(g_crash_path, sizeof g_crash_path, "%s-crash-input",
                std::filesystem::path(argv[0]).filename().string().c_str());
  for (int sig : {SIGSEGV, SIGABRT, SIGFPE, SIGBUS, SIGILL}) std::signal(sig, on_crash);

  std::vector<std::string> corpus;
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(argv[1]))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    std::ifstream in(f, std::ios::binary);
    corpus.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  if (corpus.empty()) {
    std::fprintf(stderr, "fuzz: no seed inputs in %s\n", argv[1]);
    return 2;
  }
  std::mt19937_64 rng(seed);
  double slowest = 0.0;
  auto run_one = [&](const std::string& input) {
    g_current = &input;
    const auto t0 = std::chrono::steady_clock::now();
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(input.data()), input.size());
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    slowest = std::max(slowest, ms);
    g_current = nullptr;
    if (ms > max_ms) {
      std::ofstream(g_crash_path, std::ios::binary) << input;
      std::fprintf(stderr, "fuzz: hang: one input took %.0f ms (limit %.0f); written to %s\n", ms,
                   max_ms, g_crash_path);
      std::exit(1);
    }
  };
  const auto t0 = std::chrono::steady_clock::now();
  for (const auto& c : corpus) run_one(c);
  for (long i = 0; i < runs; ++i)
    run_one(mutate(corpus[static_cast<std::size_t>(rng() % corpus.size())], rng));
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "fuzz: %zu seeds + %ld mutations, 0 crashes, 0 hangs, %.2f s (slowest input %.1f ms)\n",
      corpus.size(), runs, secs, slowest);
  return 0;
}
