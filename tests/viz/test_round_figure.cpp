// The round figures' numbers and the frames of a hole's film, from hand-made rounds (no play, no
// display); plot_round_holes writes one PNG per hole through the plot script.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "game/course.hpp"
#include "viz/figure_data.hpp"
#include "viz/image.hpp"
#include "viz/render_round.hpp"
#include "viz/round_figure.hpp"
#include "viz_test_util.hpp"

namespace mg::viz {
namespace {

game::Course two_hole_course() {
  return game::parse_course(
      "format_version: 1\nname: two\nmax_strokes: 4\nholes:\n"
      "  - {field: flat, tee: [0.2, 0.0], hole: [1.2, 0.1], par: 2}\n"
      "  - {field: bank-shot, par: 2}\n",
      "two.yaml", ".");
}

/// A straight path from `a` to `b`, `n` points.
std::vector<std::array<double, 2>> line(std::array<double, 2> a, std::array<double, 2> b, int n) {
  std::vector<std::array<double, 2>> p;
  for (int i = 0; i < n; ++i) {
    const double u = static_cast<double>(i) / (n - 1);
    p.push_back({a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1])});
  }
  return p;
}

/// Hole 1 of two_hole_course: short of the hole (50 points), then holed (31 points).
game::HoleResult two_putts(const field::Field& f) {
  game::HoleResult h;
  h.field = f.name;
  h.par = 2;
  h.strokes = 2;
  h.sunk = true;
  game::StrokeRecord s1;
  s1.ball = f.tee;
  s1.angle = 0.1;
  s1.speed = 1.2;
  s1.rest = {0.9, 0.05};
  s1.path = line(s1.ball, s1.rest, 50);
  game::StrokeRecord s2;
  s2.ball = s1.rest;
  s2.angle = 0.16;
  s2.speed = 0.8;
  s2.rest = f.hole.position;
  s2.sunk = true;
  s2.path = line(s2.ball, f.hole.position, 31);
  h.putts = {s1, s2};
  return h;
}

std::vector<game::RoundResult> rounds_of(const game::Course& c, int n) {
  std::vector<game::RoundResult> rounds;
  for (int r = 0; r < n; ++r) {
    game::RoundResult round;
    round.course = c.name;
    round.player = game::Player::kOracle;
    for (const auto& ch : c.holes) {
      game::HoleResult h = two_putts(ch.field);
      h.strokes = 2 + r;  // mean over the rounds: 2 + (n - 1) / 2
      round.holes.push_back(h);
    }
    rounds.push_back(round);
  }
  return rounds;
}

TEST(RoundFigure, CsvsHoldEveryStrokeAndEveryPathPoint) {
  const game::Course c = two_hole_course();
  const auto rounds = rounds_of(c, 3);
  const CsvTable strokes = parse_csv(round_strokes_csv(rounds, 0), "strokes");
  ASSERT_EQ(strokes.column("round").size(), 6u);
  EXPECT_EQ(strokes.column("stroke")[0], 1.0);
  EXPECT_EQ(strokes.column("stroke")[1], 2.0);
  EXPECT_EQ(strokes.column("sunk")[1], 1.0);
  EXPECT_EQ(strokes.column("round")[5], 2.0);
  EXPECT_DOUBLE_EQ(strokes.column("rest_x")[0], 0.9);
  const CsvTable paths = parse_csv(round_paths_csv(rounds, 0), "paths");
  EXPECT_EQ(paths.column("x").size(), 3u * (50 + 31));
  EXPECT_DOUBLE_EQ(mean_hole_strokes(rounds, 1), 3.0);
}

TEST(RoundFigure, ObstacleCornersAreTheFootprint) {
  const game::Course c = two_hole_course();
  const field::Field& f = c.holes[1].field;  // bank-shot: one block 0.3 x 0.5 at (1, 0)
  ASSERT_EQ(f.obstacles.size(), 1u);
  const CsvTable t = parse_csv(obstacles_csv(f), "obstacles");
  const auto x = t.column("x"), y = t.column("y"), block = t.column("block");
  ASSERT_EQ(x.size(), 4u);
  double area = 0.0;  // shoelace: counter-clockwise gives a positive area
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(block[k], 1.0);
    EXPECT_NEAR(f.obstacles[0].distance({x[k], y[k]}), 0.0, 1e-9);
    area += x[k] * y[(k + 1) % 4] - x[(k + 1) % 4] * y[k];
  }
  EXPECT_NEAR(0.5 * area, 0.3 * 0.5, 1e-9);
  const std::string none = obstacles_csv(c.holes[0].field);  // flat: the header only
  EXPECT_EQ(none.rfind("obstacle,block,x,y", 0), 0u) << none;
  EXPECT_EQ(std::count(none.begin(), none.end(), '\n'), 1) << none;
}

TEST(RoundFigure, PlotRoundHolesWritesOnePngPerHole) {
  const game::Course c = two_hole_course();
  const auto dir = testing::temp_dir("round_figure");
  const auto pngs = plot_round_holes(c, rounds_of(c, 2), dir / "figs", "two", dir / "data");
  ASSERT_EQ(pngs.size(), 2u);
  for (std::size_t h = 0; h < 2; ++h) {
    EXPECT_EQ(pngs[h], dir / "figs" / ("two-hole" + std::to_string(h + 1) + ".png"));
    const Image img = read_png(pngs[h]);
    EXPECT_GT(img.width, 500);
    EXPECT_GT(img.height, 300);
  }
  EXPECT_TRUE(std::filesystem::exists(dir / "data" / "two-hole2_obstacles.csv"));
  EXPECT_FALSE(std::filesystem::exists(dir / "data" / "two-hole1_obstacles.csv"));
}

TEST(RoundFigure, PlotRoundHolesRefusesRoundsOfAnotherCourseAndBadStems) {
  const game::Course c = two_hole_course();
  const auto dir = testing::temp_dir("round_figure_bad");
  EXPECT_THROW(plot_round_holes(c, {}, dir, "x"), InputError);
  auto rounds = rounds_of(c, 1);
  rounds[0].holes.pop_back();
  EXPECT_THROW(plot_round_holes(c, rounds, dir, "x"), InputError);
  rounds = rounds_of(c, 1);
  rounds[0].holes[1].field = "arctan";
  EXPECT_THROW(plot_round_holes(c, rounds, dir, "x"), InputError);
  EXPECT_THROW(plot_round_holes(c, rounds_of(c, 1), dir, "a/b"), InputError);
  EXPECT_THROW(plot_round_holes(c, rounds_of(c, 1), dir, ""), InputError);
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(HoleFilm, FramesFollowTheStrokesAndHoleTheBall) {
  const game::Course c = two_hole_course();
  const field::Field& f = c.holes[0].field;
  const game::HoleResult h = two_putts(f);
  const double fps = 20.0;
  const auto frames = hole_film_frames(f, h, 1, fps);
  // Per stroke: 0.6 s aim (12 frames), the path at 20 fps (10 ms a point: every 5th point, the
  // last always), 0.5 s hold (10 frames).
  const std::size_t roll1 = 10 + 1, roll2 = 6 + 1;  // points 0, 5, .., 45, 49 and 0, .., 30
  ASSERT_EQ(frames.size(), 12 + roll1 + 10 + 12 + roll2 + 10);
  int rests = 0;
  for (const auto& fr : frames) rests += fr.rest;
  EXPECT_EQ(rests, 2);
  const FilmFrame& first = frames.front();
  EXPECT_EQ(first.label, "hole 1, stroke 1/2");
  ASSERT_TRUE(first.aim.has_value());
  EXPECT_DOUBLE_EQ(*first.aim, 0.1);
  EXPECT_EQ(first.path_points, 0u);
  EXPECT_NEAR(first.ball[2], f.height(f.tee[0], f.tee[1]) + f.ball.radius, 1e-12);
  const FilmFrame& end1 = frames[12 + roll1 + 9];
  EXPECT_TRUE(end1.rest);
  EXPECT_FALSE(end1.aim.has_value());
  EXPECT_EQ(end1.path_points, 50u);
  EXPECT_DOUBLE_EQ(end1.ball[0], 0.9);
  EXPECT_NE(end1.overlay.find("at rest"), std::string::npos) << end1.overlay;
  EXPECT_EQ(frames[12 + roll1 + 10].label, "hole 1, stroke 2/2");
  const FilmFrame& last = frames.back();
  EXPECT_TRUE(last.rest);
  EXPECT_EQ(last.stroke, 1u);
  EXPECT_NE(last.overlay.find("sunk"), std::string::npos);
  // Holed: the ball's top below the surface, under the hole marker.
  EXPECT_LT(last.ball[2] + f.ball.radius, f.height(f.hole.position[0], f.hole.position[1]));
  // Rolling frames show the path so far and the ball on it.
  const FilmFrame& mid = frames[12 + 3];
  EXPECT_EQ(mid.path_points, 16u);
  EXPECT_DOUBLE_EQ(mid.ball[0], h.putts[0].path[15][0]);
  EXPECT_THROW(hole_film_frames(f, h, 1, 0.0), InputError);
}

TEST(HoleFilm, AWhiffHasNoRollingFrames) {
  const game::Course c = two_hole_course();
  const field::Field& f = c.holes[0].field;
  game::HoleResult h;
  game::StrokeRecord s;
  s.ball = s.rest = f.tee;
  h.putts = {s};
  h.strokes = 1;
  const auto frames = hole_film_frames(f, h, 3, 10.0);
  ASSERT_EQ(frames.size(), 6u + 5u);
  EXPECT_EQ(frames.front().label, "hole 3, stroke 1/1");
  EXPECT_TRUE(frames.back().rest);
  EXPECT_EQ(frames.back().path_points, 0u);
}

}  // namespace
}  // namespace mg::viz
