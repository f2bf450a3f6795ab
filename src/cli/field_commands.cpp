// field list | field show FIELD [--json]
#include <memory>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "core/check.hpp"
#include "core/csv.hpp"
#include "core/io.hpp"
#include "field/field.hpp"
#include "field/field_json.hpp"

namespace mg::cli {

void add_field_commands(CLI::App& app) {
  CLI::App* field_cmd = app.add_subcommand("field", "Inspect minigolf fields");
  field_cmd->require_subcommand(1);

  CLI::App* list = field_cmd->add_subcommand("list", "List the shipped fields");
  list->callback([] {
    for (const auto& name : field::list_shipped_fields()) {
      const field::Field f = field::load_field(name);
      fmt::print("{:<16} {}\n", name, f.description);
    }
  });

  struct ShowOptions {
    std::string field;
    bool json = false;
  };
  auto show_opts = std::make_shared<ShowOptions>();
  CLI::App* show = field_cmd->add_subcommand("show", "Print a field, resolved and validated");
  show->add_option("field", show_opts->field, "Shipped field name or path to a field file")
      ->required();
  show->add_flag("--json", show_opts->json, "Print one JSON object");
  show->callback([show_opts] {
    const field::Field f = field::load_field(show_opts->field);
    const nlohmann::json j = field::field_to_json(f);
    if (show_opts->json) {
      fmt::print("{}\n", j.dump());
      return;
    }
    fmt::print("{}: {}\n", f.name, f.description);
    fmt::print("  source             {}\n", f.source);
    fmt::print("  lane               x [{}, {}] m, y [{}, {}] m, cell {} m\n", f.bounds[0],
               f.bounds[1], f.bounds[2], f.bounds[3], f.cell_size);
    fmt::print("  heights            [{:.4f}, {:.4f}] m\n", j["height_range"][0].get<double>(),
               j["height_range"][1].get<double>());
    fmt::print("  tee                ({}, {}) m\n", f.tee[0], f.tee[1]);
    fmt::print("  hole               ({}, {}) m, diameter {} m, depth {} m\n", f.hole.position[0],
               f.hole.position[1], f.hole.diameter, f.hole.depth);
    fmt::print("  ball               radius {} m, mass {} kg\n", f.ball.radius, f.ball.mass);
    fmt::print("  rolling resistance {} (deceleration {:.3f} m/s^2 on the flat)\n",
               f.rolling_resistance, 5.0 / 7.0 * f.rolling_resistance * 9.81);
    fmt::print("  sliding friction   {}\n", f.sliding_friction);
    fmt::print("  surface            {}\n", j["surface"].dump());
  });

  struct HeightsOptions {
    std::string field;
    std::string output;
    double cell = 0.02;
  };
  auto heights_opts = std::make_shared<HeightsOptions>();
  CLI::App* heights =
      field_cmd->add_subcommand("heights", "Sample the surface on a grid (CSV x,y,z, metres)");
  heights->add_option("field", heights_opts->field, "Shipped field name or path")->required();
  heights->add_option("-o,--output", heights_opts->output, "Output CSV file")
      ->check(output_file())
      ->required();
  heights->add_option("--cell", heights_opts->cell, "Grid spacing [m]")->capture_default_str();
  heights->callback([heights_opts] {
    require_in_range("--cell", heights_opts->cell, 0.002, 1.0);
    const field::Field f = field::load_field(heights_opts->field);
    const auto& b = f.bounds;
    const int nx = static_cast<int>((b[1] - b[0]) / heights_opts->cell) + 1;
    const int ny = static_cast<int>((b[3] - b[2]) / heights_opts->cell) + 1;
    std::vector<std::vector<double>> rows;
    rows.reserve(static_cast<std::size_t>(nx * ny));
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double x = b[0] + i * heights_opts->cell, y = b[2] + j * heights_opts->cell;
        rows.push_back({x, y, f.height(x, y)});
      }
    write_file_atomic(heights_opts->output, format_csv({"x", "y", "z"}, rows));
  });
}

}  // namespace mg::cli
