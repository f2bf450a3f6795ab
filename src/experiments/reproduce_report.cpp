// report.md of `reproduce` from its tables, and the thesis's values for its "thesis" columns
// (reproduce_steps.hpp).
#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/io.hpp"
#include "experiments/real_robot.hpp"
#include "experiments/reproduce_steps.hpp"
#include "field/map_reader.hpp"
#include "system/distributed.hpp"

namespace mg::experiments::reproduce_steps {
namespace {

std::string thesis_key(const std::string& field) {
  std::string k = field;
  std::replace(k.begin(), k.end(), '-', '_');
  return k;
}

// The rows of `table`, empty if no step wrote any.
std::string entry(const std::map<std::string, std::string>& tables, const std::string& table) {
  const auto it = tables.find(table);
  return it == tables.end() ? std::string() : it->second;
}

}  // namespace

double Thesis::mse(const std::string& field, const std::string& output,
                   const std::string& method) const {
  std::string m = method;
  std::replace(m.begin(), m.end(), '-', '_');
  const YAML::Node mse = root["mse"];
  if (!mse || !mse.IsMap() || !mse[thesis_key(field)]) return NAN;
  const YAML::Node f = mse[thesis_key(field)];
  // (yaml-cpp: assigning to a Node writes through, so pick the node without reassigning)
  const YAML::Node o = f[output] ? f[output] : f["simulator_" + output];
  return o && o.IsMap() && o[m] ? o[m].as<double>() : NAN;
}

double Thesis::success(const std::string& field, const std::string& method,
                       const char* where) const {
  std::string m = method;
  std::replace(m.begin(), m.end(), '-', '_');
  const YAML::Node s = root["success"];
  if (!s || !s.IsMap() || !s[thesis_key(field)]) return NAN;
  const YAML::Node f = s[thesis_key(field)];
  if (!f[where] || !f[where][m]) return NAN;
  const YAML::Node c = f[where][m];
  return c[1].as<double>() / c[0].as<double>();
}

Thesis load_thesis() {
  const std::filesystem::path p = data_dir() / "reference" / "thesis-results.yaml";
  return Thesis{field::load_yaml(read_text_file(p), p.string())};
}

std::string report_markdown(const Run& run, const Tables& t, const std::string& rounds_md,
                            double elapsed_s) {
  const ReproduceOptions& opt = run.opt;
  std::string report;
  report += fmt::format(
      "# minigolf reproduce{}: thesis chapter 6 on the simulated WAM\n\n"
      "Revision `{}`, seed {}, {} threads, {:.0f} s. Everything below was measured by this run on "
      "the full "
      "system (the arm hits the ball in MuJoCo), except the columns marked **thesis**, which quote "
      "Kronander's tables for comparison only. Raw numbers: `csv/`; settings: `run.json`.\n\n",
      opt.quick ? " --quick" : "", opt.revision, opt.seed, system::thread_count(opt.threads),
      elapsed_s);
  report +=
      "## Data sets (teacher, thesis 5.1)\n\n| field | region (outputs) | examples | strategy | "
      "full-system putts | ball-only putts |\n|---|---|---|---|---|---|\n" +
      t.data_md;
  report +=
      "\n## Validation MSE (thesis tables 6.1-6.4)\n\nAngle MSE in deg² (the thesis does not state "
      "its unit; its values fit deg²), speed in (m/s)². Arctan: the mean over " +
      std::to_string(run.arctan_splits) +
      " random training sets, 9 validation points each, corners always in training (thesis 6.2.4); "
      "the other fields: a separate validation set of " +
      std::to_string(kValidationSituations) +
      " random situations collected by the teacher.\n\n| field | output | method | ours | thesis "
      "|\n|---|---|---|---|---|\n" +
      t.mse_md;
  report +=
      "\n## The robot plays (thesis table 6.5)\n\nRandom test situations of each field's region "
      "(the first 30 are the thesis's attempt count), "
      "hit with the model's prediction on the full system. Oracle ceiling: the fraction of the "
      "same situations for which the teacher finds a sinking putt.\n\n"
      "| field | method | situations | sunk | success (95 % CI) | oracle ceiling | thesis "
      "|\n|---|---|---|---|---|---|---|\n" +
      t.success_md;
  report += "\n![success](figures/success.png)\n";
  report += fmt::format(
                "\n## Learning curves (beyond the thesis)\n\nSuccess on {} test situations against "
                "the number of training examples (random subsets of the training set; median and "
                "10-90 % over {} subsets).\n\n| field | method | examples | median success | 10-90 "
                "% |\n|---|---|---|---|---|\n",
                run.curve_situations, run.curve_seeds) +
            t.curves_md;
  for (const auto& name : opt.fields)
    report += fmt::format("![{} learning curve](figures/{}_learning_curve.png)\n", name, name);
  if (opt.beyond) {
    report += fmt::format(
        "\n## Beyond the thesis: the robot teaches itself\n\n"
        "No teacher, no data set: `minigolf self-teach` chooses its own putts on the full system "
        "and learns from every "
        "outcome, misses included, through hindsight labels (where each ball path says other holes "
        "would have been sunk). "
        "Baselines in the same simulator, on the same test situations, with the same accounting: "
        "**teacher-gpr** is the "
        "thesis protocol (the teacher collects examples at random situations, every full-system "
        "putt it spends counted; "
        "GPR on what it found so far), **crkr** is Cost-regularized Kernel Regression (Kober et "
        "al. 2012). "
        "Success against own full-system putts, median and 10-90 % over {} runs, {} test "
        "situations per point.\n\n"
        "| field | learner | own putts | median success | 10-90 % |\n|---|---|---|---|---|\n",
        opt.quick ? 2 : 10, opt.quick ? 30 : 100);
    report += entry(t.beyond_md, "curves");
    report += fmt::format(
                  "\n### Goal check: one self-taught robot (seed {}) on {} test situations\n\n"
                  "| field | own putts | situations | sunk | success (95 % CI) "
                  "|\n|---|---|---|---|---|\n",
                  opt.seed, run.n_test) +
              entry(t.beyond_md, "goal");
    report +=
        "\n### Hindsight labels replayed with the hole really there\n\nOwn-target checks: labels "
        "within 1 cm of the target of "
        "the putt they came from, checked by that putt's outcome (free). Replayed: labels more "
        "than 2 cm from it, replayed on "
        "the full system with the hole at the label.\n\n"
        "| field | putts | labels | own-target checks sank | replayed | precision (95 % CI) "
        "|\n|---|---|---|---|---|---|\n" +
        entry(t.beyond_md, "hindsight");
    report += fmt::format(
                  "\n### Noise\n\nPerception: the hole's and the ball's perceived positions each "
                  "off by a Gaussian of this "
                  "std per axis (the robot chooses its putt for the xi it sees). Execution: the "
                  "launch study's joint-torque "
                  "noise. {} test situations per point.\n\n"
                  "| field | model | noise | level | success (95 % CI) |\n|---|---|---|---|---|\n",
                  opt.quick ? 30 : 100) +
              entry(t.beyond_md, "noise");
    report += '\n';
    report += entry(t.beyond_md, "figures");
  }
  if (!entry(t.real_md, "rows").empty()) {
    const int kIdentify = RealRobotOptions{}.identify_putts;  // reproduce keeps the default
    report += fmt::format(
        "\n## The real-robot rows (beyond the thesis: a plant stands in for the real WAM)\n\n"
        "The thesis played 10 attempts per model on its real arm (table 6.5). Here the plant `{}` "
        "(hash {}; grass, "
        "a missed tilt, a biased club face, a slower arm, friction, vision noise and latency: "
        "docs/reality.md) is the "
        "real arm: the nominal-simulator model as it is, then after 10 of the robot's own putts "
        "there, three ways: a residual over the model in the world as surveyed (`self-teach "
        "--prior --no-revise`, the belief never revised); the same with the belief revised from "
        "every putt it played (the green and the arm from the ball paths it saw, `self-teach "
        "--prior`); and the belief identified first from {} putts (`identify`), then revised on "
        "with the residual from the other {}. Every hit is planned in the belief of its time (an "
        "angle-only model's fixed speed played as the arrival speed it gave on the surveyed "
        "green). The oracle ceiling is the "
        "teacher's in the true world on the same 10 situations (angle-only fields: at the club "
        "speed that arrives there as the fixed speed did on the survey).\n\n"
        "| field | method | nominal model | residual only, 10 own putts | revising, 10 own putts "
        "| identified, {} + {} own putts | oracle ceiling | thesis real robot (for comparison) |\n"
        "|---|---|---|---|---|---|---|---|\n",
        run.real_plant.source, run.real_plant.hash, kIdentify, 10 - kIdentify, kIdentify,
        10 - kIdentify);
    report += entry(t.real_md, "rows");
    report +=
        "\n### Adaptation curves over random plants (`plant random`)\n\nThe GPR nominal model on "
        "seeded random plants; "
        "success after that many own putts (0: the nominal model), and its ratio to each plant's "
        "oracle ceiling.\n\n"
        "| field | own putts | median | 10-90 % | worst | of ceiling: median | worst | plants at "
        ">= 95 % of ceiling |\n"
        "|---|---|---|---|---|---|---|---|\n" +
        entry(t.real_md, "curves") + "\n" + entry(t.real_md, "figures");
  }
  report += rounds_md;
  report += "\n## Figures\n\n" + t.figures_md;
  return report;
}

}  // namespace mg::experiments::reproduce_steps
