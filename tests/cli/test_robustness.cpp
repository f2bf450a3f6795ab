// Issue 13, part 3 "silent wrong results": each reproducer gives a one-line error that names the
// problem and exit code 2 (never a NaN printed with exit 0, a model written that is then
// rejected, a wrapped-around seed or an ignored argument).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "run_command.hpp"

namespace mg::cli::testing {
namespace {

namespace fs = std::filesystem;

class Robustness : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("mg_robust_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // A small smooth data set: angle = atan2(y, x), speed = sqrt(d).
    std::string csv = "xi_x,xi_y,angle,speed\n";
    for (int i = 0; i < 20; ++i) {
      const double x = 0.5 + 0.1 * i;
      const double y = -0.6 + 0.06 * i * (i % 3);
      csv += std::to_string(x) + "," + std::to_string(y) + "," + std::to_string(std::atan2(y, x)) + "," +
             std::to_string(std::sqrt(std::hypot(x, y))) + "\n";
    }
    train_ = write("train.csv", csv);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) const {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  /// Exit code 2, exactly one line on stderr, and it contains every one of `needles`.
  static void expect_input_error(const CommandResult& r, const std::string& what,
                                 std::initializer_list<std::string> needles) {
    EXPECT_EQ(r.exit_code, 2) << what << "\n" << r.out << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << what << "\n" << r.err;
    for (const auto& n : needles) EXPECT_NE(r.err.find(n), std::string::npos) << what << ": '" << n << "' in\n" << r.err;
  }
  fs::path dir_;
  std::string train_;
};

TEST_F(Robustness, RegCovarZeroIsRefusedBeforeAModelIsWritten) {
  const std::string model = path("m.json");
  const CommandResult r = run_minigolf("train --method gmr --gaussians 2 --reg-covar 0 " + train_ + " -o " + model);
  expect_input_error(r, "--reg-covar 0", {"reg_covar"});
  EXPECT_FALSE(fs::exists(model));
}

TEST_F(Robustness, GprModelWithAHugeTargetIsRejectedNamingTheFile) {
  const std::string model = path("gpr.json");
  ASSERT_EQ(run_minigolf("train --method gpr --restarts 1 " + train_ + " -o " + model).exit_code, 0);
  nlohmann::json j = nlohmann::json::parse(std::ifstream(model));
  j["gps"][0]["training_targets"][0] = 1e200;
  std::ofstream(model) << j.dump();
  const CommandResult r = run_minigolf("predict " + model + " " + train_);
  expect_input_error(r, "target 1e200", {model, "1e+200"});
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
}

TEST_F(Robustness, JointGmrQueryAtTheEndOfTheDoubleRangeIsRejectedNamingTheFile) {
  const std::string model = path("joint.json");
  ASSERT_EQ(run_minigolf("train --method joint-gmr --gaussians 2 " + train_ + " -o " + model).exit_code, 0);
  const std::string queries = write("q.csv", "xi_x,xi_y\n1e308,-1e308\n");
  const CommandResult r = run_minigolf("predict " + model + " " + queries);
  expect_input_error(r, "query 1e308", {queries, "xi_x"});
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
}

TEST_F(Robustness, NegativeSeedIsRefusedNotWrappedAround) {
  for (const std::string& args : {"train --method gmr " + train_ + " -o " + path("m.json") + " --seed -1",
                                  "ds demos -o " + path("d.csv") + " --seed -1",
                                  std::string("console --seed -1 --script /dev/null")}) {
    const CommandResult r = run_minigolf(args);
    expect_input_error(r, args, {"--seed"});
  }
}

TEST_F(Robustness, DirectoryAsConfigOrScriptIsRefused) {
  const std::string d = dir_.string();
  for (const std::string& args : {"console --config " + d + " --script /dev/null", "console --script " + d,
                                  "putt --angle 0 --speed 1 --config " + d,
                                  "putt --ball-only --angle 0 --speed 1 --config " + d}) {
    const CommandResult r = run_minigolf(args + " < /dev/null");
    expect_input_error(r, args, {d});
  }
}

TEST_F(Robustness, PuttWithAConfigWorksOutsideTheRepositoryRoot) {
  // The config leaves hitting_model at its default (a path relative to the repository root).
  const std::string config = write("module.yaml", "field: flat\n");
  const CommandResult r = run_minigolf("putt --ball-only --angle 0 --speed 1 --json --config " + config);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string cmd = "cd " + dir_.string() + " && " + std::string(MINIGOLF_BINARY) +
                          " putt --angle 0 --speed 1 --json --config " + config + " > /dev/null 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
}

TEST_F(Robustness, OverflowingNumberInALearnerModelNamesTheFile) {
  const std::string model = path("gmr.json");
  ASSERT_EQ(run_minigolf("train --method gmr --gaussians 2 " + train_ + " -o " + model).exit_code, 0);
  std::string text;
  {
    std::ifstream in(model);
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  const auto at = text.find("\"seed\": 1");
  ASSERT_NE(at, std::string::npos) << text.substr(0, 400);
  text.replace(at, 9, "\"seed\": 1e999");
  std::ofstream(model) << text;
  const CommandResult r = run_minigolf("predict " + model + " " + train_);
  expect_input_error(r, "1e999", {model, "out of range"});
}

TEST_F(Robustness, CrashReproducersOfIssue13AreInputErrors) {
  // Were SIGSEGV (exit 139): k-means read an empty result when every restart overflowed.
  const std::string s = write("s.csv", "xi_x,angle\n1e200,0\n2,0.1\n");
  for (const char* method : {"gmr", "joint-gmr"}) {
    const CommandResult r =
        run_minigolf(std::string("train --method ") + method + " --inputs xi_x --outputs angle " + s + " -o " + path("m.json"));
    expect_input_error(r, method, {s});
  }
  const std::string demos = write("d.csv", "demo,t,x,y,z,vx,vy,vz\n0,0,-0.3,0,0.02135,0,0,0\n0,0.1,-0.2,0,0.02135,1e200,0,0\n"
                                           "0,0.2,-0.1,0,0.02135,1,0,0\n0,0.3,0,0,0.02135,1.5,0,0\n");
  const CommandResult r = run_minigolf("ds fit " + demos + " --gaussians 1 -o " + path("h.json"));
  expect_input_error(r, "ds fit 1e200", {demos});
}

TEST_F(Robustness, MalformedCommandLineNumbersAreInputErrors) {
  for (const std::string& args : {"train " + train_ + " -o " + path("m.json") + " --gaussians two",
                                  "ds fit " + train_ + " -o " + path("h.json") + " --gaussians 50"}) {
    const CommandResult r = run_minigolf(args);
    expect_input_error(r, args, {"--gaussians"});
  }
}

}  // namespace
}  // namespace mg::cli::testing
