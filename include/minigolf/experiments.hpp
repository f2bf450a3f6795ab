#pragma once
/// minigolf C++ API: experiments over a system (docs/learning.md, docs/robustness.md): sweeps of
/// (angle, speed), collecting a data set with the teacher, the robot playing test situations with
/// a learned model, learning curves, the launch study, adaptation, and thesis chapter 6 end to
/// end (reproduce). Results are the same for any thread count.
#include "experiments/adaptation.hpp"
#include "experiments/collect.hpp"
#include "experiments/evaluate.hpp"
#include "experiments/launch_study.hpp"
#include "experiments/learning_curves.hpp"
#include "experiments/reproduce.hpp"
#include "experiments/round_study.hpp"
#include "experiments/sweep.hpp"
