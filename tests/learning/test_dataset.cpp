#include "learning/dataset.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "learning_test_util.hpp"

namespace mg::learning {
namespace {

using testing::kDataDir;

void expect_error(const std::filesystem::path& file, const std::string& needle,
                  const std::vector<std::string>& outputs = kDefaultOutputs) {
  try {
    load_dataset(file, kDefaultInputs, outputs);
    FAIL() << "expected InputError for " << file;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(file.filename().string()), std::string::npos) << e.what();
  }
}

TEST(LearningDataset, MalformedFilesAreClearErrors) {
  expect_error(kDataDir / "missing_column.csv", "missing column 'speed'");
  expect_error(kDataDir / "text_in_number.csv", "'abc'");
  expect_error(kDataDir / "nan_value.csv", "finite");
  expect_error(kDataDir / "empty.csv", "empty");
  expect_error(kDataDir / "one_row.csv", "at least 2 data rows, got 1");
  expect_error(kDataDir / "short_row.csv", "expected 4 values, got 2");
  EXPECT_THROW(load_dataset(kDataDir / "no_such_file.csv"), IoError);
}

TEST(LearningDataset, ColumnsAreChosenByName) {
  const CsvTable t = parse_csv("speed,junk,xi_y,angle,xi_x\n1,9,2,3,4\n5,9,6,7,8\n", "mem");
  const Dataset d = dataset_from_table(t, kDefaultInputs, kDefaultOutputs);
  EXPECT_EQ(d.inputs(0, 0), 4.0);
  EXPECT_EQ(d.inputs(1, 1), 6.0);
  EXPECT_EQ(d.outputs(0, 0), 3.0);
  EXPECT_EQ(d.outputs(1, 1), 5.0);
  const Dataset one = dataset_from_table(t, {"xi_x"}, {"angle"});
  EXPECT_EQ(one.inputs.cols(), 1);
  EXPECT_EQ(one.outputs.cols(), 1);
  EXPECT_THROW(dataset_from_table(t, {"xi_x"}, {"xi_x"}), InputError);
  EXPECT_THROW(dataset_from_table(t, {"xi_x", "xi_x"}, {"angle"}), InputError);
  EXPECT_THROW(dataset_from_table(t, {}, {"angle"}), InputError);
  const Eigen::MatrixXd q = query_inputs(t, {"xi_y"});
  EXPECT_EQ(q(1, 0), 6.0);
}

// Found by fuzzing: a value of 1e200 crashed GMR training (squared distances overflow).
TEST(LearningDataset, HugeValuesAreAClearErrorNamingTheFile) {
  const CsvTable t = parse_csv("xi_x,angle\n1e200,0\n2,0.1\n", "s.csv");
  try {
    dataset_from_table(t, {"xi_x"}, {"angle"});
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("s.csv: row 1, column 'xi_x'"), std::string::npos)
        << e.what();
  }
  EXPECT_NO_THROW(
      dataset_from_table(parse_csv("xi_x,angle\n1e90,0\n2,0.1\n", "ok.csv"), {"xi_x"}, {"angle"}));
}

}  // namespace
}  // namespace mg::learning
