// plant random --seed S -o FILE   a plant drawn from the documented realistic ranges
// plant show FILE [--field F]     what a plant changes, resolved over a field
#include <cmath>
#include <memory>

#include <fmt/format.h>

#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "core/io.hpp"
#include "field/field.hpp"
#include "plant/plant.hpp"

namespace mg::cli {

void add_plant_commands(CLI::App& app) {
  CLI::App* plant =
      app.add_subcommand("plant", "Plants: the world as it really is (docs/reality.md)");
  plant->require_subcommand(1);

  struct RandomArgs {
    std::uint64_t seed = 1;
    std::string out;
  };
  auto r = std::make_shared<RandomArgs>();
  CLI::App* random = plant->add_subcommand(
      "random",
      "Write a plant drawn from the realistic ranges (grass +-20 %, slope error +-0.5 %, ...)");
  random->add_option("--seed", r->seed, "Seed of the draw")
      ->check(unsigned_integer())
      ->capture_default_str();
  random->add_option("-o,--output", r->out, "Plant YAML file to write")
      ->check(output_file())
      ->required();
  random->callback([r] {
    const plant::Plant p = plant::random_plant(r->seed);
    write_file_atomic(r->out,
                      fmt::format("# plant random --seed {}\n", r->seed) + plant::plant_to_yaml(p));
    fmt::print("wrote {}\n", r->out);
  });

  struct ShowArgs {
    std::string file, field = "flat";
  };
  auto s = std::make_shared<ShowArgs>();
  CLI::App* show =
      plant->add_subcommand("show", "Check a plant file and print what it changes over a field");
  show->add_option("file", s->file, "Plant YAML file")->required();
  show->add_option("--field", s->field, "Field the grass scales apply to")->capture_default_str();
  show->callback([s] {
    const plant::Plant p = plant::load_plant(s->file);
    const field::Field f = field::load_field(s->field);
    fmt::print("plant {} (hash {}){}\n", p.source, p.hash,
               p.empty() ? ": empty, the world is the robot's model" : "");
    if (p.empty()) return;
    fmt::print(
        "  rolling resistance {:.4f} (field {:.4f}), sliding friction {:.4f} (field {:.4f})\n",
        plant::true_rolling_resistance(f, p), f.rolling_resistance,
        plant::true_sliding_friction(f, p), f.sliding_friction);
    fmt::print("  extra slope ({:.5f}, {:.5f}), hole offset ({:.4f}, {:.4f}) m\n",
               p.field.extra_slope[0], p.field.extra_slope[1], p.field.hole_offset[0],
               p.field.hole_offset[1]);
    for (const auto& b : p.field.bumps)
      fmt::print("  bump of {:+.4f} m at ({:.3f}, {:.3f}) m, widths ({:.3f}, {:.3f}) m\n", b.height,
                 b.center[0], b.center[1], b.sigma[0], b.sigma[1]);
    fmt::print(
        "  launch angle bias {:.5f} rad, club speed x{:.4f}, club restitution x{:.4f}, torque "
        "noise {}\n",
        p.arm.launch_angle_bias, p.arm.club_speed_scale, p.arm.club_restitution_scale,
        p.arm.torque_noise);
    fmt::print("  joint friction [{:.3f}] N m\n", fmt::join(p.arm.joint_friction, ", "));
    fmt::print("  vision noise {} m, latency {} s\n", p.perception.noise, p.perception.latency);
  });
}

}  // namespace mg::cli
