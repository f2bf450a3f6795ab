// vision calibrate | vision measure: the stereo cameras (docs/perception.md "Cameras"; the
// stereo computer, vision-cam, is vision_cam_command.cpp).
//
//   minigolf vision calibrate [--rig R] [--field F] [--views N] [--seed S] [--frames DIR] -o FILE
//   minigolf vision measure [--field F] [--ball X,Y] [--hole X,Y] [--rig R] [--calibration C]
//                           [--plant P] [--grid NX,NY] [--bump CAMERA:DX,DY,DZ,YAW,PITCH]
//                           [--frames DIR] [--json]
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <thread>

#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "perception/udp.hpp"
#include "perception/vision_message.hpp"
#include "sim/putt.hpp"
#include "system/system.hpp"
#include "vision/calibrate.hpp"
#include "vision/calibration.hpp"
#include "vision/rig.hpp"
#include "vision/still_scene.hpp"
#include "vision/video.hpp"
#include "viz/renderer.hpp"

namespace mg::cli {
namespace {

nlohmann::json vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json sighting_json(const vision::Sighting& s, const Eigen::Vector3d& truth) {
  nlohmann::json j;
  j["seen"] = s.views > 0 ? vec(s.point) : nlohmann::json();
  j["true"] = vec(truth);
  j["error"] = s.views > 0 ? nlohmann::json((s.point - truth).norm()) : nlohmann::json();
  j["views"] = s.views;
  return j;
}

struct Stats {
  std::vector<double> v;
  nlohmann::json json(double scale) const {
    if (v.empty()) return nullptr;
    std::vector<double> s = v;
    std::sort(s.begin(), s.end());
    double sq = 0;
    for (double x : s) sq += x * x;
    return {{"rms", scale * std::sqrt(sq / static_cast<double>(s.size()))},
            {"median", scale * s[s.size() / 2]},
            {"worst", scale * s.back()},
            {"n", s.size()}};
  }
};

}  // namespace

void add_camera_commands(CLI::App& app) {
  CLI::App* group = app.add_subcommand(
      "vision", "The stereo cameras: calibrate the rig, measure ball and hole from pixels");
  group->require_subcommand(1);

  // --- vision calibrate
  struct CalOptions {
    std::string rig = vision::kDefaultRig;
    std::string field = "flat";
    std::string output;
    std::string frames;
    int views = 20;
    std::uint64_t seed = 1;
  };
  auto c = std::make_shared<CalOptions>();
  CLI::App* cal = group->add_subcommand(
      "calibrate",
      "Calibrate the rig from rendered checkerboards (OpenCV); write the robot's belief of it");
  cal->add_option("--rig", c->rig, "Rig file or shipped rig name")->capture_default_str();
  cal->add_option("--field", c->field, "Field the lane board is laid on")->capture_default_str();
  cal->add_option("--views", c->views, "Board poses seen by every camera, 15..200")
      ->check(CLI::Range(15, 200))
      ->capture_default_str();
  cal->add_option("--seed", c->seed, "Seed of the board poses")
      ->check(unsigned_integer())
      ->capture_default_str();
  cal->add_option("--frames", c->frames, "Write the lane board's frames here (PNG)");
  cal->add_option("-o,--output", c->output, "Calibration file to write (YAML)")
      ->required()
      ->check(output_file());
  cal->callback([c] {
    const vision::Rig rig = vision::load_rig(c->rig);
    const system::System sys(system::load_config("", c->field));
    vision::check_rig_sees_field(rig, sys.arm_world().field());
    viz::GlWindow window(64, 64, false, "minigolf vision");
    vision::RigRenderer renderer(sys.arm_world(), rig);
    auto d = sys.arm_world().make_data();
    const auto& f = sys.arm_world().field();
    vision::place_still_scene(sys.arm_world(), d.get(), f.tee, f.hole.position);
    vision::CalibrateOptions o;
    o.views = c->views;
    o.seed = c->seed;
    const vision::CalibrateReport rep = vision::calibrate_rig(renderer, d.get(), rig, o);
    if (!c->frames.empty()) {
      const auto dir = frames_dir(c->frames);
      for (int i = 0; i < renderer.size(); ++i)
        viz::write_png(
            dir / fmt::format("lane-board-{}.png", rig.cameras[static_cast<std::size_t>(i)].name),
            renderer.render(i, d.get(), &rep.field_board));
    }
    write_file_atomic(c->output, vision::format_calibration(rep.calibration));
    const auto& cal = rep.calibration;
    std::string per;
    for (std::size_t i = 0; i < cal.cameras.size(); ++i) {
      const auto truth = vision::camera_from_spec(rig.cameras[i]);
      per += fmt::format(
          "  {}: RMS {:.3f} px, fx {:.2f} (true {:.2f}), cx {:.2f} (true {:.2f}), k1 {:.4f} "
          "(true {:.4f}), position off by {:.1f} mm, lane board RMS {:.3f} px\n",
          cal.cameras[i].name, cal.rms_px[i], cal.cameras[i].fx, truth.fx, cal.cameras[i].cx,
          truth.cx, cal.cameras[i].dist[0], truth.dist[0],
          1000 * (cal.cameras[i].centre() - truth.centre()).norm(), rep.field_rms_px[i]);
    }
    fmt::print(
        "vision calibrate: rig {} ({}), {} board poses used ({} rendered, {} without every "
        "corner in every camera)\n{}  stereo RMS {:.3f} px, baseline {:.4f} m (stereoCalibrate) "
        "vs {:.4f} m (lane board)\nwrote {}\n",
        rig.name, rig.source, cal.views, rep.poses_tried, rep.poses_rejected, per,
        cal.stereo_rms_px, rep.stereo_baseline, rep.pnp_baseline, c->output);
  });

  // --- vision measure
  struct MeasureOptions {
    SystemArgs sys;
    std::string rig = vision::kDefaultRig;
    std::string calibration;
    std::string ball, hole, grid, frames, bump;
    bool json = false;
  };
  auto m = std::make_shared<MeasureOptions>();
  CLI::App* mea = group->add_subcommand(
      "measure", "One still scene: where the cameras see the ball and the hole, and the truth");
  mea->add_option("--field", m->sys.field, "Shipped field name or path to a field file")
      ->capture_default_str();
  mea->add_option("--plant", m->sys.plant, kPlantHelp);
  mea->add_option("--rig", m->rig, "Rig file or shipped rig name")->capture_default_str();
  mea->add_option("--calibration", m->calibration,
                  "Calibration file (vision calibrate); default: the rig's exact cameras");
  mea->add_option("--ball", m->ball, "Ball X,Y [m] (default: the tee)");
  mea->add_option("--hole", m->hole, "Hole X,Y [m] (default: the field's)");
  mea->add_option("--grid", m->grid,
                  "NX,NY: the ball over a grid of the lane (0.1 m inside its bounds); prints the "
                  "error statistics");
  mea->add_option("--frames", m->frames, "Write each camera's frame and its detections (PNG)");
  mea->add_option("--bump", m->bump,
                  "CAMERA:DX,DY,DZ,YAW,PITCH: that camera moved [m] and turned [deg] after "
                  "calibration (the truth renders it so; the belief is unchanged)");
  mea->add_flag("--json", m->json, "Print one JSON object");
  mea->callback([m] {
    const vision::Rig believed = vision::load_rig(m->rig);
    vision::Rig rig = believed;
    if (!m->bump.empty()) {
      const auto colon = m->bump.find(':');
      if (colon == std::string::npos)
        throw InputError(
            fmt::format("--bump: expected CAMERA:DX,DY,DZ,YAW,PITCH, got '{}'", one_line(m->bump)));
      const auto b = parse_vector<5>("--bump", m->bump.substr(colon + 1));
      rig = vision::bump_camera(rig, m->bump.substr(0, colon), {b[0], b[1], b[2]}, b[3], b[4]);
    }
    const system::System sys(system::load_config("", m->sys.field), load_plant_arg(m->sys.plant));
    const sim::World& world = sys.arm_world();
    const field::Field& f = world.field();
    vision::check_rig_sees_field(rig, f);
    vision::Calibration calib = m->calibration.empty() ? vision::exact_calibration(believed)
                                                       : vision::load_calibration(m->calibration);
    vision::check_calibration_matches(calib, rig);
    std::array<double, 2> hole =
        m->hole.empty() ? f.hole.position : parse_vector<2>("--hole", m->hole);
    field::check_hole_position(sys.field(), hole);
    hole = system::real_hole(sys, hole);
    std::vector<std::array<double, 2>> balls;
    if (!m->grid.empty()) {
      if (!m->ball.empty()) throw InputError("vision measure: --ball and --grid: give one");
      const auto g = parse_vector<2>("--grid", m->grid);
      if (g[0] != std::floor(g[0]) || g[1] != std::floor(g[1]) || g[0] < 2 || g[1] < 2 ||
          g[0] > 50 || g[1] > 50)
        throw InputError(fmt::format("--grid: expected two whole numbers 2..50, got {}", m->grid));
      const auto& b = f.bounds;
      for (int i = 0; i < static_cast<int>(g[0]); ++i)
        for (int j = 0; j < static_cast<int>(g[1]); ++j) {
          const std::array<double, 2> p{b[0] + 0.1 + (b[1] - b[0] - 0.2) * i / (g[0] - 1),
                                        b[2] + 0.1 + (b[3] - b[2] - 0.2) * j / (g[1] - 1)};
          try {
            field::check_ball_position(f, p, "ball");
          } catch (const InputError&) {
            continue;  // in the cup, an obstacle or off the lane
          }
          if (std::hypot(p[0] - hole[0], p[1] - hole[1]) < f.hole.diameter) continue;
          balls.push_back(p);
        }
    } else {
      const auto p = m->ball.empty() ? f.tee : parse_vector<2>("--ball", m->ball);
      field::check_ball_position(f, p, "--ball");
      balls.push_back(p);
    }
    const std::filesystem::path dir =
        m->frames.empty() ? std::filesystem::path() : frames_dir(m->frames);
    viz::GlWindow window(64, 64, false, "minigolf vision");
    vision::RigRenderer renderer(world, rig);
    const vision::StereoModel model(calib, sys.field());
    auto d = world.make_data();
    Stats ball_err, ball_stereo_err, hole_err, reproj, cpu, render;
    int seen = 0, stereo = 0;
    nlohmann::json single;
    for (std::size_t k = 0; k < balls.size(); ++k) {
      vision::place_still_scene(world, d.get(), balls[k], hole);
      vision::StereoData data(model);
      const vision::StillMeasurement s = vision::measure_still(renderer, model, data, d.get());
      if (s.ball.views > 0) ++seen, ball_err.v.push_back((s.ball.point - s.true_ball).norm());
      if (s.ball.views == 2)
        ++stereo, reproj.v.push_back(s.ball.reprojection_px),
            ball_stereo_err.v.push_back((s.ball.point - s.true_ball).norm());
      if (s.hole.views > 0) hole_err.v.push_back((s.hole.point - s.true_hole).norm());
      cpu.v.push_back(s.cpu_seconds);
      render.v.push_back(s.render_seconds / 2);
      if (!dir.empty())
        for (int i = 0; i < 2; ++i) {
          const auto& cam = renderer.truth(i);
          std::vector<Eigen::Vector2d> truth;
          for (const auto& p : {s.true_ball, s.true_hole})
            if (auto px = vision::project(cam, p)) truth.push_back(*px);
          const std::string stem =
              balls.size() > 1 ? fmt::format("{}-{:03d}", cam.name, k) : cam.name;
          viz::write_png(dir / (stem + ".png"), s.images[static_cast<std::size_t>(i)]);
          viz::write_png(dir / (stem + "-detections.png"),
                         vision::annotate(s.images[static_cast<std::size_t>(i)],
                                          s.ball.blobs[static_cast<std::size_t>(i)],
                                          s.hole.blobs[static_cast<std::size_t>(i)], truth));
        }
      if (balls.size() == 1) {
        single["ball"] = sighting_json(s.ball, s.true_ball);
        single["hole"] = sighting_json(s.hole, s.true_hole);
        single["reprojection_px"] =
            s.ball.views == 2 ? nlohmann::json(s.ball.reprojection_px) : nlohmann::json();
        single["cpu_ms"] = 1000 * s.cpu_seconds;
        // Per camera: the detections' centres and the truth's projections [pixels].
        for (int i = 0; i < 2; ++i) {
          const auto& cam = renderer.truth(i);
          const auto k2 = static_cast<std::size_t>(i);
          const auto px = [](const Eigen::Vector2d& p) { return nlohmann::json{p.x(), p.y()}; };
          const auto tb = vision::project(cam, s.true_ball), th = vision::project(cam, s.true_hole);
          single["cameras"].push_back(
              {{"name", cam.name},
               {"ball_px", s.ball.blobs[k2].found ? px(s.ball.blobs[k2].pixel) : nlohmann::json()},
               {"ball_true_px", tb ? px(*tb) : nlohmann::json()},
               {"hole_px", s.hole.blobs[k2].found ? px(s.hole.blobs[k2].pixel) : nlohmann::json()},
               {"hole_true_px", th ? px(*th) : nlohmann::json()}});
        }
      }
    }
    nlohmann::json out;
    if (balls.size() == 1) {
      out = single;
    } else {
      out["positions"] = balls.size();
      out["ball_seen"] = seen;
      out["ball_stereo"] = stereo;
      out["ball_error_mm"] = ball_err.json(1000);
      out["ball_error_stereo_mm"] = ball_stereo_err.json(1000);  // triangulated only
      out["hole_error_mm"] = hole_err.json(1000);
      out["reprojection_px"] = reproj.json(1);
      out["cpu_ms_per_pair"] = cpu.json(1000);
      out["render_ms_per_frame"] = render.json(1000);
    }
    out["rig"] = rig.name;
    out["calibration"] = calib.source;
    out["field"] = f.name;
    if (m->json) {
      fmt::print("{}\n", out.dump());
      return;
    }
    fmt::print("{}\n", out.dump(2));
  });
}

}  // namespace mg::cli
