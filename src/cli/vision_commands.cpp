// vision-sim: plays the stereo-vision system of normal mode. Publishes ball and hole positions
// (a ball at rest on the tee, or a simulated ball-only putt) as `minigolf-vision/1` datagrams.
//
//   minigolf vision-sim [--to HOST:PORT] [--rate HZ] [--duration S] [--field F] [--hole X,Y]
//                       [--angle RAD --speed M/S] [--noise M] [--latency S] [--dropout P]
//                       [--seed N] [--inject-bad N] [--fast]
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <thread>

#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "core/error.hpp"
#include "core/rng.hpp"
#include "field/field.hpp"
#include "perception/udp.hpp"
#include "perception/vision_message.hpp"
#include "sim/putt.hpp"

namespace mg::cli {
namespace {

enum class BadKind { kMalformed, kOutOfRange, kRepeated };

}  // namespace

void add_vision_commands(CLI::App& app) {
  struct Options {
    std::string to = "127.0.0.1:47001";
    double rate = 60.0;
    double duration = 2.0;
    std::string field = "flat";
    std::string hole;
    double angle = 0.0;
    double speed = 0.0;
    double noise = 0.0;
    double latency = 0.0;
    double dropout = 0.0;
    std::uint64_t seed = 1;
    std::uint64_t inject_bad = 0;
    bool fast = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "vision-sim", "Publish simulated ball and hole positions over UDP (minigolf-vision/1)");
  cmd->add_option("--to", o->to, "Destination HOST:PORT")->capture_default_str();
  cmd->add_option("--rate", o->rate, "Messages per second [Hz], [0.001, 1000]")
      ->check(finite_number(1e-3, 1000.0))
      ->capture_default_str();
  cmd->add_option("--duration", o->duration, "Publish for this long [s], [0.001, 3600]")
      ->check(finite_number(1e-3, 3600.0))
      ->capture_default_str();
  cmd->add_option("--field", o->field, "Shipped field name or path to a field file")
      ->capture_default_str();
  cmd->add_option("--hole", o->hole, "Hole centre X,Y [m] (default: the field's)");
  CLI::Option* angle_opt =
      cmd->add_option("--angle", o->angle,
                      "Putt angle [rad]: publish a moving ball (needs --speed)")
          ->check(finite_number(-3.15, 3.15));
  CLI::Option* speed_opt =
      cmd->add_option("--speed", o->speed,
                      "Putt speed [m/s]: publish a moving ball (needs --angle)")
          ->check(finite_number(1e-3, 15.0));
  cmd->add_option("--noise", o->noise, "Gaussian noise std on every coordinate [m], [0, 0.5]")
      ->check(finite_number(0.0, 0.5))
      ->capture_default_str();
  cmd->add_option("--latency", o->latency, "Delay between capture and send [s], [0, 5]")
      ->check(finite_number(0.0, 5.0))
      ->capture_default_str();
  cmd->add_option("--dropout", o->dropout, "Probability of not sending a message, [0, 1]")
      ->check(finite_number(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "Seed for noise, dropout")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--inject-bad", o->inject_bad,
                  "Replace every Nth message by a malformed, out-of-range or repeated one, in "
                  "turn (0 = never)")
      ->check(unsigned_integer(1'000'000'000))
      ->capture_default_str();
  cmd->add_flag("--fast", o->fast, "Send as fast as possible (no pacing, no latency; for tests)");
  cmd->callback([o, angle_opt, speed_opt] {
    // Validate every number before touching the network or the simulator.
    const auto [host, port] = perception::parse_host_port("--to", o->to);
    const double rate = o->rate;
    const double duration = o->duration;
    const double noise = o->noise;
    const double latency = o->latency;
    const double dropout = o->dropout;
    const std::uint64_t seed = o->seed;
    const std::uint64_t inject_bad = o->inject_bad;
    if ((angle_opt->count() == 0) != (speed_opt->count() == 0))
      throw InputError("vision-sim: --angle and --speed go together (a moving ball); got only one");
    const bool moving = speed_opt->count() > 0;
    sim::PuttRequest request;
    if (moving) {
      request.angle = o->angle;
      request.speed = o->speed;
      request.max_duration = std::clamp(duration, 0.01, 600.0);
      request.record_interval = 0.005;
      request.validate();
    }
    const std::uint64_t count =
        std::max<std::uint64_t>(1, static_cast<std::uint64_t>(duration * rate + 1e-9));

    const sim::World world(field::load_field(o->field));
    const field::Field& f = world.field();
    const auto hole_xy = o->hole.empty() ? f.hole.position : parse_vector<2>("--hole", o->hole);
    field::check_hole_position(f, hole_xy);
    const std::array<double, 3> hole{hole_xy[0], hole_xy[1], f.height(hole_xy[0], hole_xy[1])};

    // The ball's true path: at rest on the tee, or a ball-only putt sampled every 5 ms.
    std::vector<sim::BallSample> path;
    if (moving) {
      auto data = world.make_data();
      path = simulate_putt(world, data.get(), hole_xy, request).trajectory;
    }
    if (path.empty())
      path.push_back(
          {0.0, f.tee[0], f.tee[1], f.height(f.tee[0], f.tee[1]) + f.ball.radius, 0, 0, 0});

    perception::UdpSender sender(host, port);
    Rng rng(seed);
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);

    std::uint64_t sent = 0, dropped = 0, failed = 0, last_good_seq = 0;
    std::uint64_t bad[3] = {0, 0, 0};
    std::size_t sample = 0;
    const auto start = std::chrono::steady_clock::now();
    for (std::uint64_t k = 0; k < count; ++k) {
      const double t = static_cast<double>(k) / rate;  // capture time [s], sender clock
      // Draw dropout for every message (also injected ones), so the sequence of draws and
      // hence the run is the same whatever --inject-bad says.
      const bool drop = uniform(rng) < dropout;
      while (sample + 1 < path.size() && path[sample + 1].t <= t) ++sample;
      perception::VisionMessage m;
      m.seq = k + 1;
      m.stamp = t;
      m.ball = {path[sample].x, path[sample].y, path[sample].z};
      m.hole = hole;
      if (noise > 0.0)
        for (int i = 0; i < 3; ++i) {
          m.ball[i] += noise * gauss(rng);
          m.hole[i] += noise * gauss(rng);
        }
      if (drop) {
        ++dropped;
        continue;
      }
      std::string datagram;
      const bool inject = inject_bad > 0 && (k + 1) % inject_bad == 0;
      if (inject) {
        const std::uint64_t n_bad = bad[0] + bad[1] + bad[2];
        auto kind = static_cast<BadKind>(n_bad % 3);
        // A repeat needs an earlier good message to repeat; before that, send garbage.
        if (kind == BadKind::kRepeated && last_good_seq == 0) kind = BadKind::kMalformed;
        ++bad[static_cast<int>(kind)];
        switch (kind) {
          case BadKind::kMalformed:
            datagram = R"({"format": "minigolf-vision/1", "seq": )" + std::to_string(m.seq) +
                       ", \"ball\": [";
            break;
          case BadKind::kOutOfRange:
            m.ball[0] = f.bounds[1] + 100.0;
            datagram = perception::format_vision_message(m);
            break;
          case BadKind::kRepeated:
            m.seq = last_good_seq;
            datagram = perception::format_vision_message(m);
            break;
        }
      } else {
        datagram = perception::format_vision_message(m);
        last_good_seq = m.seq;
      }
      if (!o->fast)
        std::this_thread::sleep_until(
            start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                        std::chrono::duration<double>(t + latency)));
      if (sender.send(datagram))
        ++sent;
      else
        ++failed;
    }
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    fmt::print(
        "vision-sim: sent {} to {}:{} in {:.2f} s ({}; {} messages at {} Hz), dropped {}, "
        "bad injected {} ({} malformed, {} out of range, {} repeated), send errors {}\n",
        sent, host, port, elapsed, moving ? "moving ball" : "ball at rest", count, rate, dropped,
        bad[0] + bad[1] + bad[2], bad[0], bad[1], bad[2], failed);
  });
}

}  // namespace mg::cli
