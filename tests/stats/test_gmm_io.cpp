#include "stats/gmm_io.hpp"

#include <cstring>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "test_util.hpp"

namespace mg::stats {
namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(StatsGmmIo, RoundTripIsBitIdentical) {
  mg::Rng rng(21);
  Gmm g = testing::random_gmm(3, 3, rng);
  g.means[0](0) = 0.1 + 0.2;  // classic non-representable value
  g.means[1](2) = -1e-300;
  const std::string text = gmm_to_json(g).dump();
  const Gmm back = gmm_from_json(nlohmann::json::parse(text));
  ASSERT_EQ(back.num_components(), 3);
  for (int k = 0; k < 3; ++k) {
    EXPECT_TRUE(same_bits(back.priors(k), g.priors(k)));
    for (int i = 0; i < 3; ++i) {
      EXPECT_TRUE(same_bits(back.means[k](i), g.means[k](i)));
      for (int j = 0; j < 3; ++j)
        EXPECT_TRUE(same_bits(back.covariances[k](i, j), g.covariances[k](i, j)));
    }
  }
  EXPECT_EQ(gmm_to_json(back).dump(), text);
}

void expect_input_error(const nlohmann::json& j, const std::string& needle) {
  try {
    gmm_from_json(j, "model.json");
    FAIL() << "expected InputError for " << j.dump();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(StatsGmmIo, BrokenInputIsAClearError) {
  mg::Rng rng(22);
  const nlohmann::json good = gmm_to_json(testing::random_gmm(2, 2, rng));
  nlohmann::json j = good;
  j.erase("means");
  expect_input_error(j, "missing field 'means'");
  j = good;
  j["priors"][0] = "x";
  expect_input_error(j, "priors[0]");
  j = good;
  j["covariances"][1][0] = {1.0};
  expect_input_error(j, "covariances[1]");
  j = good;
  j["covariances"][0] = {{1.0, 2.0}, {2.0, 1.0}};  // symmetric, not positive definite
  expect_input_error(j, "positive definite");
  j = good;
  j["priors"] = {0.5, 0.6};
  expect_input_error(j, "sum of 1");
  expect_input_error(nlohmann::json::array(), "JSON object");
  j = good;
  j["type"] = "gp";
  expect_input_error(j, "type");
}

}  // namespace
}  // namespace mg::stats
