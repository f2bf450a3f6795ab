// minigolf.play and minigolf.courses: a round of minigolf (game/, docs/play.md), the dict of
// `minigolf play --json` through the same report code.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>

#include "game/report.hpp"
#include "plant/plant.hpp"
#include "python/bindings.hpp"

namespace mg::python {

void bind_game(py::module_& m) {
  m.def("courses", &game::list_shipped_courses, "Names of the shipped courses (data/courses)");
  m.def(
      "play",
      [](const std::string& course, const std::string& player, std::uint64_t seed, int budget,
         const std::string& plant, const std::string& config, const std::string& hitting_model,
         int threads) {
        std::string text;
        {
          py::gil_scoped_release release;
          const game::Course c = game::load_course(course);
          game::RoundOptions o;
          o.player = game::parse_player(player, "player");
          o.seed = seed;
          o.calibration_putts = budget;
          o.planner.threads = threads;
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
      "Plays a round on `course` (shipped name or path) by `player` (robot: the arm with its own "
      "model of each field and `budget` learning putts per field; oracle: planning in the true "
      "world, ball-only putts; greedy: aim at the hole). plant: the world as it really is. "
      "Returns the dict of `minigolf play --json`. Releases the GIL.");
}

}  // namespace mg::python
