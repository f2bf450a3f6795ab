#include "experiments/round_study.hpp"

#include <memory>

#include <fmt/format.h>

#include "belief/belief.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "experiments/evaluate.hpp"
#include "plant/plant.hpp"
#include "system/system.hpp"
#include "viz/round_figure.hpp"

namespace mg::experiments {

std::map<std::string, game::HitModel> load_round_models(const std::vector<std::string>& specs,
                                                        const std::string& what) {
  std::map<std::string, game::HitModel> models;
  for (const auto& spec : specs) {
    const auto eq = spec.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size())
      throw InputError(fmt::format("{}: expected FIELD=FILE, got '{}'", what, spec));
    const field::Field field = field::load_field(spec.substr(0, eq));
    const std::string file = spec.substr(eq + 1);
    auto model = std::make_shared<const learning::Model>(learning::load_model(file));
    check_playable_model(*model, file);
    if (!models.emplace(field.name, round_hit_model(model, field)).second)
      throw InputError(fmt::format("{}: two models for field '{}'", what, field.name));
  }
  return models;
}

RoundStudy round_study(const RoundStudyOptions& o, const std::filesystem::path& out,
                       const std::function<void(const std::string&)>& log) {
  const std::vector<std::string> names =
      o.courses.empty() ? game::list_shipped_courses() : o.courses;
  std::vector<game::Course> courses;
  for (const auto& n : names) courses.push_back(game::load_course(n));
  const auto config = system::load_config(o.config, "");
  const plant::Plant plant = o.plant.empty() ? plant::Plant{} : plant::load_plant(o.plant);
  game::RoundOptions base;
  if (!o.belief.empty()) base.belief = belief::load_belief(o.belief).estimate;
  base.calibration_putts = o.budget;
  base.planner.threads = o.threads;
  base.validate();
  const std::vector<game::Player> players = game::comparison_players();
  RoundStudy study;
  for (const auto& course : courses) {
    study.rounds.push_back(game::play_seeds(
        course, config, plant, players, base, o.seed, o.seeds, [&](int done, int total) {
          log(fmt::format("round {}: {}/{} rounds", course.name, done, total));
        }));
  }
  std::string csv =
      "course,player,seed,hole,field,par,stroke,ball_x,ball_y,angle,speed,rest_x,rest_y,sunk,"
      "left_lane\n";
  for (const auto& c : study.rounds)
    for (std::size_t p = 0; p < c.players.size(); ++p)
      for (std::size_t s = 0; s < c.rounds[p].size(); ++s) {
        const std::string rows = game::round_csv(c.rounds[p][s]);
        std::size_t pos = rows.find('\n') + 1;  // past the header
        while (pos < rows.size()) {
          const std::size_t end = rows.find('\n', pos);
          csv += fmt::format("{},{},{},{}\n", c.course.name, game::to_string(c.players[p]),
                             o.seed + s, rows.substr(pos, end - pos));
          pos = end + 1;
        }
      }
  write_file_atomic(out / "rounds.csv", csv);
  study.markdown = game::comparison_markdown(
      study.rounds, o.seeds, plant.empty() ? "" : fmt::format(", plant {}", plant.source));
  if (o.plots) {
    std::filesystem::create_directories(out / "figures");
    for (const auto& c : study.rounds) {
      const auto pngs = viz::plot_round_holes(c.course, c.rounds.front(), out / "figures",
                                              "round-" + c.course.name);
      study.markdown +=
          fmt::format("\n{} (the robot's ball paths, {} seeds):\n\n", c.course.name, o.seeds);
      for (const auto& png : pngs)
        study.markdown +=
            fmt::format("![{}](figures/{})\n", png.stem().string(), png.filename().string());
    }
  }
  write_file_atomic(out / "rounds.md", study.markdown);
  return study;
}

}  // namespace mg::experiments
