// The learners' view of a putt with cameras (docs/perception.md, needs a display: xvfb-run -a):
// arm putts from the tee towards the hole at a few club speeds and angles, each path seen by the
// cameras over the whole roll (system::perceive_putt) against the simulator's recorded path at
// the same instants: the horizontal position error along the roll (before and after the
// hand-off), the speed error, the launch read from the path, the frames lost, and the CPU of
// watching a path (the roll after the hand-off rendered and processed).
//
//   path_report [--field F] [--rig R] [--calibration C] [--speeds A,B,..] [--angles A,B,..]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <exception>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "system/observe.hpp"
#include "system/system.hpp"
#include "vision/camera_perception.hpp"

namespace {

double process_cpu() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

std::vector<double> numbers(const std::string& text) {
  std::vector<double> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
    }
    if (used == 0 || used != item.size() || !std::isfinite(v))
      throw std::invalid_argument("expected numbers separated by commas, got '" + text + "'");
    out.push_back(v);
  }
  return out;
}

/// The recorded sample pair around `t`, linearly interpolated (5 ms apart).
mg::sim::BallSample truth_at(const std::vector<mg::sim::BallSample>& path, double t) {
  const auto b = std::lower_bound(path.begin(), path.end(), t,
                                  [](const mg::sim::BallSample& s, double v) { return s.t < v; });
  if (b == path.begin()) return *b;
  if (b == path.end()) return path.back();
  const auto& a = *(b - 1);
  const double u = (t - a.t) / (b->t - a.t);
  const auto mix = [u](double p, double q) { return p + u * (q - p); };
  return {t,
          mix(a.x, b->x),
          mix(a.y, b->y),
          mix(a.z, b->z),
          mix(a.vx, b->vx),
          mix(a.vy, b->vy),
          mix(a.vz, b->vz)};
}

nlohmann::json stats_mm(std::vector<double> v, double scale = 1e3) {
  if (v.empty()) return nullptr;
  std::sort(v.begin(), v.end());
  double sq = 0;
  for (double x : v) sq += x * x;
  return {{"rms", scale * std::sqrt(sq / static_cast<double>(v.size()))},
          {"median", scale * v[v.size() / 2]},
          {"worst", scale * v.back()},
          {"n", v.size()}};
}

}  // namespace

int run(int argc, char** argv) {
  using namespace mg;
  std::string field = "flat", rig_name = "stereo", calibration, dump;
  std::vector<double> speeds{0.8, 1.2}, angles{-0.05, 0.05};
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--field")
      field = v;
    else if (a == "--rig")
      rig_name = v;
    else if (a == "--calibration")
      calibration = v;
    else if (a == "--speeds")
      speeds = numbers(v);
    else if (a == "--angles")
      angles = numbers(v);
    else if (a == "--dump")
      dump = v;
    else {
      std::fprintf(stderr, "path_report: unknown option %s\n", a.c_str());
      return 2;
    }
  }
  const vision::Cameras cameras = vision::load_cameras(rig_name, calibration);
  const system::System sys(system::load_config("", field), {}, {},
                           vision::camera_perception(cameras));
  system::SystemData data(sys);
  auto* source = dynamic_cast<vision::CameraPerceptionSource*>(data.perception.get());
  const auto hole = sys.field().hole.position;
  const double aim = std::atan2(hole[1] - sys.field().tee[1], hole[0] - sys.field().tee[0]);
  std::vector<double> before, after, speed_err, launch_angle, launch_speed, cpu_path, cpu_putt;
  nlohmann::json putts = nlohmann::json::array();
  long samples = 0, sunk = 0;
  for (double club : speeds)
    for (double da : angles) {
      control::FullPuttOptions o;
      o.record_interval = 0.005;
      const double c0 = process_cpu();
      control::FullPuttResult r = system::arm_putt(sys, data, hole, aim + da, club, o);
      const double c1 = process_cpu();
      if (!r.hit) continue;
      const auto truth = r.outcome.trajectory;
      const auto launch = r.launch;
      const long lost0 = source->roll_stats().lost, frames0 = source->roll_stats().frames;
      system::perceive_putt(sys, data, r);
      const double c2 = process_cpu();
      cpu_putt.push_back(c1 - c0);
      cpu_path.push_back(c2 - c1);
      const auto& seen = r.outcome.trajectory;
      if (!dump.empty()) {  // both paths as CSV (t, x, y, z, vx, vy, vz), one pair per putt
        const auto write = [&](const char* what, const std::vector<sim::BallSample>& path) {
          const std::string name =
              dump + "/" + field + "-" + std::to_string(putts.size()) + "-" + what + ".csv";
          if (FILE* f = std::fopen(name.c_str(), "w")) {
            for (const auto& s : path)
              std::fprintf(f, "%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f\n", s.t, s.x, s.y, s.z, s.vx,
                           s.vy, s.vz);
            std::fclose(f);
          }
        };
        write("seen", seen);
        write("truth", truth);
      }
      samples += static_cast<long>(seen.size());
      sunk += r.outcome.sunk ? 1 : 0;
      double worst = 0;
      for (const auto& s : seen) {
        const auto t = truth_at(truth, s.t);
        const double e = std::hypot(s.x - t.x, s.y - t.y);
        (s.t <= r.handoff_time ? before : after).push_back(e);
        worst = std::max(worst, e);
        speed_err.push_back(std::hypot(s.vx, s.vy) - std::hypot(t.vx, t.vy));
      }
      if (std::isfinite(r.launch.speed)) {
        launch_angle.push_back(std::remainder(r.launch.angle - launch.angle, 2 * M_PI));
        launch_speed.push_back(r.launch.speed / launch.speed - 1.0);
      }
      putts.push_back({{"club", club},
                       {"angle", aim + da},
                       {"sunk", r.outcome.sunk},
                       {"roll_s", truth.empty() ? 0.0 : truth.back().t},
                       {"handoff_s", r.handoff_time},
                       {"samples", seen.size()},
                       {"last_sample_s", seen.empty() ? 0.0 : seen.back().t},
                       {"roll_frames", source->roll_stats().frames - frames0},
                       {"roll_frames_lost", source->roll_stats().lost - lost0},
                       {"worst_mm", 1e3 * worst},
                       {"launch_seen", std::isfinite(r.launch.speed)},
                       {"cpu_putt_s", c1 - c0},
                       {"cpu_path_s", c2 - c1}});
    }
  const auto& rs = source->roll_stats();
  nlohmann::json out = {
      {"field", field},
      {"rig", cameras.rig.name},
      {"calibration", cameras.calibration.source},
      {"putts", putts},
      {"sunk", sunk},
      {"samples", samples},
      {"error_before_handoff_mm", stats_mm(before)},
      {"error_after_handoff_mm", stats_mm(after)},
      {"speed_error_mm_s", stats_mm(speed_err)},
      {"launch_angle_error_mrad", stats_mm(launch_angle)},
      {"launch_speed_error_percent", stats_mm(launch_speed, 100.0)},
      {"cpu_path_s", stats_mm(cpu_path, 1.0)},
      {"cpu_putt_s", stats_mm(cpu_putt, 1.0)},
      {"roll_frames", rs.frames},
      {"roll_frames_lost", rs.lost},
      {"roll_pipeline_ms_per_frame", rs.frames ? 1e3 * rs.cpu_seconds / rs.frames : 0.0},
      {"roll_render_ms_per_frame", rs.frames ? 1e3 * rs.render_seconds / rs.frames : 0.0}};
  std::printf("%s\n", out.dump(2).c_str());
  return 0;
}

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {  // bad numbers, files, rigs: one line, exit 2
    std::fprintf(stderr, "path_report: error: %s\n", e.what());
    return 2;
  }
}
