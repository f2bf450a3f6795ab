// Learning curves against own putts, learning while playing, and noise in the evaluation.
#include <gtest/gtest.h>

#include "../slow_test.hpp"
#include "core/error.hpp"
#include "experiments/evaluate.hpp"
#include "experiments/learning_curves.hpp"
#include "field/situations.hpp"
#include "learning/learner.hpp"

namespace mg::experiments {
namespace {

const system::System& hill() {
  static const system::System s(system::load_config("", "regular-hill"));
  return s;
}

/// A GPR model from three of the teacher's regular-hill examples (a poor start).
learning::Model three_example_model() {
  learning::Dataset d;
  d.input_names = {"xi_x", "xi_y"};
  d.output_names = {"angle", "speed"};
  d.inputs.resize(3, 2);
  d.outputs.resize(3, 2);
  d.inputs << 1.75, -0.15, 1.85, 0.05, 2.05, 0.05;
  d.outputs << -0.0676, 1.5432, 0.0276, 1.5373, 0.0319, 1.5417;
  learning::TrainOptions o;
  return learning::train(d, o);
}

/// 30 test situations of seed 3, without the oracle (learning while playing refuses it).
EvaluateOptions thirty_situations() {
  EvaluateOptions o;
  o.situations = 30;
  o.seed = 3;
  o.oracle = false;
  return o;
}

TEST(LearningWhilePlaying, OutcomesJoinTheModelAndItImproves) {
  const auto region = hill().field().situations;
  const EvaluateOptions o = thirty_situations();
  const learning::Model start = three_example_model();
  const Evaluation fixed = evaluate_model(hill(), start, region, o);
  const LearningEvaluation learned = evaluate_learning(hill(), start, region, o);
  int added = 0;
  for (int k : learned.labels_added) added += k;
  EXPECT_GE(added, 20);
  EXPECT_GT(learned.learned.gps[0].size(), start.gps[0].size());
  // Measured: 5 of 30 without learning, 26 of 30 with it.
  EXPECT_GE(learned.evaluation.sunk, fixed.sunk + 10)
      << fixed.sunk << " " << learned.evaluation.sunk;
  // The same inputs give the same bits.
  const LearningEvaluation again = evaluate_learning(hill(), start, region, o);
  EXPECT_EQ(learning::model_to_json(again.learned).dump(),
            learning::model_to_json(learned.learned).dump());
  // The residual way keeps the start as its prior; appending needs a GPR's own data.
  ASSERT_TRUE(learned.learned.prior);
  EXPECT_EQ(learning::model_to_json(*learned.learned.prior).dump(),
            learning::model_to_json(start).dump());
  EvaluateOptions append = o;
  append.learn = LearnMode::kAppend;
  learning::Model gmr = start;
  gmr.method = learning::Method::kGmr;
  EXPECT_THROW(evaluate_learning(hill(), gmr, region, append), InputError);
  EXPECT_THROW(evaluate_learning(hill(), learned.learned, region, append),
               InputError);  // a residual model
  const LearningEvaluation appended = evaluate_learning(hill(), start, region, append);
  EXPECT_GT(appended.learned.gps[0].size(), start.gps[0].size());
  EXPECT_FALSE(appended.learned.prior);
}

// Learning while playing from balls anywhere: each putt is hit from its ball and its
// labels keep that ball.
TEST(LearningWhilePlaying, FromBallsAnywhere) {
  const auto region = field::region_from_spec(hill().field(), "", "box:0,0.4:-0.2,0.2:2,2");
  const EvaluateOptions o = thirty_situations();
  const learning::Model start = three_example_model();
  const Evaluation fixed = evaluate_model(hill(), start, region, o);
  const LearningEvaluation learned = evaluate_learning(hill(), start, region, o);
  int off_tee = 0;
  for (std::size_t i = 0; i < fixed.rows.size(); ++i) {
    EXPECT_EQ(learned.evaluation.rows[i].ball, fixed.rows[i].ball);
    EXPECT_EQ(learned.evaluation.rows[i].hole, fixed.rows[i].hole);
    off_tee += fixed.rows[i].ball != hill().field().tee;
  }
  EXPECT_EQ(off_tee, 30);
  // The residual reads the prior's inputs and the ball's position (the hill needs it).
  EXPECT_EQ(learned.learned.input_names,
            (std::vector<std::string>{"xi_x", "xi_y", "ball_x", "ball_y"}));
  // Measured: 7 of 30 without learning, 16 with the residual, 19 appending.
  EXPECT_GE(learned.evaluation.sunk, fixed.sunk + 5)
      << fixed.sunk << " " << learned.evaluation.sunk;
  EvaluateOptions append = o;
  append.learn = LearnMode::kAppend;
  const LearningEvaluation appended = evaluate_learning(hill(), start, region, append);
  EXPECT_GT(appended.learned.gps[0].size(), start.gps[0].size());
  EXPECT_GE(appended.evaluation.sunk, fixed.sunk + 8) << appended.evaluation.sunk;
}

TEST(Noise, ZeroNoiseChangesNothingAndNoiseIsSeeded) {
  const auto region = hill().field().situations;
  EvaluateOptions o;
  o.situations = 6;
  o.oracle = false;
  const learning::Model m = three_example_model();
  const Evaluation plain = evaluate_model(hill(), m, region, o);
  o.noise_seed = 12345;  // no noise: the seed is not used
  const Evaluation zero = evaluate_model(hill(), m, region, o);
  for (std::size_t i = 0; i < plain.rows.size(); ++i)
    EXPECT_EQ(plain.rows[i].outcome.rest_position, zero.rows[i].outcome.rest_position);
  o.perception_noise = 0.01;
  o.torque_noise = 0.005;
  const Evaluation a = evaluate_model(hill(), m, region, o);
  const Evaluation b = evaluate_model(hill(), m, region, o);
  bool differs = false;
  for (std::size_t i = 0; i < a.rows.size(); ++i) {
    EXPECT_EQ(a.rows[i].outcome.rest_position, b.rows[i].outcome.rest_position);
    differs = differs || a.rows[i].outcome.rest_position != plain.rows[i].outcome.rest_position;
  }
  EXPECT_TRUE(differs);  // the noise moved the balls
  o.torque_noise = -1.0;
  EXPECT_THROW(evaluate_model(hill(), m, region, o), InputError);
}

TEST(LearningCurves, SameBitsForOneAndTwoThreadsAndEveryLearnerRuns) {
  MG_SLOW_TEST();
  const auto region = hill().field().situations;
  CurveOptions o;
  o.checkpoints = {2, 4};
  o.seeds = 2;
  o.situations = 3;
  o.teacher.strategy = teacher::Strategy::kMinSpeed;
  for (const auto learner :
       {CurveLearner::kSelfTeach, CurveLearner::kTeacherGpr, CurveLearner::kCrkr}) {
    o.threads = 1;
    const auto one = learning_curves(hill(), region, learner, o);
    o.threads = 2;
    const auto two = learning_curves(hill(), region, learner, o);
    EXPECT_EQ(curves_csv(one), curves_csv(two)) << to_string(learner);
    ASSERT_EQ(one.size(), 2u);
    EXPECT_EQ(one[0].putts, (std::vector<int>{2, 4}));
  }
  // From balls anywhere: the self-teaching and teacher learners run and keep their
  // bits over threads; CRKR, which acts from the tee, refuses.
  const auto anywhere = field::region_from_spec(hill().field(), "", "box:0,0.4:-0.2,0.2:2,2");
  for (const auto learner : {CurveLearner::kSelfTeach, CurveLearner::kTeacherGpr}) {
    o.threads = 1;
    const auto one = learning_curves(hill(), anywhere, learner, o);
    o.threads = 2;
    EXPECT_EQ(curves_csv(one), curves_csv(learning_curves(hill(), anywhere, learner, o)))
        << to_string(learner);
  }
  EXPECT_THROW(learning_curves(hill(), anywhere, CurveLearner::kCrkr, o), InputError);
  o.checkpoints = {4, 2};
  EXPECT_THROW(learning_curves(hill(), region, CurveLearner::kCrkr, o), InputError);
  const auto s = summarize({CurveRun{CurveLearner::kCrkr, 0, {5}, {1}, 10, 0},
                            CurveRun{CurveLearner::kCrkr, 1, {5}, {3}, 10, 0}});
  EXPECT_DOUBLE_EQ(s.median[0], 0.2);
  EXPECT_DOUBLE_EQ(s.q10[0], 0.12);
}

}  // namespace
}  // namespace mg::experiments
