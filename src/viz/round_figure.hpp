#pragma once
/// Figures of rounds of minigolf (game/round.hpp), one PNG per hole of the course: the field's
/// height colour map with its obstacles, tee and hole (the cup to scale) and the ball path of
/// every stroke of every round given (one colour per stroke number, rests as dots, a ball that
/// left the lane as a cross), titled with the field, par and the mean strokes over the rounds.
/// The numbers go through CSV files to scripts/plots/plot.py (`round`; core/plot.hpp).
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "game/course.hpp"
#include "game/round.hpp"

namespace mg::viz {

/// round,stroke,ball_x,ball_y,angle,speed,rest_x,rest_y,sunk,left_lane: every stroke of hole
/// `hole` (0-based) in every round (round from 0, stroke from 1) [m, rad, m/s].
std::string round_strokes_csv(const std::vector<game::RoundResult>& rounds, std::size_t hole);
/// round,stroke,x,y: those strokes' ball paths [m] (points 10 ms apart). Header only when no
/// stroke has a path.
std::string round_paths_csv(const std::vector<game::RoundResult>& rounds, std::size_t hole);
/// The mean strokes (penalties included) of hole `hole` over the rounds.
double mean_hole_strokes(const std::vector<game::RoundResult>& rounds, std::size_t hole);

/// Writes `out_dir`/`stem`-hole<K>.png for every hole K = 1.. of `course` and returns their
/// paths. `rounds`: rounds played on `course` (game::play_round), at least one. `out_dir` is made
/// when missing. The CSVs go to a temporary folder removed afterwards, or to `data_dir` (kept)
/// when given. InputError for no rounds, a round of another course (hole count or fields), or a
/// stem that is empty or has a '/'; IoError/Error from the files and the plot script.
std::vector<std::filesystem::path> plot_round_holes(const game::Course& course,
                                                    const std::vector<game::RoundResult>& rounds,
                                                    const std::filesystem::path& out_dir,
                                                    const std::string& stem,
                                                    const std::filesystem::path& data_dir = {});

}  // namespace mg::viz
