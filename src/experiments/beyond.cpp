#include "experiments/beyond.hpp"

#include <cmath>

#include <fmt/format.h>

#include "core/io.hpp"
#include "core/rng.hpp"
#include "experiments/evaluate.hpp"
#include "experiments/learning_curves.hpp"
#include "selfteach/robust.hpp"
#include "selfteach/self_teach.hpp"
#include "system/parallel.hpp"

namespace mg::experiments {

std::map<std::string, std::string> beyond_thesis(
    const system::System& sys, const std::string& name, const field::Situations& region,
    const std::map<std::string, learning::Model>& teacher_models, const BeyondOptions& opt) {
  std::map<std::string, std::string> md;
  const std::vector<int> checkpoints =
      opt.quick ? std::vector<int>{10, 25, 50} : std::vector<int>{10, 25, 50, 100, 150};
  const int budget = checkpoints.back();

  // ---- learning curves against own putts
  CurveOptions co;
  co.checkpoints = checkpoints;
  co.seeds = opt.quick ? 2 : 10;
  co.situations = opt.quick ? 30 : 100;
  co.seed = opt.seed;
  co.test_seed = derive_seed(opt.seed, 77);
  co.threads = opt.threads;
  co.teacher = opt.teacher;
  std::string all_runs, curve = "method,x,median,p10,p90\n";
  for (const auto learner :
       {CurveLearner::kSelfTeach, CurveLearner::kTeacherGpr, CurveLearner::kCrkr}) {
    const auto runs = learning_curves(sys, region, learner, co);
    const std::string csv = curves_csv(runs);
    all_runs += all_runs.empty() ? csv : csv.substr(csv.find('\n') + 1);
    const auto s = summarize(runs);
    for (std::size_t k = 0; k < s.putts.size(); ++k) {
      curve += fmt::format("{},{},{},{},{}\n", to_string(learner), s.putts[k], s.median[k],
                           s.q10[k], s.q90[k]);
      md["curves"] +=
          fmt::format("| {} | {} | {} | {:.0f} % | {:.0f}-{:.0f} % |\n", name, to_string(learner),
                      s.putts[k], 100 * s.median[k], 100 * s.q10[k], 100 * s.q90[k]);
    }
    opt.say(
        fmt::format("{}: {} learning curves ({} runs) done", name, to_string(learner), co.seeds));
  }
  write_file_atomic(opt.csv_path(name + "_own_putts_runs.csv"), all_runs);
  write_file_atomic(opt.csv_path(name + "_own_putts_curve.csv"), curve);
  opt.plot(fmt::format("learning-curve {} {} --xlabel {} --title {}",
                       shell_quote(opt.csv_path(name + "_own_putts_curve.csv")),
                       shell_quote(opt.fig_path(name + "_own_putts.png")),
                       shell_quote("own full-system putts spent (misses included)"),
                       shell_quote(fmt::format(
                           "{}: success on {} test situations, median and 10-90 % over {} runs",
                           name, co.situations, co.seeds))),
           opt.fig_path(name + "_own_putts.png"));
  md["figures"] +=
      fmt::format("![{} learning from own putts](figures/{}_own_putts.png)\n", name, name);

  // ---- goal check: one self-taught robot on the full test set, at 50 putts and at the budget
  selfteach::SelfTeachOptions so;
  so.budget = budget;
  so.seed = opt.seed;
  so.threads = opt.threads;
  so.checkpoints = {std::min(50, budget), budget};
  const auto taught = selfteach::self_teach(sys, region, so);
  EvaluateOptions eo;
  eo.situations = opt.test_situations;
  eo.seed = derive_seed(opt.seed, 78);
  eo.threads = opt.threads;
  eo.oracle = false;
  for (const auto& [putts, model] : taught.checkpoint_models) {
    const auto e = evaluate_model(sys, model, region, eo);
    md["goal"] +=
        fmt::format("| {} | {} | {} | {} | {:.1f} % ({:.1f}-{:.1f} %) |\n", name, putts,
                    eo.situations, e.sunk, 100 * e.success_ratio, 100 * e.ci95[0], 100 * e.ci95[1]);
  }
  if (taught.trained) learning::save_model(taught.model, opt.csv_path(name + "_self_taught.json"));
  opt.say(fmt::format("{}: goal check done", name));

  // ---- hindsight labels replayed with the hole really there (labels away from their own target)
  std::vector<selfteach::Label> sample;
  for (const auto& l : taught.labels) {
    const auto& p = taught.putts[static_cast<std::size_t>(l.putt)];
    if (std::hypot(l.hole[0] - p.target[0], l.hole[1] - p.target[1]) > 0.02) sample.push_back(l);
  }
  const std::size_t want = opt.quick ? 10 : 40;
  if (sample.size() > want) {
    std::vector<selfteach::Label> thin;
    for (std::size_t k = 0; k < want; ++k) thin.push_back(sample[k * sample.size() / want]);
    sample = std::move(thin);
  }
  std::vector<int> right(sample.size(), 0);
  system::parallel_for(
      sys, static_cast<int>(sample.size()), opt.threads, [&](int i, system::SystemData& d) {
        right[static_cast<std::size_t>(i)] =
            selfteach::replay_label(sys, d, sample[static_cast<std::size_t>(i)]) ? 1 : 0;
      });
  int k = 0;
  for (int r : right) k += r;
  const auto ci = wilson_interval(k, static_cast<int>(sample.size()));
  md["hindsight"] +=
      fmt::format("| {} | {} | {} | {} of {} | {} | {} |\n", name, taught.putts.size(),
                  taught.labels.size(), taught.on_target_sunk, taught.on_target, sample.size(),
                  sample.empty() ? std::string("- (every label lay at its own putt's target)")
                                 : fmt::format("{} sank: {:.0f} % ({:.0f}-{:.0f} %)", k,
                                               100.0 * k / static_cast<double>(sample.size()),
                                               100 * ci[0], 100 * ci[1]));
  opt.say(fmt::format("{}: hindsight labels replayed ({} of {} sank)", name, k, sample.size()));

  // ---- noise: perception (hole and ball position std) and execution (torque std)
  std::vector<std::pair<std::string, const learning::Model*>> players;
  for (const auto& [m, model] : teacher_models)
    if (m != "joint-gmr") players.emplace_back("teacher-" + m, &model);
  if (taught.trained) players.emplace_back("self-teach", &taught.model);
  const std::vector<double> perception =
      opt.quick ? std::vector<double>{0.0, 0.01}
                : std::vector<double>{0.0, 0.0025, 0.005, 0.0075, 0.01};
  const std::vector<double> torque =
      opt.quick ? std::vector<double>{0.01} : std::vector<double>{0.0, 0.0025, 0.005, 0.0075, 0.01};
  std::string pcurve = "method,x,median,p10,p90\n", tcurve = pcurve;
  // kind 0: perception noise [m]; 1: torque noise [of the limits]. The same situations and draws
  // for every model.
  const auto noisy = [&](int kind, double level) {
    EvaluateOptions ne;
    ne.situations = opt.quick ? 30 : 100;
    ne.seed = derive_seed(opt.seed, 79);
    ne.threads = opt.threads;
    ne.oracle = false;
    ne.noise_seed = derive_seed(opt.seed, 80);
    (kind == 0 ? ne.perception_noise : ne.torque_noise) = level;
    return ne;
  };
  for (const auto& [label, model] : players) {
    for (int kind = 0; kind < 2; ++kind)
      for (double level : kind == 0 ? perception : torque) {
        const EvaluateOptions ne = noisy(kind, level);
        const auto e = evaluate_model(sys, *model, region, ne);
        const double x = kind == 0 ? 1000.0 * level : level;
        (kind == 0 ? pcurve : tcurve) +=
            fmt::format("{},{},{},{},{}\n", label, x, e.success_ratio, e.ci95[0], e.ci95[1]);
        md["noise"] +=
            fmt::format("| {} | {} | {} | {:g} | {:.0f} % ({:.0f}-{:.0f} %) |\n", name, label,
                        kind == 0 ? "perception std [mm]" : "torque std [of limits]", x,
                        100 * e.success_ratio, 100 * e.ci95[0], 100 * e.ci95[1]);
      }
  }
  // Noise-aware: at the strongest noise of each kind, the arrival speed that maximises P(sink)
  // under the noise as the robot measures it (10 practice putts), self-taught anew for it.
  if (region.learn_speed && taught.trained) {
    for (int kind = 0; kind < 2; ++kind) {
      const double level = kind == 0 ? perception.back() : torque.back();
      const auto noise = kind == 0 ? selfteach::LaunchNoise{0.0, 0.0, level, 0}
                                   : selfteach::measure_launch_noise(sys, region, level, 0.0, 10,
                                                                     derive_seed(opt.seed, 81));
      selfteach::SelfTeachOptions ro = so;
      ro.checkpoints = {};
      ro.arrival_speed = selfteach::robust_arrival_speed(sys.field(), region, noise);
      const auto robust = selfteach::self_teach(sys, region, ro);
      if (!robust.trained) {
        md["noise"] += fmt::format(
            "| {} | self-teach noise-aware (s* = {:.2f} m/s) | {} | {:g} | no model: {} labels in "
            "{} putts |\n",
            name, ro.arrival_speed, kind == 0 ? "perception std [mm]" : "torque std [of limits]",
            kind == 0 ? 1000.0 * level : level, robust.labels.size(), robust.putts.size());
        continue;
      }
      const EvaluateOptions ne = noisy(kind, level);
      const auto e = evaluate_model(sys, robust.model, region, ne);
      const double x = kind == 0 ? 1000.0 * level : level;
      const std::string label = "self-teach noise-aware";
      (kind == 0 ? pcurve : tcurve) +=
          fmt::format("{},{},{},{},{}\n", label, x, e.success_ratio, e.ci95[0], e.ci95[1]);
      md["noise"] += fmt::format(
          "| {} | {} (s* = {:.2f} m/s; measured launch std {:.3f} deg, speed {:.2f} %; {} + {} "
          "putts) | {} | {:g} | {:.0f} % ({:.0f}-{:.0f} %) |\n",
          name, label, ro.arrival_speed, noise.angle_std * 180.0 / M_PI,
          100.0 * noise.speed_rel_std, noise.putts, robust.putts.size(),
          kind == 0 ? "perception std [mm]" : "torque std [of limits]", x, 100 * e.success_ratio,
          100 * e.ci95[0], 100 * e.ci95[1]);
    }
  }
  write_file_atomic(opt.csv_path(name + "_perception_noise.csv"), pcurve);
  write_file_atomic(opt.csv_path(name + "_torque_noise.csv"), tcurve);
  opt.plot(fmt::format("learning-curve {} {} --xlabel {} --title {}",
                       shell_quote(opt.csv_path(name + "_perception_noise.csv")),
                       shell_quote(opt.fig_path(name + "_perception_noise.png")),
                       shell_quote("hole and ball position std [mm]"),
                       shell_quote(fmt::format(
                           "{}: success under perception noise (95 % Wilson interval)", name))),
           opt.fig_path(name + "_perception_noise.png"));
  opt.plot(fmt::format("learning-curve {} {} --xlabel {} --title {}",
                       shell_quote(opt.csv_path(name + "_torque_noise.csv")),
                       shell_quote(opt.fig_path(name + "_torque_noise.png")),
                       shell_quote("joint torque noise std [fraction of limits]"),
                       shell_quote(fmt::format(
                           "{}: success under execution noise (95 % Wilson interval)", name))),
           opt.fig_path(name + "_torque_noise.png"));
  md["figures"] += fmt::format(
      "![{} perception noise](figures/{}_perception_noise.png) ![{} execution "
      "noise](figures/{}_torque_noise.png)\n",
      name, name, name, name);
  opt.say(fmt::format("{}: noise curves done", name));
  return md;
}

}  // namespace mg::experiments
