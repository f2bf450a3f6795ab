// Learner model files (src/learning/model_io.cpp): round trips and broken files.
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/io.hpp"
#include "learning/learner.hpp"
#include "learning_test_util.hpp"

namespace mg::learning {
namespace {

using testing::flat_field;
using testing::options;
using testing::same_bits;

void expect_model_error(const nlohmann::json& j, const std::string& needle) {
  try {
    model_from_json(j, "m.json");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(LearningModel, SaveLoadRoundTripIsBitIdentical) {
  testing::ScratchDir dir;
  const Dataset d = flat_field(25, 13);
  const Eigen::MatrixXd q = flat_field(50, 14).inputs;
  for (Method m : {Method::kGpr, Method::kGmr, Method::kJointGmr}) {
    const Model model = train(d, options(m));
    const auto path = dir / "model.json";
    save_model(model, path);
    const Model back = load_model(path);
    const auto path2 = dir / "model2.json";
    save_model(back, path2);
    EXPECT_EQ(read_text_file(path), read_text_file(path2)) << method_name(m);
    const Predictions a = predict(model, q);
    const Predictions b = predict(back, q);
    EXPECT_TRUE(same_bits(a.mean, b.mean)) << method_name(m);
    EXPECT_TRUE(same_bits(a.std, b.std)) << method_name(m);
    EXPECT_EQ(report_to_json(model).dump(), report_to_json(back).dump());
    const auto j = nlohmann::json::parse(read_text_file(path));
    EXPECT_EQ(j.at("format_version"), kModelFormatVersion);
    EXPECT_EQ(j.at("method"), std::string(method_name(m)));
  }
}

TEST(LearningModel, BrokenOrIncompatibleModelFilesAreClearErrors) {
  EXPECT_THROW(load_model(testing::kDataDir / "truncated_model.json"), InputError);
  try {
    load_model(testing::kDataDir / "future_model.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("format_version"), std::string::npos) << e.what();
  }
  const nlohmann::json gpr = model_to_json(train(flat_field(10, 16), options(Method::kGpr)));
  const nlohmann::json gmr = model_to_json(train(flat_field(10, 16), options(Method::kGmr, 2)));
  nlohmann::json j = gpr;
  j.erase("format_version");
  expect_model_error(j, "format_version");
  j = gpr;
  j["method"] = "svm";
  expect_model_error(j, "gpr, gmr, joint-gmr");
  j = gpr;
  j["gps"][1]["noise_std"] = "high";
  expect_model_error(j, "gps[1].noise_std");
  j = gpr;
  j["gps"][0]["length_scales"] = {1.0};
  expect_model_error(j, "length scales");
  j = gmr;
  j["gmms"][0]["priors"] = {0.2, 0.2};
  expect_model_error(j, "gmms[0]");
  j = gmr;
  j["gmms"].erase(1);
  expect_model_error(j, "gmms");
  j = gmr;
  j["method"] = "joint-gmr";
  expect_model_error(j, "gmms");
}

// A model with an input named twice predicted one angle for every query (both
// places read one column); also inside a residual's prior. Item 6: a key twice in the file (the
// last won) is refused by the JSON reader.
TEST(LearningModel, DuplicateNamesAndKeysAreRefused) {
  const nlohmann::json gpr = model_to_json(train(flat_field(10, 16), options(Method::kGpr)));
  const std::string first = gpr["inputs"][0].get<std::string>();
  nlohmann::json j = gpr;
  j["inputs"] = {first, first};
  expect_model_error(j, "m.json.inputs: '" + first + "' appears twice (expected distinct names)");
  j = gpr;
  j["outputs"] = {"angle", "angle"};
  expect_model_error(j, "m.json.outputs: 'angle' appears twice");
  j = gpr;
  j["prior"] = gpr;
  j["prior"]["inputs"] = {first, first};
  expect_model_error(j, "m.json.prior.inputs: '" + first + "' appears twice");

  testing::ScratchDir dir;
  const auto path = dir / "dup.json";
  std::string text = gpr.dump();
  text.insert(1, "\"method\": \"gmr\", ");  // the file's own "method" comes later
  write_file_atomic(path, text);
  try {
    load_model(path);
    FAIL() << "a duplicate key was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("duplicate key 'method'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mg::learning
