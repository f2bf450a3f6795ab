// Learner model JSON (core/json_io + learning/learner), then one prediction and its
// beyond-training check (the corpus holds models with fixed outputs, e.g. angle-only models).
#include <Eigen/Core>

#include "core/json_io.hpp"
#include "harness.hpp"
#include "learning/learner.hpp"

MG_FUZZ_TARGET({
  const auto m = mg::learning::model_from_json(
      mg::parse_json(std::string(mg::fuzz::as_text(data, size)), "fuzz.json"), "fuzz.json");
  const auto p = mg::learning::predict(m, Eigen::MatrixXd::Ones(1, m.num_inputs()));
  (void)mg::learning::beyond_training(m, p);
})
