#pragma once
/// minigolf C++ API: the game (docs/play.md, docs/round.md): courses of holes, the stroke planner,
/// a round played by the robot, the oracle or the greedy player, and its reports.
#include "game/course.hpp"
#include "game/planner.hpp"
#include "game/report.hpp"
#include "game/round.hpp"
#include "game/skill.hpp"
