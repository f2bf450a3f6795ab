// End-to-end tests of `minigolf ds ...`: run the built binary, check exit codes and JSON keys.
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/io.hpp"
#include "ds/demonstrations.hpp"

namespace {

namespace fs = std::filesystem;

struct CliRun {
  int code = -1;
  std::string out;
  std::string err;
};

CliRun run(const std::string& args) {
  static int counter = 0;
  const fs::path err_file =
      fs::temp_directory_path() /
      ("mg_ds_cli_err_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  const std::string cmd = std::string(MINIGOLF_BINARY) + " " + args + " 2>" + err_file.string();
  CliRun r;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return r;
  char buf[4096];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int status = ::pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream e(err_file);
  r.err.assign(std::istreambuf_iterator<char>(e), {});
  fs::remove(err_file);
  return r;
}

class DsCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("mg_ds_cli_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static fs::path dir_;
};
fs::path DsCli::dir_;

TEST_F(DsCli, DemosFitCheckRolloutEndToEnd) {
  const fs::path demos = dir_ / "demos.csv", model = dir_ / "model.json", traj = dir_ / "traj.csv";
  CliRun r = run("ds demos -o " + demos.string() + " --seed 3 --count 4");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(mg::ds::read_demonstrations(demos).size(), 4u);

  r = run("ds fit " + demos.string() + " -o " + model.string() +
          " --gaussians 2 --max-evaluations 150 --seed 5 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  for (const char* key :
       {"max_eigenvalue", "default_speed", "fit_seconds", "velocity_rmse", "mean_path_distance"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_LE(j["max_eigenvalue"].get<double>(), -1e-4);

  r = run("ds check " + model.string() + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["ok"].get<bool>());
  EXPECT_LE(j["max_eigenvalue"].get<double>(), -1e-4);

  r = run("ds rollout " + model.string() +
          " --start=-0.3,0.02,0.12 --angle 0.3 --speed 1.2 --modulator sine -o " + traj.string() +
          " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["reached"].get<bool>());
  EXPECT_LT(j["position_error"].get<double>(), 0.005);
  ASSERT_EQ(j["velocity"].size(), 3u);
  const double vx = j["velocity"][0], vy = j["velocity"][1], vz = j["velocity"][2];
  EXPECT_NEAR(std::sqrt(vx * vx + vy * vy + vz * vz), 1.2, 0.012);
  EXPECT_NEAR(std::atan2(vy, vx), 0.3, 1.0 * M_PI / 180.0);
  EXPECT_GT(j["duration"].get<double>(), 0.0);
  const auto table = mg::read_csv(traj);
  EXPECT_GT(table.num_rows(), 10u);
  EXPECT_NO_THROW(table.column_index("vz"));
}

TEST_F(DsCli, ShippedModelChecksAndRollsOut) {
  CliRun r = run("ds check default --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_LE(nlohmann::json::parse(r.out)["max_eigenvalue"].get<double>(), -1e-4);
  r = run("ds rollout " + (mg::data_dir() / "models" / "hitting-default.json").string() +
          " --start=-0.4,0.05,0.1 --angle=-0.4 --speed 2 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"reached", "position_error", "velocity", "duration"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_LT(j["angle_error"].get<double>(), 1.0 * M_PI / 180.0);
  // Human-readable output too.
  r = run("ds rollout default");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("reached the ball"), std::string::npos);
}

TEST_F(DsCli, MseObjectiveFits) {
  const fs::path demos = dir_ / "demos_mse.csv", model = dir_ / "model_mse.json";
  ASSERT_EQ(run("ds demos -o " + demos.string() + " --count 3").code, 0);
  const CliRun r = run("ds fit " + demos.string() + " -o " + model.string() +
                       " --gaussians 2 --objective mse --max-evaluations 150 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(run("ds check " + model.string()).code, 0);
}

TEST_F(DsCli, BadInputIsAOneLineErrorWithExitCode2) {
  const fs::path one = dir_ / "one.csv", broken = dir_ / "broken.json", apart = dir_ / "apart.csv";
  std::ofstream(one) << "demo,t,x,y,z,vx,vy,vz\n0,0,-0.3,0,0.1,1,0,0\n";
  std::ofstream(broken) << "{\"format_version\": 1";
  std::ofstream(apart) << "demo,t,x,y,z,vx,vy,vz\n0,0,-0.3,0,0.1,1,0,0\n0,0.1,-0.2,0,0.1,1,0,0\n0,"
                          "0.2,0,0,0.02,1,0,0\n"
                          "1,0,-0.3,0,0.1,1,0,0\n1,0.1,-0.2,0,0.1,1,0,0\n1,0.2,0,0.5,0.02,1,0,0\n";
  for (const std::string& args : std::vector<std::string>{
           "ds fit " + (dir_ / "missing.csv").string() + " -o " + (dir_ / "x.json").string(),
           "ds fit " + one.string() + " -o " + (dir_ / "x.json").string(),
           "ds fit " + apart.string() + " -o " + (dir_ / "x.json").string(),
           "ds fit " + one.string() + " -o " + (dir_ / "x.json").string() + " --objective bogus",
           "ds check " + broken.string(), "ds rollout " + broken.string(),
           "ds rollout default --start 1,2", "ds rollout default --modulator cubic",
           "ds rollout default --speed=-3"}) {
    const CliRun r = run(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("minigolf: error:"), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir_ / "x.json"));
}

TEST_F(DsCli, UnstableModelFailsTheCheck) {
  auto j =
      nlohmann::json::parse(mg::read_text_file(mg::data_dir() / "models" / "hitting-default.json"));
  auto& cov = j["seds"]["gmm"]["covariances"][0];
  auto& mean = j["seds"]["gmm"]["means"][0];
  for (int r = 0; r < 3; ++r) {
    mean[3 + r] = mean[r];
    for (int c = 0; c < 3; ++c) {
      cov[3 + r][c] = cov[r][c];
      cov[r][3 + c] = cov[r][c];
      cov[3 + r][3 + c] = cov[r][c].get<double>() + (r == c ? 1.0 : 0.0);
    }
  }
  const fs::path bad = dir_ / "unstable.json";
  std::ofstream(bad) << j.dump();
  const CliRun r = run("ds check " + bad.string() + " --json");
  EXPECT_NE(r.code, 0);
  const auto out = nlohmann::json::parse(r.out);
  EXPECT_FALSE(out["ok"].get<bool>());
  EXPECT_GT(out["max_eigenvalue"].get<double>(), 0.0);
  EXPECT_NE(run("ds rollout " + bad.string()).code, 0);
}

}  // namespace
