#include "viz/render_round.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"

namespace mg::viz {

namespace {

constexpr double kPathInterval = 0.01;  // [s] between a stroke's path points (game/round.cpp)

std::string launch_text(const game::StrokeRecord& s) {
  return fmt::format("launch {:.3f} rad, {:.2f} m/s{}", s.angle, s.speed, s.bank ? ", bank" : "");
}

std::string outcome_text(const game::StrokeRecord& s) {
  if (s.sunk) return "sunk";
  if (s.left_lane) return "left the lane: put back, +1 stroke";
  return fmt::format("at rest ({:.2f}, {:.2f}) m", s.rest[0], s.rest[1]);
}

/// The camera preset `name`; "top" fitted to the whole lane (borders included) and the image.
mjvCamera film_camera(const std::string& name, const sim::World& world, const mjData* d, int width,
                      int height) {
  mjvCamera c = camera_preset(name, world, d);
  if (name != "top") return c;
  const field::Field& f = world.field();
  const auto& b = f.bounds;
  const double margin = f.borders.thickness + 0.05;  // [m]
  const double wx = b[1] - b[0] + 2 * margin, wy = b[3] - b[2] + 2 * margin;
  c.lookat[0] = 0.5 * (b[0] + b[1]);
  c.lookat[1] = 0.5 * (b[2] + b[3]);
  c.lookat[2] = f.height(c.lookat[0], c.lookat[1]);
  const double t = std::tan(0.5 * world.model()->vis.global.fovy * 3.14159265358979323846 / 180);
  const double aspect = static_cast<double>(width) / height;
  c.distance = 1.05 * std::max(wy / (2 * t), wx / (2 * t * aspect));
  return c;
}

}  // namespace

std::array<double, 3> film_ball_position(const field::Field& field, std::array<double, 2> xy,
                                         bool in_cup) {
  const double r = field.ball.radius;
  if (in_cup) {
    const auto& h = field.hole.position;
    return {xy[0], xy[1], field.height(h[0], h[1]) - field.hole.depth + r};
  }
  return {xy[0], xy[1], field.height(xy[0], xy[1]) + r};
}

std::vector<FilmFrame> hole_film_frames(const field::Field& field, const game::HoleResult& hole,
                                        int hole_number, double fps, const FilmTiming& timing) {
  if (!(fps >= 1.0 && fps <= 240.0))
    throw InputError(fmt::format("render: --fps {}: expected 1..240", fps));
  const auto& cup = field.hole.position;
  const double rim = 0.5 * field.hole.diameter;
  const auto inside_rim = [&](const std::array<double, 2>& p) {
    return std::hypot(p[0] - cup[0], p[1] - cup[1]) < rim;
  };
  const int aim_frames = std::max(1, static_cast<int>(std::lround(timing.aim * fps)));
  const int hold_frames = std::max(1, static_cast<int>(std::lround(timing.hold * fps)));
  const std::size_t n = hole.putts.size();
  std::vector<FilmFrame> frames;
  for (std::size_t k = 0; k < n; ++k) {
    const game::StrokeRecord& s = hole.putts[k];
    FilmFrame f;
    f.stroke = k;
    f.label = fmt::format("hole {}, stroke {}/{}", hole_number, k + 1, n);
    f.overlay = launch_text(s);
    f.ball = film_ball_position(field, s.ball, false);
    f.aim = s.angle;
    for (int i = 0; i < aim_frames; ++i) frames.push_back(f);
    f.aim.reset();

    // Rolling: one frame per 1/fps of the path, its last point always shown.
    bool dropped = false;  // a sunk ball, once inside the rim, is drawn in the cup
    const std::size_t points = s.path.size();
    for (int i = 0; points > 0; ++i) {
      const auto idx = std::min(
          points - 1, static_cast<std::size_t>(std::floor(i / fps / kPathInterval + 1e-9)));
      for (std::size_t j = f.path_points; j <= idx; ++j)
        dropped = dropped || (s.sunk && inside_rim(s.path[j]));
      f.path_points = idx + 1;
      f.ball = film_ball_position(field, s.path[idx], dropped);
      frames.push_back(f);
      if (idx == points - 1) break;
    }

    // At rest (or in the cup).
    f.path_points = points;
    if (s.sunk)
      f.ball = film_ball_position(field, dropped ? s.path.back() : cup, true);
    else
      f.ball = film_ball_position(field, s.rest, false);
    f.overlay = launch_text(s) + "\n" + outcome_text(s);
    for (int i = 0; i < hold_frames; ++i) {
      f.rest = i + 1 == hold_frames;
      frames.push_back(f);
    }
  }
  return frames;
}

RenderOutputs render_hole_film(const sim::World& world, const game::HoleResult& hole,
                               const std::vector<FilmFrame>& frames, const RenderOptions& options,
                               const std::filesystem::path& out) {
  if (options.width % 2 != 0 || options.height % 2 != 0)
    throw InputError(fmt::format("render: --size {}x{}: width and height must be even (video)",
                                 options.width, options.height));
  if (frames.empty()) throw Error("render: the hole has no strokes to draw");
  for (const auto& f : frames)
    if (f.stroke >= hole.putts.size() || f.path_points > hole.putts[f.stroke].path.size())
      throw Error("render: a film frame names a stroke or path point the hole does not have");
  check_render_outputs(out);

  // The pose of every frame: the world's state with the hole set and the ball moved (the ball's
  // orientation is not recorded: drawn unrotated).
  const field::Field& field = world.field();
  const sim::DataPtr data = world.make_data();
  world.set_hole(data.get(), field.hole.position);
  const int ball = world.ids().ball_qpos;
  Renderer renderer(world, options.width, options.height);
  const auto pose = [&](const FilmFrame& f) {
    for (int i = 0; i < 3; ++i) data->qpos[ball + i] = f.ball[static_cast<std::size_t>(i)];
    data->qpos[ball + 3] = 1.0;
    data->qpos[ball + 4] = data->qpos[ball + 5] = data->qpos[ball + 6] = 0.0;
    copy_pose(world.model(), data.get(), renderer.data());
  };
  pose(frames.front());
  mjvCamera camera =
      film_camera(options.camera, world, renderer.data(), options.width, options.height);

  // The drawn path: 3 mm above the surface, so that it shows on the lane.
  const auto decorations = [&](const FilmFrame& f) {
    Decorations deco;
    deco.aim_angle = f.aim;
    deco.label = f.label;
    deco.overlay = f.overlay;
    const auto& path = hole.putts[f.stroke].path;
    deco.path.reserve(f.path_points);
    for (std::size_t j = 0; j < f.path_points; ++j)
      deco.path.push_back({path[j][0], path[j][1], field.height(path[j][0], path[j][1]) + 0.003});
    return deco;
  };
  const auto draw = [&](const FilmFrame& f) {
    pose(f);
    if (options.camera == "follow") camera = camera_preset(options.camera, world, renderer.data());
    return renderer.render(camera, decorations(f));
  };

  RenderOutputs result;
  result.filmstrip = out.string() + "-filmstrip.png";
  std::vector<Image> stills;
  for (const auto& f : frames)
    if (f.rest) stills.push_back(draw(f));
  if (stills.empty()) stills.push_back(draw(frames.back()));
  write_png(result.filmstrip, filmstrip(stills));
  if (!options.video) return result;
  const VideoOutput video =
      write_video(out, options.width, options.height, options.fps, static_cast<int>(frames.size()),
                  [&](int k) { return draw(frames[static_cast<std::size_t>(k)]); });
  result.video = video.path;
  result.frames = video.frames;
  result.used_ffmpeg = video.used_ffmpeg;
  return result;
}

}  // namespace mg::viz
