// Adaptation: a model from the nominal simulator in a world unlike it, corrected by the
// robot's own putts; the study over random plants; zero plants change no bit.
#include <memory>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/io.hpp"
#include "experiments/adaptation.hpp"
#include "experiments/evaluate.hpp"
#include "learning/dataset.hpp"
#include "learning/learner.hpp"
#include "selfteach/self_teach.hpp"

namespace mg::experiments {
namespace {

/// GPR on the shipped regular-hill data set: the nominal-simulator model.
const learning::Model& nominal_model() {
  static const learning::Model m = [] {
    const learning::Dataset d =
        learning::load_dataset(data_dir() / "datasets" / "regular-hill.csv");
    learning::TrainOptions o;
    return learning::train(d, o);
  }();
  return m;
}

plant::Plant slow_grass() {
  return plant::parse_plant("format_version: 1\nfield: {rolling_resistance_scale: 1.15}\n",
                            "slow.yaml");
}

EvaluateOptions play(int n, std::uint64_t seed) {
  EvaluateOptions o;
  o.situations = n;
  o.seed = seed;
  o.oracle = false;
  return o;
}

TEST(Adaptation, ANominalModelFailsOnSlowerGrassAndAFewOwnPuttsRecoverIt) {
  const auto config = system::load_config("", "regular-hill");
  const system::System real(config, slow_grass());
  const auto& region = real.field().situations;
  // The thesis's real-robot failure, measured: 10 of 60; here on 20 situations.
  const Evaluation before = evaluate_model(real, nominal_model(), region, play(20, 5));
  EXPECT_LE(before.sunk, 10);
  selfteach::SelfTeachOptions so;
  so.budget = 5;
  so.threads = 1;
  so.prior = std::make_shared<const learning::Model>(nominal_model());
  const auto adapted = selfteach::self_teach(real, region, so);
  ASSERT_TRUE(adapted.trained);
  ASSERT_TRUE(adapted.model.prior);
  const Evaluation after = evaluate_model(real, adapted.model, region, play(20, 5));
  EXPECT_GE(after.sunk, 19) << "before " << before.sunk;
  // The saved residual model plays the same after a file round trip.
  const learning::Model back = learning::model_from_json(learning::model_to_json(adapted.model));
  EXPECT_EQ(evaluate_model(real, back, region, play(5, 9)).sunk,
            evaluate_model(real, adapted.model, region, play(5, 9)).sunk);
}

TEST(Adaptation, LearningWhilePlayingTheResidualWayBeatsAppending) {
  const auto config = system::load_config("", "regular-hill");
  const system::System real(config, slow_grass());
  const auto& region = real.field().situations;
  EvaluateOptions o = play(30, 3);
  const auto residual = evaluate_learning(real, nominal_model(), region, o);
  o.learn = LearnMode::kAppend;
  const auto appended = evaluate_learning(real, nominal_model(), region, o);
  // Appending was measured at 8 of 60; the residual corrects from the first putt on.
  EXPECT_GE(residual.evaluation.sunk, 27);
  EXPECT_GT(residual.evaluation.sunk, appended.evaluation.sunk + 5);
}

TEST(Adaptation, AnEmptyPlantChangesNoBitOfAnEvaluation) {
  const auto config = system::load_config("", "regular-hill");
  const system::System nominal(config);
  const system::System empty(config, plant::parse_plant("format_version: 1\n", "empty.yaml"));
  const auto& region = nominal.field().situations;
  EvaluateOptions o = play(4, 2);
  o.oracle = true;
  o.teacher.strategy = teacher::parse_strategy(region.strategy);
  const Evaluation a = evaluate_model(nominal, nominal_model(), region, o);
  const Evaluation b = evaluate_model(empty, nominal_model(), region, o);
  EXPECT_EQ(evaluation_csv(a, nominal.field()), evaluation_csv(b, empty.field()));
}

TEST(Adaptation, TheStudyIsTheSameForAnyThreadCount) {
  const auto config = system::load_config("", "flat");
  const learning::Dataset d = learning::load_dataset(data_dir() / "datasets" / "flat.csv");
  auto prior = std::make_shared<learning::Model>(learning::train(d, learning::TrainOptions{}));
  AdaptationOptions o;
  o.plants = 2;
  o.situations = 6;
  o.checkpoints = {0, 2};
  o.oracle = false;
  o.threads = 1;
  const auto one = adaptation_study(config, prior, field::load_field("flat").situations, o);
  o.threads = 2;
  const auto two = adaptation_study(config, prior, field::load_field("flat").situations, o);
  EXPECT_EQ(adaptation_csv(one, o.learner), adaptation_csv(two, o.learner));
  ASSERT_EQ(one.size(), 2u);
  EXPECT_EQ(one[0].putts, (std::vector<int>{0, 2}));
  o.checkpoints = {0};
  EXPECT_THROW(adaptation_study(config, prior, field::load_field("flat").situations, o),
               InputError);
}

}  // namespace
}  // namespace mg::experiments
