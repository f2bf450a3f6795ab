#pragma once
/// minigolf C++ API: hitting-parameter learners (docs/learning.md): data sets, GPR / GMR /
/// joint-GMR models xi -> (angle, speed), their files, predictions and scores, over the
/// statistics they share with the hitting motion (GMM, GMR, GPR).
///
///   mg::learning::Dataset d = mg::learning::load_dataset("flat.csv", {"xi_x", "xi_y"}, {"angle"});
///   mg::learning::Model m = mg::learning::train(d, {});
///   mg::learning::Predictions p = mg::learning::predict(m, queries);  // (N x I) -> mean, std
#include "learning/dataset.hpp"
#include "learning/learner.hpp"
#include "stats/gmm.hpp"
#include "stats/gmr.hpp"
#include "stats/gpr.hpp"
