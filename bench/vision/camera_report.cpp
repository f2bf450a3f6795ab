// The cameras' figures for docs/perception.md "Cameras" (needs a display: xvfb-run -a):
//   static: `minigolf vision measure --grid` (not here);
//   rolling: ball-only putts on a field, rendered at the rig's rate; the error of the raw
//            triangulation and of the filter's estimate against the simulator, per frame;
//   cpu:     detection + triangulation + filter per stereo pair at the rig's size, rendering
//            excluded (the same pair processed again and again), and the render time per frame.
//
//   camera_report [--field F] [--rig R] [--calibration C] [--putts N] [--repeat N]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/putt.hpp"
#include "system/system.hpp"
#include "vision/calibration.hpp"
#include "vision/rig_renderer.hpp"
#include "vision/stereo_pipeline.hpp"
#include "vision/still_scene.hpp"
#include "viz/renderer.hpp"

namespace {

double thread_cpu() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

nlohmann::json stats_mm(std::vector<double> v) {
  if (v.empty()) return nullptr;
  std::sort(v.begin(), v.end());
  double sq = 0;
  for (double x : v) sq += x * x;
  return {{"rms", 1e3 * std::sqrt(sq / static_cast<double>(v.size()))},
          {"median", 1e3 * v[v.size() / 2]},
          {"worst", 1e3 * v.back()},
          {"n", v.size()}};
}

}  // namespace

int main(int argc, char** argv) {
  using namespace mg;
  std::string field = "flat", rig_name = "stereo", calibration;
  int putts = 5, repeat = 500;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--field")
      field = v;
    else if (a == "--rig")
      rig_name = v;
    else if (a == "--calibration")
      calibration = v;
    else if (a == "--putts")
      putts = std::stoi(v);
    else if (a == "--repeat")
      repeat = std::stoi(v);
    else {
      std::fprintf(stderr, "camera_report: unknown option %s\n", a.c_str());
      return 2;
    }
  }
  const vision::Rig rig = vision::load_rig(rig_name);
  const system::System sys(system::load_config("", field));
  const vision::Calibration calib =
      calibration.empty() ? vision::exact_calibration(rig) : vision::load_calibration(calibration);
  const vision::StereoModel model(calib, sys.field());
  viz::GlWindow window(64, 64, false, "camera_report");
  const sim::World& world = sys.ball_world();
  vision::RigRenderer renderer(world, rig);
  auto d = world.make_data();
  const field::Field& f = world.field();
  const double period = 1.0 / rig.cameras[0].rate_hz;

  // Rolling: putts from the tee towards the hole, speeds spread over a sinking range.
  std::vector<double> raw, filtered, raw_moving, filtered_moving;
  long frames = 0, stereo = 0, mono = 0, lost = 0;
  double render_s = 0;
  const double aim = std::atan2(f.hole.position[1] - f.tee[1], f.hole.position[0] - f.tee[0]);
  for (int k = 0; k < putts; ++k) {
    sim::PuttRequest req;
    req.angle = aim + 0.04 * (k - putts / 2);
    req.speed = 1.2 + 0.25 * k;
    sim::start_putt(world, d.get(), f.hole.position, req);
    sim::OutcomeTracker tracker(world, d.get(), {});
    vision::StereoData data(model);
    double next = 0.0;
    const double t0 = d->time;
    for (int step = 0; step < 20000; ++step) {
      if (d->time - t0 >= next - 1e-12) {
        next += period;
        const auto r0 = std::chrono::steady_clock::now();
        const viz::Image* images[2] = {&renderer.render(0, d.get()), &renderer.render(1, d.get())};
        render_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - r0).count();
        vision::stereo_frame(model, data, images, d->time);
        ++frames;
        const int qb = world.ids().ball_qpos;
        const Eigen::Vector3d truth(d->qpos[qb], d->qpos[qb + 1], d->qpos[qb + 2]);
        const double speed =
            std::hypot(d->qvel[world.ids().ball_dof], d->qvel[world.ids().ball_dof + 1]);
        const auto& s = data.last_ball;
        (s.views == 2 ? stereo : s.views == 1 ? mono : lost)++;
        if (truth.z() < f.height(truth.x(), truth.y())) break;  // in the cup
        if (s.views == 2) {
          raw.push_back((s.point - truth).norm());
          if (speed > 0.05) raw_moving.push_back((s.point - truth).norm());
        }
        const auto e = vision::stereo_estimate(model, data, d->time);
        if (e.ball_fresh) {
          const double err = std::hypot(e.ball.x() - truth.x(), e.ball.y() - truth.y());
          filtered.push_back(err);
          if (speed > 0.05) filtered_moving.push_back(err);
        }
      }
      world.step(d.get());
      if (tracker.update(d.get())) break;
    }
  }

  // CPU per stereo pair: a still scene at the rig's size, processed `repeat` times.
  auto ad = sys.arm_world().make_data();
  vision::RigRenderer arm_renderer(sys.arm_world(), rig);
  vision::place_still_scene(sys.arm_world(), ad.get(), {1.0, 0.2}, f.hole.position);
  const viz::Image a = arm_renderer.render(0, ad.get()), b = arm_renderer.render(1, ad.get());
  const viz::Image* images[2] = {&a, &b};
  vision::StereoData data(model);
  vision::stereo_frame(model, data, images, 0.0);  // the first frame sizes the buffers
  const double c0 = thread_cpu();
  for (int i = 1; i <= repeat; ++i) vision::stereo_frame(model, data, images, i * period);
  const double per_pair = (thread_cpu() - c0) / repeat;

  nlohmann::json out = {{"field", f.name},
                        {"rig", rig.name},
                        {"calibration", calib.source},
                        {"size", {rig.cameras[0].width, rig.cameras[0].height}},
                        {"rolling",
                         {{"putts", putts},
                          {"frames", frames},
                          {"ball_stereo", stereo},
                          {"ball_mono", mono},
                          {"ball_lost", lost},
                          {"raw_error_mm", stats_mm(raw)},
                          {"filtered_error_mm", stats_mm(filtered)},
                          {"raw_error_moving_mm", stats_mm(raw_moving)},
                          {"filtered_error_moving_mm", stats_mm(filtered_moving)}}},
                        {"cpu_ms_per_pair", 1e3 * per_pair},
                        {"pairs_per_second_per_core", 1.0 / per_pair},
                        {"render_ms_per_frame", frames ? 1e3 * render_s / (2.0 * frames) : 0.0}};
  std::printf("%s\n", out.dump(2).c_str());
  return 0;
}
