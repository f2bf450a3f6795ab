// view | render: the live MuJoCo viewer on the console session, and off-screen rendered hits.
//
//   minigolf view [--config FILE] [--field F] [--realtime|--lockstep] [--script FILE] [--echo]
//                 [--camera NAME] [--size WxH] [--screenshot PNG]
//   minigolf render --field F [--config FILE] [--hole X,Y] (--angle RAD --speed M/S | --model M)
//                   [--camera NAME] [--size WxH] [--fps N] [--no-video] -o OUT
//   minigolf render --course C [--hole K] [--player P] [--seed S] [--budget N] [--plant P]
//                   [--config FILE] [--camera NAME] [--size WxH] [--fps N] [--no-video] -o OUT
//
// Both need a display or `xvfb-run -a` (docs/viz.md); without one: one line, exit 1.
#include <initializer_list>
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "core/error.hpp"
#include "game/round.hpp"
#include "system/system.hpp"
#include "viz/render_hit.hpp"
#include "viz/render_round.hpp"
#include "viz/renderer.hpp"
#include "viz/viewer.hpp"

namespace mg::cli {

namespace {

std::array<int, 2> parse_size(const std::string& text) {
  const auto x = text.find('x');
  if (x == std::string::npos) throw InputError(fmt::format("--size: expected WxH, got '{}'", text));
  const std::uint64_t w = parse_unsigned("--size", text.substr(0, x));
  const std::uint64_t h = parse_unsigned("--size", text.substr(x + 1));
  if (w < 16 || h < 16 || w > 4096 || h > 4096)
    throw InputError(fmt::format("--size {}: expected 16..4096 pixels each way", text));
  return {static_cast<int>(w), static_cast<int>(h)};
}

void check_camera(const std::string& name) {
  for (const auto& n : viz::camera_names())
    if (n == name) return;
  throw InputError(fmt::format("--camera '{}': expected overview, side, top or follow", name));
}

void add_view(CLI::App& app) {
  struct Args {
    std::string config, field, script, camera = "overview", size = "1280x800", screenshot;
    bool realtime = false, lockstep = false, echo = false;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "view", "Watch the arm live in a MuJoCo window (console commands on standard input)");
  cmd->add_option("--config", a->config, "Module config YAML");
  cmd->add_option("--field", a->field, "Shipped field name or path (overrides the config)");
  auto* rt =
      cmd->add_flag("--realtime", a->realtime, "Three threads paced at 500 Hz by the wall clock");
  auto* ls = cmd->add_flag("--lockstep", a->lockstep,
                           "One thread, paced to the wall clock (default; the console's bits)");
  rt->excludes(ls);
  cmd->add_option("--script", a->script, "Read commands from this file instead of standard input");
  cmd->add_flag("--echo", a->echo, "Print every command before its answer");
  cmd->add_option("--camera", a->camera, "overview | side | top | follow")->capture_default_str();
  cmd->add_option("--size", a->size, "Window size WxH [pixels]")->capture_default_str();
  cmd->add_option("--screenshot", a->screenshot,
                  "Write the last frame here (PNG) when the session ends");
  cmd->callback([a] {
    const control::ModuleConfig config = system::load_config(a->config, a->field);
    {
      const system::System check(config);
    }  // the field and the models load (and fail) before the window
    check_camera(a->camera);
    viz::ViewerOptions o;
    o.realtime = a->realtime;
    o.echo = a->echo;
    o.script = a->script;
    o.screenshot = a->screenshot;
    o.camera = a->camera;
    const auto size = parse_size(a->size);
    o.width = size[0];
    o.height = size[1];
    viz::run_viewer(config, o);
  });
}

struct RenderArgs {
  std::string config, field, hole, model, camera = "overview", size = "640x480", out;
  std::optional<double> angle, speed;
  double fps = 30.0;
  bool no_video = false;
  // --course: the film of one hole of a round.
  std::string course, player = "robot", plant;
  std::uint64_t seed = 0;
  int budget = 6;
  bool camera_given = false;
};

/// render --course: plays the round up to the hole (game::play_round; the holes before it are
/// played too, so the hole is the one `play` plays with the seed) and films the hole's strokes.
void render_course(const RenderArgs& a) {
  const game::Course course = game::load_course(a.course);
  const std::size_t n = course.holes.size();
  std::uint64_t k = 1;
  if (!a.hole.empty()) {
    if (a.hole.find(',') != std::string::npos)
      throw InputError(
          fmt::format("--hole '{}': with --course, the hole's number 1..{}", a.hole, n));
    k = parse_unsigned("--hole", a.hole);
  }
  if (k < 1 || k > n)
    throw InputError(fmt::format("--hole {}: course {} has holes 1..{}", k, course.name, n));
  game::RoundOptions o;
  o.player = game::parse_player(a.player, "--player");
  o.seed = a.seed;
  o.calibration_putts = a.budget;
  o.validate();
  const std::string camera = a.camera_given ? a.camera : "top";
  check_camera(camera);
  const auto size = parse_size(a.size);
  viz::RenderOptions ro;
  ro.camera = camera;
  ro.width = size[0];
  ro.height = size[1];
  ro.fps = a.fps;
  ro.video = !a.no_video;
  if (ro.width % 2 != 0 || ro.height % 2 != 0)
    throw InputError(fmt::format("--size {}: width and height must be even (video)", a.size));
  if (!(a.fps >= 1.0 && a.fps <= 240.0))
    throw InputError(fmt::format("render: --fps {}: expected 1..240", a.fps));
  std::string stem = a.out;
  if (stem.size() > 4 && stem.substr(stem.size() - 4) == ".mp4") stem.resize(stem.size() - 4);
  viz::check_render_outputs(stem);
  const control::ModuleConfig config = system::load_config(a.config, "");
  const plant::Plant plant = load_plant_arg(a.plant);
  const game::CourseHole& ch = course.holes[k - 1];
  const system::System sys(config, ch.field);              // its ball world is drawn
  viz::GlWindow window(64, 64, false, "minigolf render");  // before the round: no display fails
  game::Course upto = course;
  upto.holes.resize(k);
  game::ImaginedCache cache;
  Progress progress(fmt::format("render {} hole {} ({})", course.name, k, a.player),
                    static_cast<int>(k));
  const game::RoundResult round = game::play_round(
      upto, config, plant, o, &cache,
      [&](int h, const game::StrokeRecord& s) { progress.update(h + (s.sunk ? 1 : 0)); });
  progress.finish();
  const game::HoleResult& hole = round.holes.back();
  const auto frames =
      viz::hole_film_frames(sys.ball_world().field(), hole, static_cast<int>(k), a.fps);
  const viz::RenderOutputs out = viz::render_hole_film(sys.ball_world(), hole, frames, ro, stem);
  fmt::print("hole {} of {} ({}, par {}), {}: {} stroke{}, {}\n", k, course.name, ch.field.name,
             ch.par, a.player, hole.strokes, hole.strokes == 1 ? "" : "s",
             hole.sunk ? "sunk" : "not sunk");
  fmt::print("filmstrip: {} ({} stroke{})\n", out.filmstrip.string(), hole.putts.size(),
             hole.putts.size() == 1 ? "" : "s");
  if (ro.video)
    fmt::print("video: {} ({} frames, {}x{}, {:g} fps{})\n", out.video.string(), out.frames,
               ro.width, ro.height, ro.fps,
               out.used_ffmpeg ? "" : "; PNG frames: ffmpeg not found");
}

void add_render(CLI::App& app) {
  auto a = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand(
      "render",
      "Render one hit off-screen (or, with --course, one hole of a round): an MP4 and a "
      "filmstrip");
  cmd->add_option("--config", a->config, "Module config YAML");
  cmd->add_option("--field", a->field, "Shipped field name or path (overrides the config)");
  cmd->add_option("--hole", a->hole,
                  "Hole centre X,Y [m] (default: the field's); with --course: the hole's number "
                  "K (default 1)");
  cmd->add_option("--angle", a->angle, "Hitting angle [rad]");
  cmd->add_option("--speed", a->speed, "Club speed [m/s]");
  cmd->add_option("--model", a->model, "Parameter model: angle and speed from `auto`");
  cmd->add_option(
      "--course", a->course,
      "Film one hole of a round on this course (shipped name or path): the ball's strokes");
  cmd->add_option("--player", a->player, "With --course: robot, oracle or greedy")
      ->check(CLI::IsMember({"robot", "oracle", "greedy"}))
      ->capture_default_str();
  cmd->add_option("--seed", a->seed, "With --course: the round's seed")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--budget", a->budget, "With --course: the robot's learning putts per field")
      ->check(CLI::Range(1, 50))
      ->capture_default_str();
  cmd->add_option("--plant", a->plant, std::string(kPlantHelp) + " (with --course)");
  cmd->add_option("--camera", a->camera,
                  "overview | side | top | follow (with --course, default top)")
      ->capture_default_str();
  cmd->add_option("--size", a->size, "Image size WxH [pixels], even")->capture_default_str();
  cmd->add_option("--fps", a->fps, "Video frames per simulated second")->capture_default_str();
  cmd->add_flag("--no-video", a->no_video, "The filmstrip only");
  cmd->add_option("-o,--output", a->out,
                  "Output stem: OUT.mp4 (or OUT-frames/) and OUT-filmstrip.png")
      ->required();
  cmd->callback([a, cmd] {
    const auto given = [&](std::initializer_list<const char*> names) {
      for (const char* n : names)
        if (cmd->count(n) > 0) return true;
      return false;
    };
    if (given({"--course"})) {
      if (given({"--field", "--angle", "--speed", "--model"}))
        throw InputError(
            "render --course: films the round's own strokes; --field, --angle, --speed and "
            "--model are for one hit");
      a->camera_given = given({"--camera"});
      render_course(*a);
      return;
    }
    if (given({"--player", "--seed", "--budget", "--plant"}))
      throw InputError("render: --player, --seed, --budget and --plant go with --course");
    const control::ModuleConfig config = system::load_config(a->config, a->field);
    check_camera(a->camera);
    const auto size = parse_size(a->size);
    viz::HitRequest req;
    if (!a->hole.empty()) req.hole = parse_vector<2>("--hole", a->hole);
    req.angle = a->angle;
    req.speed = a->speed;
    req.params_model = a->model;
    req.fps = a->fps;
    std::string stem = a->out;
    if (stem.size() > 4 && stem.substr(stem.size() - 4) == ".mp4") stem.resize(stem.size() - 4);
    viz::RenderOptions ro;
    ro.camera = a->camera;
    ro.width = size[0];
    ro.height = size[1];
    ro.fps = a->fps;
    ro.video = !a->no_video;
    if (ro.width % 2 != 0 || ro.height % 2 != 0)
      throw InputError(fmt::format("--size {}: width and height must be even (video)", a->size));
    viz::validate(req);
    viz::check_render_outputs(stem);
    const system::System sys(config);  // the field and the models load (and fail) before drawing
    if (req.angle) sys.check_request(*req.angle, *req.speed, "render");
    if (req.hole) field::check_hole_position(sys.field(), *req.hole);
    viz::GlWindow window(64, 64, false,
                         "minigolf render");  // before the run: no display fails fast
    const viz::HitRecording rec = viz::record_hit(config, req);
    const viz::RenderOutputs out = viz::render_hit(sys.arm_world(), rec, ro, stem);
    const auto& o = *rec.outcome;
    fmt::print(
        "hit: angle {:.4f} rad, speed {:.4f} m/s, hole ({:.3f}, {:.3f}): ball {} at ({:.3f}, "
        "{:.3f})\n",
        rec.angle, rec.speed, rec.hole[0], rec.hole[1], o.sunk ? "holed" : sim::to_string(o.end),
        o.rest_position[0], o.rest_position[1]);
    std::string stages;
    for (const auto& s : rec.stages)
      stages += fmt::format("{}{} {:.3f} s", stages.empty() ? "" : ", ", s.name, s.pose.time);
    fmt::print("filmstrip: {} ({})\n", out.filmstrip.string(), stages);
    if (ro.video)
      fmt::print("video: {} ({} frames, {}x{}, {:g} fps{})\n", out.video.string(), out.frames,
                 ro.width, ro.height, ro.fps,
                 out.used_ffmpeg ? "" : "; PNG frames: ffmpeg not found");
  });
}

}  // namespace

void add_viz_commands(CLI::App& app) {
  add_view(app);
  add_render(app);
}

}  // namespace mg::cli
