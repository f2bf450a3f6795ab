#pragma once
/// `minigolf render --course`: the film of one hole of a round (game/round.hpp). The strokes are
/// drawn one after the other in the ball-only world of the hole's field: before each, the ball at
/// its start with an aim arrow along the planned launch; then the ball moved along the stroke's
/// recorded path (x, y every 10 ms; z = the surface + the ball's radius) in real time; then a
/// short hold at its rest. The arm is not drawn (its own hit is `render` without --course).
///
/// The film replays a finished round, so drawing cannot change it.
#include <array>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "field/field.hpp"
#include "game/round.hpp"
#include "sim/world.hpp"
#include "viz/render_hit.hpp"

namespace mg::viz {

/// How long the still parts of a stroke last [s of film].
struct FilmTiming {
  double aim = 0.6;   ///< the ball at its start with the aim arrow
  double hold = 0.5;  ///< the ball at its rest (or in the cup)
};

/// One frame of a hole's film.
struct FilmFrame {
  std::size_t stroke = 0;               ///< index into the hole's putts
  std::array<double, 3> ball{0, 0, 0};  ///< [m, world] the ball's centre
  std::optional<double> aim;            ///< [rad, world] the launch direction, before the stroke
  std::size_t path_points = 0;          ///< how many of the stroke's path points are drawn
  bool rest = false;                    ///< the stroke's last frame (its filmstrip picture)
  std::string label;                    ///< "hole K, stroke n/N"
  std::string overlay;                  ///< the launch, then the outcome
};

/// [m, world] the ball's centre at `xy` on `field`: the surface + its radius; `in_cup`: low in
/// the cup (hidden under the hole marker).
std::array<double, 3> film_ball_position(const field::Field& field, std::array<double, 2> xy,
                                         bool in_cup);

/// The frames of hole `hole_number` (1-based, for the labels) of a round, played on `field` (the
/// course hole's, with its tee and hole), at `fps`: per stroke, round(aim * fps) frames (at
/// least 1) at the start with the arrow, one frame per 1/fps of the path (10 ms a point, the
/// last point always shown), round(hold * fps) frames (at least 1) at the rest, the last flagged
/// `rest`. A sunk ball is drawn in the cup from the first path point inside the cup's rim on.
/// InputError unless fps is 1..240.
std::vector<FilmFrame> hole_film_frames(const field::Field& field, const game::HoleResult& hole,
                                        int hole_number, double fps, const FilmTiming& timing = {});

/// Draws `frames` (hole_film_frames of `hole` on `ball_world`'s field) off-screen in
/// `ball_world`, its hole at the field's: OUT.mp4 (or OUT-frames/) unless options.video is
/// false, and OUT-filmstrip.png (the `rest` frames side by side, each with its stroke's whole
/// path). Camera "top" is fitted to the whole lane and the image size; the others are the
/// presets of `render`. Needs a current OpenGL context (GlWindow). `out` is the stem.
RenderOutputs render_hole_film(const sim::World& ball_world, const game::HoleResult& hole,
                               const std::vector<FilmFrame>& frames, const RenderOptions& options,
                               const std::filesystem::path& out);

}  // namespace mg::viz
