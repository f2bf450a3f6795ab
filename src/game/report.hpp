#pragma once
/// What a round reports (docs/round.md): the JSON of `play --json` and Python's `play`, the CSV of
/// every stroke, and the comparison of players over seeds and courses (`play --compare`, the
/// "round of minigolf" section of `reproduce`). One flow for the CLI, Python and reproduce.
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "game/round.hpp"

namespace mg::game {

/// {"course", "player", "holes": [{"field", "par", "strokes", "sunk", "putts": [{"ball", "angle",
/// "speed", "rest", "sunk", "left_lane", "bank", "sink_probability"}]}], "total_strokes",
/// "total_par", "learning_putts", "imagined_putts"}
nlohmann::json round_json(const RoundResult& round);

/// One row per stroke: hole,field,par,stroke,ball_x,ball_y,angle,speed,rest_x,rest_y,sunk,left_lane
std::string round_csv(const RoundResult& round);

/// The players of a comparison (`play --compare`, `reproduce`): robot, oracle, exact-oracle,
/// greedy.
std::vector<Player> comparison_players();

/// Rounds of one course by several players over consecutive seeds.
struct CourseRounds {
  Course course;
  std::vector<Player> players;
  std::vector<std::vector<RoundResult>> rounds;  ///< [player][seed]
};

/// Plays `course` by every player for seeds first_seed .. first_seed + seeds - 1 (one shared
/// imagined-putt cache). `progress(done, total)` after every round.
CourseRounds play_seeds(const Course& course, const control::ModuleConfig& config,
                        const plant::Plant& plant, const std::vector<Player>& players,
                        const RoundOptions& base, std::uint64_t first_seed, int seeds,
                        const std::function<void(int, int)>& progress = {});

/// A player's figures over holes (of one course or several): mean strokes per hole with the
/// half-width of its 95 % interval (normal approximation over holes), strokes minus par likewise,
/// hole-in-one and finished rates, learning putts per field.
struct PlayerSummary {
  Player player = Player::kRobot;
  int holes = 0;
  double strokes = 0.0, strokes_ci = 0.0;
  double vs_par = 0.0, vs_par_ci = 0.0;
  double hole_in_one = 0.0;  ///< fraction
  int finished = 0;          ///< holes sunk within max_strokes
  double learning_putts_per_field = 0.0;
};

/// Summary of `player`'s rounds over every course in `all` that it played.
PlayerSummary summarize(const std::vector<CourseRounds>& all, Player player);

/// The Markdown tables: per player over all courses (with the difference to the oracle and its
/// paired 95 % interval when the oracle played), then the mean strokes per hole of each course.
std::string comparison_markdown(const std::vector<CourseRounds>& all, int seeds,
                                const std::string& plant_note);

/// The rounds of one course in one world (a plant) by the robot revising its belief and the
/// oracle (`revising`), and by the robot keeping its belief (`kept`, RoundOptions::revise false).
struct PlantRounds {
  std::string plant;  ///< its name in the table
  CourseRounds revising;
  CourseRounds kept;
};

/// The Markdown of docs/round.md "Rounds on unknown plants": strokes per hole per plant, then per
/// player over every plant with the 95 % interval and the difference to the oracle paired hole
/// by hole.
std::string plant_comparison_markdown(const std::vector<PlantRounds>& all, int seeds);

}  // namespace mg::game
