// The planning path against MuJoCo: random ball-only putts on every shipped field through
// `fast_putt` and `simulate_putt`, their agreement and speed as a Markdown table (the table of
// docs/physics.md, "The planning path", comes from this program).
//
// Random putts: start uniform on the lane (the ball inside the borders, not overlapping an
// obstacle, at least 0.1 m from the hole), angle uniform in [-pi, pi], speed uniform in
// [0.3, 4.0] m/s, the field's hole. Agreement: both sunk, or both left the lane, or neither sunk
// nor left the lane with rest positions within 1 cm. Speeds are CPU time of this thread.
//
// --chaos adds a table: agreement without the replay, and MuJoCo's with itself for a start moved
// by 1e-13 m.
//
// Run: ./build/bench/sim/fast_putt_report [--putts N] [--fields a,b] [--seed S] [--chaos]
//        [--replay-airtime S] [--replay-wall-hits N] [--calm-speed V] [--verbose]
// (the last three: FastPuttOptions; --replay-airtime 0: never replay)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/rng.hpp"
#include "field/field.hpp"
#include "sim/fast_putt.hpp"

namespace {

using namespace mg;
constexpr double kPi = 3.14159265358979323846;
constexpr double kAgreeDistance = 0.01;  // [m]

struct Options {
  int putts = 10000;
  std::vector<std::string> fields;
  std::uint64_t seed = 20261205;
  bool verbose = false;
  bool chaos = false;  // the second table
  sim::FastPuttOptions fast;
};

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

std::vector<sim::PuttRequest> random_putts(const field::Field& f, int n, Rng& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double r = f.ball.radius;
  const auto& b = f.bounds;
  std::vector<sim::PuttRequest> putts;
  while (static_cast<int>(putts.size()) < n) {
    const std::array<double, 2> p{b[0] + r + (b[1] - b[0] - 2 * r) * u(rng),
                                  b[2] + r + (b[3] - b[2] - 2 * r) * u(rng)};
    const double angle = -kPi + 2.0 * kPi * u(rng), speed = 0.3 + 3.7 * u(rng);
    if (std::hypot(p[0] - f.hole.position[0], p[1] - f.hole.position[1]) < 0.1) continue;
    if (std::any_of(f.obstacles.begin(), f.obstacles.end(),
                    [&](const field::Obstacle& o) { return o.distance(p) <= r; }))
      continue;
    sim::PuttRequest q;
    q.start = p;
    q.angle = angle;
    q.speed = speed;
    putts.push_back(q);
  }
  return putts;
}

struct Row {
  int putts = 0, agree = 0, flips = 0;
  double max_rest_mm = 0.0, median_rest_mm = 0.0;
  double fast_per_s = 0.0, mujoco_per_s = 0.0, mean_mujoco_steps = 0.0;
};

// A stream per field name (FNV-1a), so a field's putts do not depend on the other fields listed.
std::uint64_t field_stream(const std::string& name) {
  std::uint64_t h = 14695981039346656037ULL;
  for (const char c : name) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ULL;
  return h;
}

bool left(const sim::PuttOutcome& o) { return o.end == sim::PuttEnd::kLeftLane; }

// Both sunk, both off the lane, or neither with rest positions within 1 cm (appended to
// `rest_mm` [mm] when not null).
bool agree(const sim::PuttOutcome& a, const sim::PuttOutcome& b, std::vector<double>* rest_mm) {
  if (a.sunk != b.sunk) return false;
  if (a.sunk) return true;
  if (left(a) || left(b)) return left(a) && left(b);
  const double diff =
      std::hypot(a.rest_position[0] - b.rest_position[0], a.rest_position[1] - b.rest_position[1]);
  if (rest_mm != nullptr) rest_mm->push_back(1000.0 * diff);
  return diff <= kAgreeDistance;
}

Row compare(const std::string& name, const Options& opt) {
  const sim::World world(field::load_field(name));
  auto d = world.make_data();
  Rng rng(derive_seed(opt.seed, field_stream(name)));
  const auto putts = random_putts(world.field(), opt.putts, rng);
  const auto hole = world.field().hole.position;
  std::vector<sim::PuttOutcome> fast, slow;
  fast.reserve(putts.size());
  slow.reserve(putts.size());
  double t0 = cpu_seconds();
  for (const auto& q : putts) fast.push_back(sim::fast_putt(world, d.get(), hole, q, {}, opt.fast));
  const double fast_s = cpu_seconds() - t0;
  t0 = cpu_seconds();
  for (const auto& q : putts) slow.push_back(sim::simulate_putt(world, d.get(), hole, q));
  const double slow_s = cpu_seconds() - t0;

  Row row;
  row.putts = static_cast<int>(putts.size());
  std::vector<double> rest_mm;
  long mujoco_steps = 0;
  for (std::size_t i = 0; i < putts.size(); ++i) {
    const auto &a = fast[i], &b = slow[i];
    mujoco_steps += a.steps;
    const bool agreed = agree(a, b, &rest_mm);
    row.flips += a.sunk != b.sunk;
    row.agree += agreed;
    if (!agreed && opt.verbose)
      fmt::print(stderr,
                 "{} putt {}: start {:.17g} {:.17g} angle {:.17g} speed {:.17g}: fast {} ({:.4f}, "
                 "{:.4f}), MuJoCo {} ({:.4f}, {:.4f})\n",
                 name, i, (*putts[i].start)[0], (*putts[i].start)[1], putts[i].angle,
                 putts[i].speed, sim::to_string(a.end), a.rest_position[0], a.rest_position[1],
                 sim::to_string(b.end), b.rest_position[0], b.rest_position[1]);
  }
  std::sort(rest_mm.begin(), rest_mm.end());
  if (!rest_mm.empty()) {
    row.max_rest_mm = rest_mm.back();
    row.median_rest_mm = rest_mm[rest_mm.size() / 2];
  }
  row.fast_per_s = row.putts / fast_s;
  row.mujoco_per_s = row.putts / slow_s;
  row.mean_mujoco_steps = static_cast<double>(mujoco_steps) / row.putts;
  return row;
}

// MuJoCo's own chaos: agreement without the replay, and of MuJoCo with itself when the start
// moves by 1e-13 m (what any path not bit-identical to MuJoCo meets).
void chaos_row(const std::string& name, const Options& opt) {
  const sim::World world(field::load_field(name));
  auto d = world.make_data();
  Rng rng(derive_seed(opt.seed, field_stream(name)));
  const auto putts = random_putts(world.field(), opt.putts, rng);
  const auto hole = world.field().hole.position;
  sim::FastPuttOptions no_replay = opt.fast;
  no_replay.replay_airtime = 0.0;
  int fast_agree = 0, self_agree = 0;
  for (const auto& q : putts) {
    const sim::PuttOutcome ref = sim::simulate_putt(world, d.get(), hole, q);
    sim::PuttRequest moved = q;
    (*moved.start)[0] += 1e-13;
    fast_agree += agree(sim::fast_putt(world, d.get(), hole, q, {}, no_replay), ref, nullptr);
    self_agree += agree(sim::simulate_putt(world, d.get(), hole, moved), ref, nullptr);
  }
  fmt::print("| {} | {} | {:.2f} | {:.2f} |\n", name, putts.size(), 100.0 * fast_agree / opt.putts,
             100.0 * self_agree / opt.putts);
  std::fflush(stdout);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--putts" && has_value) {
      o.putts = std::atoi(argv[++i]);
    } else if (a == "--seed" && has_value) {
      o.seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (a == "--fields" && has_value) {
      std::string list = argv[++i];
      for (std::size_t p = 0; p != std::string::npos;) {
        const std::size_t q = list.find(',', p);
        o.fields.push_back(list.substr(p, q == std::string::npos ? q : q - p));
        p = q == std::string::npos ? q : q + 1;
      }
    } else if (a == "--replay-airtime" && has_value) {
      o.fast.replay_airtime = std::atof(argv[++i]);
    } else if (a == "--replay-wall-hits" && has_value) {
      o.fast.replay_wall_hits = std::atoi(argv[++i]);
    } else if (a == "--calm-speed" && has_value) {
      o.fast.calm_speed = std::atof(argv[++i]);
    } else if (a == "--chaos") {
      o.chaos = true;
    } else if (a == "--verbose") {
      o.verbose = true;
    } else {
      std::fprintf(stderr,
                   "usage: fast_putt_report [--putts N] [--fields a,b] [--seed S] "
                   "[--replay-airtime S] [--replay-wall-hits N] [--calm-speed V] [--chaos] "
                   "[--verbose]\n");
      std::exit(2);
    }
  }
  if (o.putts < 1) {
    std::fprintf(stderr, "fast_putt_report: --putts: expected >= 1\n");
    std::exit(2);
  }
  if (o.fields.empty()) o.fields = field::list_shipped_fields();
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  const Options opt = parse(argc, argv);
  fmt::print("Random ball-only putts (seed {}), `fast_putt` vs `simulate_putt`:\n\n", opt.seed);
  fmt::print(
      "| field | putts | agreement % | outcome flips | max / median rest difference [mm] | "
      "fast putts/s/core | MuJoCo putts/s/core | mean MuJoCo steps per fast putt |\n");
  fmt::print("|---|---|---|---|---|---|---|---|\n");
  for (std::size_t i = 0; i < opt.fields.size(); ++i) {
    const Row r = compare(opt.fields[i], opt);
    fmt::print("| {} | {} | {:.2f} | {} | {:.3g} / {:.3g} | {:.0f} | {:.0f} | {:.0f} |\n",
               opt.fields[i], r.putts, 100.0 * r.agree / r.putts, r.flips, r.max_rest_mm,
               r.median_rest_mm, r.fast_per_s, r.mujoco_per_s, r.mean_mujoco_steps);
    std::fflush(stdout);
  }
  if (!opt.chaos) return 0;
  fmt::print(
      "\nChaos: `fast_putt` without the replay, and `simulate_putt` with the start moved by "
      "1e-13 m, against `simulate_putt`:\n\n");
  fmt::print("| field | putts | agreement without replay % | MuJoCo with itself % |\n");
  fmt::print("|---|---|---|---|\n");
  for (const auto& name : opt.fields) chaos_row(name, opt);
  return 0;
}
