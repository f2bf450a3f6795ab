// minigolf.play and minigolf.courses: a round of minigolf (game/, docs/round.md), the dict of
// `minigolf play --json` through the same report code.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <map>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "experiments/round_study.hpp"
#include "game/report.hpp"
#include "plant/plant.hpp"
#include "python/bindings.hpp"
#include "system/parallel.hpp"

namespace mg::python {

void bind_game(py::module_& m) {
  m.def("courses", &game::list_shipped_courses, "Names of the shipped courses (data/courses)");
  m.def(
      "play",
      [](const std::string& course, const std::string& player, std::uint64_t seed, int budget,
         const std::string& plant, const std::string& config, const std::string& hitting_model,
         int threads, const std::map<std::string, std::string>& models) {
        system::check_threads(threads);
        std::string text;
        {
          py::gil_scoped_release release;
          const game::Course c = game::load_course(course);
          game::RoundOptions o;
          o.player = game::parse_player(player, "player");
          o.seed = seed;
          o.calibration_putts = budget;
          o.planner.threads = threads;
          std::vector<std::string> specs;
          for (const auto& [field, file] : models) specs.push_back(field + "=" + file);
          if (!specs.empty() && o.player != game::Player::kRobot)
            throw InputError("models: only the robot player plays a learned model");
          o.models = experiments::load_round_models(specs, "models");
          o.validate();
          const plant::Plant p = plant.empty() ? plant::Plant{} : plant::load_plant(plant);
          game::ImaginedCache cache;
          nlohmann::json j = game::round_json(
              game::play_round(c, system::load_config(config, "", hitting_model), p, o, &cache));
          j["plant"] = p.source.empty() ? nlohmann::json(nullptr)
                                        : nlohmann::json{{"path", p.source}, {"hash", p.hash}};
          text = j.dump();
        }
        return py::module_::import("json").attr("loads")(text);
      },
      py::arg("course"), py::arg("player") = "robot", py::arg("seed") = 0,
      py::arg("budget") = game::RoundOptions{}.calibration_putts, py::arg("plant") = "",
      py::arg("config") = "", py::arg("hitting_model") = "", py::arg("threads") = 0,
      py::arg("models") = std::map<std::string, std::string>{},
      "Plays a round on `course` (shipped name or path) by `player` (robot: the arm with its own "
      "model of each field and `budget` learning putts per field; oracle: planning in the true "
      "world, ball-only putts launched with the arm's precision; exact-oracle: the same, exact; "
      "greedy: aim at the hole). plant: the world as it really is. models: {field: model file} "
      "the robot plays where they sink surely (as `play --model`). Returns the dict of "
      "`minigolf play --json`. Releases the GIL.");
}

}  // namespace mg::python
