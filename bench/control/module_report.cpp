// Measures the full system on the flat field over a grid of hitting angles and club speeds and
// prints Markdown tables (docs/control.md, "Measured"): club speed vs command, launch
// speed / club speed, launch-angle bias at theta = 0 per speed, launch error after that bias,
// torque demand, joint speeds, time to the rest pose and to contact.
//
//   ./build/bench/control/module_report [hitting-model.json]
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "ds/hitting_model.hpp"
#include "field/field.hpp"
#include "sim_backend/full_system.hpp"

using namespace mg;

int main(int argc, char** argv) {
  const std::string model_path =
      argc > 1 ? argv[1] : std::string(MINIGOLF_SOURCE_DIR) + "/data/models/hitting-default.json";
  const sim::World world = control::make_world_with_arm(field::load_field("flat"));
  const control::ModuleConfig config;
  const control::ModuleModel model =
      control::make_module_model(world, ds::read_hitting_model(model_path), config);
  auto d = world.make_data();

  const std::vector<double> angles{-0.3, -0.15, 0.0, 0.15, 0.3, 0.45, 0.6};
  const std::vector<double> speeds{0.3, 0.6, 1.0, 1.6, 2.2, 2.6};
  std::vector<std::vector<control::FullPuttResult>> r(angles.size());
  for (std::size_t i = 0; i < angles.size(); ++i)
    for (double v : speeds) {
      r[i].push_back(control::full_system_putt(world, model, d.get(), {2.0, 0.0}, angles[i], v));
      std::fprintf(stderr, ".");
    }
  std::fprintf(stderr, "\n");
  const std::size_t i0 = 2;  // theta = 0

  auto header = [&](const char* title) {
    std::printf("\n%s\n\n| theta [rad] |", title);
    for (double v : speeds) std::printf(" %.1f m/s |", v);
    std::printf("\n|---|");
    for (std::size_t k = 0; k < speeds.size(); ++k) std::printf("---|");
    std::printf("\n");
  };
  auto table = [&](const char* title, auto cell) {
    header(title);
    for (std::size_t i = 0; i < angles.size(); ++i) {
      std::printf("| %+.2f |", angles[i]);
      for (std::size_t k = 0; k < speeds.size(); ++k) {
        const auto& x = r[i][k];
        if (!x.hit)
          std::printf(" no hit |");
        else
          std::printf(" %s |", cell(x, i, k).c_str());
      }
      std::printf("\n");
    }
  };
  auto fmt = [](const char* f, double a) {
    char b[64];
    std::snprintf(b, sizeof b, f, a);
    return std::string(b);
  };
  table("Club speed at impact / command",
        [&](const control::FullPuttResult& x, std::size_t, std::size_t k) {
          return fmt("%.3f", x.club.speed / speeds[k]);
        });
  table("Ball launch speed / club speed",
        [&](const control::FullPuttResult& x, std::size_t, std::size_t) {
          return fmt("%.3f", x.launch.speed / x.club.speed);
        });
  std::printf("\nLaunch-angle bias at theta = 0 [rad]:");
  for (std::size_t k = 0; k < speeds.size(); ++k)
    std::printf(" %.1f m/s %+.4f%s", speeds[k], r[i0][k].launch.angle,
                k + 1 < speeds.size() ? "," : "\n");
  table("Launch-angle error after the bias at theta = 0 [rad]",
        [&](const control::FullPuttResult& x, std::size_t i, std::size_t k) {
          return fmt("%+.4f", x.launch.angle - angles[i] - r[i0][k].launch.angle);
        });
  table("Raw torque demand / limit (the clamp keeps the applied torque <= 1)",
        [&](const control::FullPuttResult& x, std::size_t, std::size_t) {
          return fmt("%.2f", x.max_raw_torque_ratio) +
                 (x.max_torque_ratio > 1.0 + 1e-12 ? " (!)" : "");
        });
  table("Max measured joint speed / limit (commanded <= 1 always)",
        [&](const control::FullPuttResult& x, std::size_t, std::size_t) {
          return fmt("%.2f", x.max_velocity_ratio) +
                 (x.max_command_velocity_ratio > 1.0 + 1e-9 ? " (!)" : "") +
                 (x.faulted ? " fault" : "");
        });
  table("Time to the rest pose / request to contact [s]",
        [&](const control::FullPuttResult& x, std::size_t, std::size_t) {
          return fmt("%.2f", x.rest_time) + " / " + fmt("%.2f", x.hit_time);
        });
  int single = 0, total = 0;
  for (const auto& row : r)
    for (const auto& x : row) {
      ++total;
      single += x.club_ball_touches == 1;
    }
  std::printf("\nThe club touched the ball exactly once in %d of %d putts\n", single, total);
  double p99 = 0, worst = 0;
  int overruns = 0, ticks = 0;
  for (const auto& row : r)
    for (const auto& x : row) {
      p99 = std::max(p99, x.timing.core_update_p99_us);
      worst = std::max(worst, x.timing.core_update_max_us);
      overruns += x.timing.overruns;
      ticks += x.timing.ticks;
    }
  std::printf(
      "\nCore update over %d ticks: worst per-putt p99 %.1f us, max %.1f us, %d over the 2 ms "
      "budget\n",
      ticks, p99, worst, overruns);
}
