#include "experiments/real_robot.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "belief/belief.hpp"
#include "core/io.hpp"
#include "experiments/adaptation.hpp"
#include "experiments/evaluate.hpp"
#include "experiments/identify.hpp"
#include "experiments/revise.hpp"
#include "selfteach/self_teach.hpp"
#include "system/system.hpp"

namespace mg::experiments {
namespace {

std::string pct(double r) { return std::isfinite(r) ? fmt::format("{:.0f} %", 100.0 * r) : "-"; }

/// `nominal` adapted by `putts` of the robot's own putts in `system` (self-teach --prior: a
/// residual over it), then played on the test situations in the belief it ended with. With
/// `revise` the robot also revises its belief from those putts, starting from `prior` (none:
/// `system`'s belief with the survey's spread).
Evaluation adapt(const system::System& system, const field::Situations& region,
                 const learning::Model& nominal, int putts, bool revise,
                 const std::optional<belief::Belief>& prior, const RealRobotOptions& opt,
                 const EvaluateOptions& eo) {
  const learning::Model* played = &nominal;
  selfteach::SelfTeachResult taught;
  std::unique_ptr<BeliefReviser> reviser;
  if (putts > 0) {
    selfteach::SelfTeachOptions so;
    so.budget = putts;
    so.seed = opt.seed;
    so.threads = opt.threads;
    so.prior = std::make_shared<const learning::Model>(nominal);
    if (revise) reviser = revise_hook(system, so, prior);
    taught = selfteach::self_teach(system, region, so);
    if (taught.trained) played = &taught.model;
  }
  if (reviser && reviser->revisions() > 0)
    return evaluate_model(reviser->system(), *played, region, eo);
  return evaluate_model(system, *played, region, eo);
}

}  // namespace

std::map<std::string, std::string> real_robot_rows(
    const control::ModuleConfig& config, const std::string& name, const field::Situations& region,
    const std::map<std::string, learning::Model>& models, const RealRobotOptions& opt) {
  std::map<std::string, std::string> md;
  const field::Field surveyed = field::load_field(config.field);
  const system::System real(config, surveyed, opt.plant);
  EvaluateOptions eo;
  eo.situations = opt.attempts;
  eo.seed = derive_seed(opt.seed, 66);
  eo.threads = opt.threads;
  eo.teacher.strategy = teacher::parse_strategy(region.strategy);
  eo.teacher.learn_speed = region.learn_speed;
  eo.teacher.fixed_speed = region.speed;
  // The revised belief: the robot's first identification putts, watched through the plant's
  // vision (experiments/identify.hpp); the rest of its own putts adapt the model in that belief.
  const int identify_putts = std::min(opt.identify_putts, opt.adaptation_putts);
  const Identification id =
      identify_world(config, real, identify_putts, "", derive_seed(opt.seed, 68), std::nullopt);
  const system::System revised(config, surveyed, opt.plant, id.belief.estimate);
  write_file_atomic(opt.csv_path(name + "_real_robot_belief.yaml"),
                    belief::belief_to_yaml(id.belief));

  std::string csv = "field,method,model,attempts,sunk,oracle_found,thesis_ratio\n";
  for (const std::string method : {"gpr", "gmr"}) {
    const auto it = models.find(method);
    if (it == models.end()) continue;
    const learning::Model& nominal = it->second;
    eo.oracle = true;
    const Evaluation before = evaluate_model(real, nominal, region, eo);
    eo.oracle = false;
    // A residual over the model, the belief never revised.
    const Evaluation kept =
        adapt(real, region, nominal, opt.adaptation_putts, false, std::nullopt, opt, eo);
    // The belief revised from every one of its own putts, with the residual.
    const Evaluation learning =
        adapt(real, region, nominal, opt.adaptation_putts, true, std::nullopt, opt, eo);
    // The belief first from the identification putts, then revised on with the residual.
    const Evaluation rev = adapt(revised, region, nominal, opt.adaptation_putts - identify_putts,
                                 true, id.belief, opt, eo);
    const double thesis = opt.thesis ? opt.thesis(name, method) : NAN;
    md["rows"] +=
        fmt::format("| {} | {} | {} of {} | {} of {} | {} of {} | {} of {} | {} | {} |\n", name,
                    method, before.sunk, opt.attempts, kept.sunk, opt.attempts, learning.sunk,
                    opt.attempts, rev.sunk, opt.attempts, pct(before.oracle_ceiling), pct(thesis));
    csv += fmt::format("{},{},nominal,{},{},{},{}\n", name, method, opt.attempts, before.sunk,
                       before.oracle_found, std::isfinite(thesis) ? fmt::format("{}", thesis) : "");
    csv += fmt::format("{},{},adapted-{},{},{},,\n", name, method, opt.adaptation_putts,
                       opt.attempts, kept.sunk);
    csv += fmt::format("{},{},revising-{},{},{},,\n", name, method, opt.adaptation_putts,
                       opt.attempts, learning.sunk);
    csv += fmt::format("{},{},revised-{}+{},{},{},,\n", name, method, identify_putts,
                       opt.adaptation_putts - identify_putts, opt.attempts, rev.sunk);
    opt.say(fmt::format(
        "{}: real-robot stand-in, {}: nominal {} of {}; after {} own putts: residual only {} of "
        "{}, revising {} of {}, identified first {} of {}; oracle ceiling {}",
        name, method, before.sunk, opt.attempts, opt.adaptation_putts, kept.sunk, opt.attempts,
        learning.sunk, opt.attempts, rev.sunk, opt.attempts, pct(before.oracle_ceiling)));
  }
  write_file_atomic(opt.csv_path(name + "_real_robot.csv"), csv);

  // Adaptation curves over random plants, the GPR nominal model.
  const auto gpr = models.find("gpr");
  if (gpr == models.end()) return md;
  AdaptationOptions ao;
  ao.plants = opt.quick ? 4 : 10;
  ao.plant_seed = opt.seed;
  ao.situations = opt.quick ? 30 : 100;
  ao.seed = opt.seed;
  ao.test_seed = derive_seed(opt.seed, 67);
  ao.threads = opt.threads;
  ao.checkpoints = {0, 1, 2, 3, 5, 10};
  const auto prior = std::make_shared<const learning::Model>(gpr->second);
  const auto rows = adaptation_study(config, prior, region, ao);
  write_file_atomic(opt.csv_path(name + "_adaptation_runs.csv"), adaptation_csv(rows, ao.learner));
  const auto s = summarize_adaptation(rows);
  std::string curve = "method,x,median,p10,p90\n";
  for (std::size_t k = 0; k < s.putts.size(); ++k) {
    curve +=
        fmt::format("adapt (GPR prior),{},{},{},{}\n", s.putts[k], s.median[k], s.q10[k], s.q90[k]);
    md["curves"] += fmt::format(
        "| {} | {} | {:.0f} % | {:.0f}-{:.0f} % | {:.0f} % | {} | {} | {} of {} |\n", name,
        s.putts[k], 100 * s.median[k], 100 * s.q10[k], 100 * s.q90[k], 100 * s.worst[k],
        pct(s.of_ceiling_median[k]), pct(s.of_ceiling_worst[k]), s.plants_at_goal[k], rows.size());
  }
  write_file_atomic(opt.csv_path(name + "_adaptation_curve.csv"), curve);
  opt.plot(
      fmt::format("learning-curve {} {} --xlabel {} --title {}",
                  shell_quote(opt.csv_path(name + "_adaptation_curve.csv")),
                  shell_quote(opt.fig_path(name + "_adaptation.png")),
                  shell_quote("own putts on the plant (0: the nominal model)"),
                  shell_quote(fmt::format(
                      "{}: success on {} test situations, median and 10-90 % over {} random plants",
                      name, ao.situations, rows.size()))),
      opt.fig_path(name + "_adaptation.png"));
  md["figures"] += fmt::format("![{} adaptation](figures/{}_adaptation.png)\n", name, name);
  opt.say(fmt::format("{}: adaptation curves over {} plants done", name, rows.size()));
  return md;
}

}  // namespace mg::experiments
