// identify_report [PLANTS] [PUTTS] [BALLS]: how well `minigolf identify` finds the world
// (docs/belief.md). Per field (flat, regular-hill, arctan, multiple-hills): PLANTS random plants
// (plant::random_plant(1..PLANTS), default 10) and the shipped stand-in data/plants/real-wam.yaml;
// on each the robot plays PUTTS identification putts (default 10) with the arm in the true world,
// perceived with the plant's vision error, and fits its belief from the first 1, 3, 5 and 10 of
// them (no prior: the survey with its spread); from the tee, or from balls drawn from the
// region BALLS (as `identify --balls`). Errors against the plant's keys: rolling
// resistance [%], each slope [mrad], club speed scale [%], launch angle bias [mrad]; the arm's
// also against its effective values (what the arm in the true world really does, noise off:
// friction and the club face add to the keys, and vary with the hit: their mean over the putts
// identified from), and the CPU of each belief update. Prints
// Markdown tables: median and worst over the random plants; the stand-in on its own.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "belief/belief.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "experiments/identify.hpp"
#include "plant/plant.hpp"
#include "system/system.hpp"

namespace {

using namespace mg;

struct Errors {
  double rho = 0, sx = 0, sy = 0, scale = 0, bias = 0, scale_eff = 0, bias_eff = 0, cpu = 0,
         predict_cpu = 0;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double worst(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }

/// What the arm in `plant`'s world really does on each of `hits`, noise off, against the robot's
/// model of the same hit: the club speed it reaches over the model's at the command, and the
/// launch angle minus the model's at the command times the plant's club speed scale (as the real
/// arm is asked for it). With joint friction both depend on the hit (its angle and speed): the
/// truth a constant bias and scale can be held to is their mean over the hits identified from.
std::vector<std::array<double, 2>> effective_arm(
    const control::ModuleConfig& config, const field::Field& field, plant::Plant plant,
    const std::vector<experiments::IdentifyHit>& hits) {
  plant.arm.torque_noise = 0.0;
  plant.perception.noise = 0.0;
  const system::System truth(config, field, plant);
  const system::System own(config, plant::true_field(field, plant));
  system::SystemData td(truth), od(own);
  std::vector<std::array<double, 2>> out;
  for (const experiments::IdentifyHit& h : hits) {
    const auto t = system::arm_hit(truth, td, h.situation, h.angle, h.speed);
    const auto m = system::arm_hit(own, od, h.situation, h.angle, h.speed);
    const double asked =
        std::clamp(h.speed * plant.arm.club_speed_scale, config.speed_min, config.speed_max);
    const auto ms = system::arm_hit(own, od, h.situation, h.angle, asked);
    out.push_back(
        {t.hit && m.hit ? t.club.speed / m.club.speed : NAN,
         t.hit && ms.hit ? std::remainder(t.launch.angle - ms.launch.angle, 2.0 * M_PI) : NAN});
  }
  return out;
}

/// The mean of the finite values among the first n.
double mean_of_first(const std::vector<std::array<double, 2>>& v, std::size_t n, std::size_t k) {
  double sum = 0.0;
  int count = 0;
  for (std::size_t i = 0; i < n && i < v.size(); ++i)
    if (std::isfinite(v[i][k])) {
      sum += v[i][k];
      ++count;
    }
  return count ? sum / count : NAN;
}

/// The spread (max - min) of the finite values.
double spread(const std::vector<std::array<double, 2>>& v, std::size_t k) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& x : v)
    if (std::isfinite(x[k])) {
      lo = std::min(lo, x[k]);
      hi = std::max(hi, x[k]);
    }
  return hi - lo;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace mg;
  const int plants = argc > 1 ? std::atoi(argv[1]) : 10;
  const int putts = argc > 2 ? std::atoi(argv[2]) : 10;
  const std::string balls = argc > 3 ? argv[3] : "";
  if (plants < 1 || putts < 1) {
    std::fprintf(stderr, "usage: identify_report [PLANTS >= 1] [PUTTS >= 1] [BALLS]\n");
    return 2;
  }
  std::vector<int> counts;
  for (int n : {1, 3, 5, 10})
    if (n <= putts) counts.push_back(n);
  const plant::Plant stand_in = plant::load_plant(data_dir() / "plants" / "real-wam.yaml");
  std::string stand_in_rows, spread_rows;
  const auto fmt_row = [](const std::string& name, double a, double b, double c, double d) {
    char row[256];
    std::snprintf(row, sizeof row, "| %s | %.2f / %.2f | %.1f / %.1f |\n", name.c_str(), a, b, c,
                  d);
    return std::string(row);
  };
  std::printf(
      "| field | putts | rolling resistance %% | slope x mrad | slope y mrad | club speed scale "
      "%% | launch bias mrad | (effective) scale %% / bias mrad | CPU per fit ms | model hits "
      "ms |\n|---|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string name : {"flat", "regular-hill", "arctan", "multiple-hills"}) {
    const control::ModuleConfig config = system::load_config("", name);
    std::vector<std::vector<Errors>> errors(counts.size());
    std::vector<std::array<double, 2>> spreads;
    for (int p = 0; p <= plants; ++p) {
      // p = 0: the stand-in; 1..plants: random plants.
      const plant::Plant plant =
          p == 0 ? stand_in : plant::random_plant(static_cast<std::uint64_t>(p));
      const system::System truth(config, plant);
      const field::Field& surveyed = truth.field();
      auto hits =
          experiments::plan_identification(truth, putts, balls, static_cast<std::uint64_t>(p));
      experiments::play_identification(truth, hits, plant.perception.noise,
                                       static_cast<std::uint64_t>(p));
      const auto eff = effective_arm(config, surveyed, plant, hits);
      const double rho = plant::true_rolling_resistance(surveyed, plant);
      for (std::size_t c = 0; c < counts.size(); ++c) {
        Errors e;
        try {
          const experiments::Identification id = experiments::identify_belief(
              config, surveyed, hits, static_cast<std::size_t>(counts[c]), std::nullopt);
          const plant::Plant& b = id.belief.estimate;
          e.rho = 100.0 * std::abs(*b.field.rolling_resistance / rho - 1.0);
          e.sx = 1e3 * std::abs(b.field.extra_slope[0] - plant.field.extra_slope[0]);
          e.sy = 1e3 * std::abs(b.field.extra_slope[1] - plant.field.extra_slope[1]);
          e.scale = 100.0 * std::abs(b.arm.club_speed_scale - plant.arm.club_speed_scale);
          e.bias = 1e3 * std::abs(b.arm.launch_angle_bias - plant.arm.launch_angle_bias);
          const auto n = static_cast<std::size_t>(counts[c]);
          e.scale_eff = 100.0 * std::abs(b.arm.club_speed_scale - mean_of_first(eff, n, 0));
          e.bias_eff = 1e3 * std::abs(b.arm.launch_angle_bias - mean_of_first(eff, n, 1));
          e.cpu = 1e3 * id.fit_cpu;
          e.predict_cpu = 1e3 * id.predict_cpu;
        } catch (const Error& ex) {
          std::fprintf(stderr, "%s plant %d, %d putts: %s\n", name.c_str(), p, counts[c],
                       ex.what());
          e.rho = e.sx = e.sy = e.scale = e.bias = e.scale_eff = e.bias_eff = INFINITY;
        }
        if (p == 0) {
          char row[512];
          std::snprintf(row, sizeof row,
                        "| %s | %d | %.2f | %.3f | %.3f | %.2f | %.2f | %.2f / %.2f | %.1f | %.0f "
                        "|\n",
                        name.c_str(), counts[c], e.rho, e.sx, e.sy, e.scale, e.bias, e.scale_eff,
                        e.bias_eff, e.cpu, e.predict_cpu);
          stand_in_rows += row;
        } else {
          errors[c].push_back(e);
        }
      }
      spreads.push_back({100.0 * spread(eff, 0), 1e3 * spread(eff, 1)});
      std::fprintf(stderr, "%s: plant %d of %d done\n", name.c_str(), p, plants);
    }
    for (std::size_t c = 0; c < counts.size(); ++c) {
      const auto& v = errors[c];
      const auto col = [&](double Errors::*m) {
        std::vector<double> x;
        for (const Errors& e : v) x.push_back(e.*m);
        return std::array<double, 2>{median(x), worst(x)};
      };
      const auto rho = col(&Errors::rho), sx = col(&Errors::sx), sy = col(&Errors::sy),
                 sc = col(&Errors::scale), bi = col(&Errors::bias), sce = col(&Errors::scale_eff),
                 bie = col(&Errors::bias_eff), cpu = col(&Errors::cpu),
                 pc = col(&Errors::predict_cpu);
      std::printf(
          "| %s | %d | %.2f / %.2f | %.3f / %.3f | %.3f / %.3f | %.2f / %.2f | %.2f / %.2f | "
          "%.2f / %.2f; %.2f / %.2f | %.1f / %.1f | %.0f |\n",
          name.c_str(), counts[c], rho[0], rho[1], sx[0], sx[1], sy[0], sy[1], sc[0], sc[1], bi[0],
          bi[1], sce[0], sce[1], bie[0], bie[1], cpu[0], cpu[1], pc[0]);
    }
    std::vector<double> ss, bs;
    for (const auto& x : spreads) {
      ss.push_back(x[0]);
      bs.push_back(x[1]);
    }
    spread_rows += fmt_row(name, median(ss), worst(ss), median(bs), worst(bs));
    std::fflush(stdout);
  }
  std::printf(
      "\nThe stand-in (data/plants/real-wam.yaml):\n\n| field | putts | rolling resistance %% | "
      "slope x mrad | slope y mrad | club speed scale %% | launch bias mrad | (effective) scale "
      "%% / bias mrad | CPU per fit ms | model hits ms |\n|---|---|---|---|---|---|---|---|---|---"
      "|\n%s",
      stand_in_rows.c_str());
  std::printf(
      "\nThe arm's effective club speed scale and launch error vary over the plan's hits (noise "
      "off; max - min over the %d hits, median / worst over the plants and the stand-in):\n\n| "
      "field | club speed scale %% | launch error mrad |\n|---|---|---|\n%s",
      putts, spread_rows.c_str());
  return 0;
}
