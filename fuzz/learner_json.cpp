// Learner model JSON (core/json_io + learning/learner), then one prediction.
#include <Eigen/Core>

#include "core/json_io.hpp"
#include "harness.hpp"
#include "learning/learner.hpp"

MG_FUZZ_TARGET({
  const auto m = mg::learning::model_from_json(mg::parse_json(std::string(mg::fuzz::as_text(data, size)), "fuzz.json"),
                                               "fuzz.json");
  (void)mg::learning::predict(m, Eigen::MatrixXd::Ones(1, m.num_inputs()));
})
