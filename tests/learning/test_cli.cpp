// End-to-end tests of `minigolf train | predict | validate`: run the built binary, check exit
// codes and output.
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/csv.hpp"
#include "core/io.hpp"
#include "learning_test_util.hpp"

namespace mg::learning {
namespace {

struct RunResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

RunResult run(const testing::ScratchDir& dir, const std::string& args) {
  const auto out_path = dir / "stdout.txt";
  const auto err_path = dir / "stderr.txt";
  const std::string cmd = fmt::format("'{}' {} > '{}' 2> '{}'", MINIGOLF_BINARY, args,
                                      out_path.string(), err_path.string());
  const int status = std::system(cmd.c_str());
  RunResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = mg::read_text_file(out_path);
  r.err = mg::read_text_file(err_path);
  return r;
}

class LearningCli : public ::testing::Test {
 protected:
  void SetUp() override {
    train_ = (dir_ / "train.csv").string();
    val_ = (dir_ / "val.csv").string();
    testing::write_dataset(testing::flat_field(20, 31), train_);
    testing::write_dataset(testing::flat_field(60, 32, 0.0), val_);
  }
  testing::ScratchDir dir_;
  std::string train_, val_;
};

TEST_F(LearningCli, TrainGprReportsHyperparametersAndWritesAVersionedModel) {
  const std::string model = (dir_ / "gpr.json").string();
  const RunResult r =
      run(dir_, fmt::format("train --method gpr '{}' -o '{}' --seed 3 --json", train_, model));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* out : {"angle", "speed"}) {
    ASSERT_TRUE(j.contains(out)) << r.out;
    EXPECT_EQ(j[out]["length_scales"].size(), 2u);
    EXPECT_GT(j[out]["signal_std"].get<double>(), 0.0);
    EXPECT_GT(j[out]["noise_std"].get<double>(), 0.0);
    EXPECT_TRUE(std::isfinite(j[out]["log_marginal_likelihood"].get<double>()));
  }
  const auto file = nlohmann::json::parse(mg::read_text_file(model));
  EXPECT_EQ(file["format_version"], 1);
  // Same seed, same file.
  const std::string model2 = (dir_ / "gpr2.json").string();
  ASSERT_EQ(
      run(dir_, fmt::format("train --method gpr '{}' -o '{}' --seed 3", train_, model2)).exit_code,
      0);
  EXPECT_EQ(mg::read_text_file(model), mg::read_text_file(model2));
}

TEST_F(LearningCli, TrainGmrReportsGaussiansLikelihoodAndBic) {
  for (const char* method : {"gmr", "joint-gmr"}) {
    const std::string model = (dir_ / "m.json").string();
    const RunResult r = run(dir_, fmt::format("train --method {} '{}' -o '{}' --gaussians 2 --json",
                                              method, train_, model));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["angle"]["n_gaussians"], 2) << method;
    EXPECT_TRUE(std::isfinite(j["speed"]["log_likelihood"].get<double>()));
    EXPECT_GT(j["speed"]["bic"].get<double>(), -2.0 * j["speed"]["log_likelihood"].get<double>());
  }
}

TEST_F(LearningCli, PredictPrintsQueryColumnsThenMeanAndStdPerOutput) {
  const std::string model = (dir_ / "m.json").string();
  ASSERT_EQ(
      run(dir_, fmt::format("train --method joint-gmr '{}' -o '{}' --gaussians 2", train_, model))
          .exit_code,
      0);
  const RunResult r = run(dir_, fmt::format("predict '{}' '{}'", model, val_));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const CsvTable t = parse_csv(r.out, "stdout");
  const std::vector<std::string> header{"xi_x",       "xi_y",      "angle",      "speed",
                                        "angle_mean", "angle_std", "speed_mean", "speed_std"};
  EXPECT_EQ(t.header, header);
  ASSERT_EQ(t.num_rows(), 60u);
  double mse = 0.0;
  for (const auto& row : t.rows) {
    mse += (row[4] - row[2]) * (row[4] - row[2]) / 60.0;
    EXPECT_GT(row[5], 0.0);
    EXPECT_GT(row[7], 0.0);
  }
  EXPECT_LT(mse, 0.02);
}

TEST_F(LearningCli, ValidatePrintsMsePerOutputAndTakesTrainOptions) {
  for (const char* method : {"gpr", "gmr", "joint-gmr"}) {
    const RunResult r = run(
        dir_,
        fmt::format(
            "validate --method {} --train '{}' --validate '{}' --gaussians 2 --restarts 3 --json",
            method, train_, val_));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    for (const char* out : {"angle", "speed"}) {
      EXPECT_LT(j[out]["mse"].get<double>(), 0.02) << method << " " << out;
      EXPECT_TRUE(std::isfinite(j[out]["nlpd"].get<double>()));
    }
  }
  const RunResult text =
      run(dir_, fmt::format("validate --train '{}' --validate '{}'", train_, val_));
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("mse"), std::string::npos);
  EXPECT_NE(text.out.find("angle"), std::string::npos);
}

TEST_F(LearningCli, OneDimensionalDatasetWithChosenColumns) {
  const std::string data = (dir_ / "one.csv").string();
  mg::write_file_atomic(
      data, "d,noise,v\n0.5,1,1.0\n1.0,1,1.4\n1.5,1,1.7\n2.0,1,2.0\n2.5,1,2.2\n3.0,1,2.45\n");
  const std::string model = (dir_ / "one.json").string();
  ASSERT_EQ(
      run(dir_, fmt::format("train '{}' -o '{}' --inputs d --outputs v", data, model)).exit_code,
      0);
  const std::string q = (dir_ / "q.csv").string();
  mg::write_file_atomic(q, "d\n1.75\n");
  const RunResult r = run(dir_, fmt::format("predict '{}' '{}'", model, q));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const CsvTable t = parse_csv(r.out, "stdout");
  EXPECT_EQ(t.header, (std::vector<std::string>{"d", "v_mean", "v_std"}));
  EXPECT_NEAR(t.rows[0][1], 1.85, 0.1);
}

TEST_F(LearningCli, BadInputExitsWithCodeTwoAndAOneLineReason) {
  const std::string data_dir = testing::kDataDir.string();
  struct Case {
    std::string args;
    std::string needle;
  };
  const std::string model = (dir_ / "m.json").string();
  const std::vector<Case> cases{
      {fmt::format("train '{}/missing_column.csv' -o '{}'", data_dir, model),
       "missing column 'speed'"},
      {fmt::format("train '{}/text_in_number.csv' -o '{}'", data_dir, model), "abc"},
      {fmt::format("train '{}/nan_value.csv' -o '{}'", data_dir, model), "finite"},
      {fmt::format("train '{}/empty.csv' -o '{}'", data_dir, model), "empty"},
      {fmt::format("train '{}/one_row.csv' -o '{}'", data_dir, model), "at least 2"},
      {fmt::format("train '{}' -o '{}' --method svm", train_, model), "gpr, gmr, joint-gmr"},
      {fmt::format("train '{}' -o '{}' --method gmr --gaussians 50", train_, model), "at most 20"},
      {fmt::format("train '{}' -o '{}' --noise-std 0.1,0.2,0.3", train_, model), "--noise-std"},
      {fmt::format("predict '{}/truncated_model.json' '{}'", data_dir, val_), "not valid JSON"},
      {fmt::format("predict '{}/future_model.json' '{}'", data_dir, val_), "format_version"},
      {fmt::format("predict '{}/no_such_model.json' '{}'", data_dir, val_), "no_such_model.json"},
  };
  for (const Case& c : cases) {
    const RunResult r = run(dir_, c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("minigolf: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(c.needle), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(model)) << "no model file after a failed train";
  // Query file without the model's input columns.
  const std::string good = (dir_ / "good.json").string();
  ASSERT_EQ(run(dir_, fmt::format("train '{}' -o '{}' --restarts 2", train_, good)).exit_code, 0);
  const std::string q = (dir_ / "q.csv").string();
  mg::write_file_atomic(q, "xi_x\n1.0\n");
  const RunResult r = run(dir_, fmt::format("predict '{}' '{}'", good, q));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("missing column 'xi_y'"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace mg::learning
