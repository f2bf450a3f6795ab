#pragma once
/// minigolf C++ API: where examples come from (docs/learning.md, docs/selfteach.md): the
/// automated teacher (a sinking putt for a situation, found on the full system) and the robot
/// teaching itself from its own putts.
///
///   mg::teacher::Example e = mg::teacher::teach(sys, data, hole,
///   mg::teacher::options_for(region));
#include "selfteach/hindsight.hpp"
#include "selfteach/self_teach.hpp"
#include "teacher/teacher.hpp"
