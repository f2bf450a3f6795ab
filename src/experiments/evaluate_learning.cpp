// `evaluate --learn`: learning while playing (evaluate.hpp, evaluate_learning), apart from the
// plain evaluation of a model in evaluate.cpp.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>

#include <fmt/format.h>

#include "belief/prior.hpp"
#include "core/error.hpp"
#include "core/rng.hpp"
#include "experiments/evaluate.hpp"
#include "experiments/evaluate_detail.hpp"
#include "experiments/revise.hpp"
#include "selfteach/hindsight.hpp"
#include "selfteach/planner.hpp"
#include "selfteach/self_teach.hpp"
#include "stats/gpr.hpp"
#include "system/believed_speed.hpp"
#include "system/observe.hpp"

namespace mg::experiments {

namespace {

/// The robot's reviser of its belief when options.revise, else nullptr.
std::unique_ptr<BeliefReviser> reviser_for(const system::System& system,
                                           const EvaluateOptions& options) {
  if (!options.revise) return nullptr;
  return std::make_unique<BeliefReviser>(system, options.belief_prior,
                                         derive_seed(options.seed, 71));
}

/// Situation `i`'s putt: the arm hits (angle `a`, club speed `v`) under the options' torque noise
/// (the situation's own stream), its ball path recorded for the labels.
control::FullPuttResult play_putt(const system::System& sys, system::SystemData& data,
                                  const field::Situation& s, double a, double v,
                                  const EvaluateOptions& options, int i) {
  control::FullPuttOptions po;
  po.record_interval = 0.005;
  po.seed = derive_seed(options.noise_seed, static_cast<std::uint64_t>(i) + 1000003);
  control::PlantEffectValues noise;
  noise.torque_noise = options.torque_noise;
  control::FullPuttResult r = system::arm_hit(sys, data, s, a, v, po, noise);
  system::perceive_putt(sys, data, r);  // the labels and the belief read what the robot saw
  return r;
}

/// The evaluation's totals, and the belief the learned model is to be played in.
void finish(LearningEvaluation& out, const system::System& last, const BeliefReviser* reviser) {
  Evaluation& e = out.evaluation;
  const int n = static_cast<int>(e.rows.size());
  for (const auto& r : e.rows) e.sunk += r.sunk;
  e.success_ratio = static_cast<double>(e.sunk) / n;
  e.ci95 = wilson_interval(e.sunk, n);
  e.oracle_ceiling = std::numeric_limits<double>::quiet_NaN();
  out.belief.estimate = last.belief();
  if (reviser != nullptr) {
    out.belief = reviser->belief();
    out.revisions = reviser->revisions();
    out.revision_max_cpu = reviser->max_cpu();
  }
}

LearningEvaluation evaluate_appending(const system::System& system, const learning::Model& model,
                                      const field::Situations& region,
                                      const EvaluateOptions& options,
                                      const std::function<void(int, int)>& progress);

/// The residual way: prior = the model, a residual GP on the hindsight labels
/// (selfteach/planner.hpp).
LearningEvaluation evaluate_residual(const system::System& system, const learning::Model& model,
                                     const field::Situations& region,
                                     const EvaluateOptions& options,
                                     const std::function<void(int, int)>& progress) {
  // The system the robot plans in: `system` until its belief is revised (options.revise).
  auto reviser = reviser_for(system, options);
  const system::System* sys = &system;
  selfteach::HindsightRules rules;
  rules.learn_speed = region.learn_speed;
  rules.arrival_speed = teacher::arrival_speed(system.field(), options.teacher.strategy);
  const double margin = selfteach::label_margin(region);
  const double hole_radius = 0.5 * system.field().hole.diameter;
  double rolling_decel = belief::rolling_deceleration(system.field());
  const auto situations =
      region.sample_situations(system.field(), options.situations, options.seed);
  detail::check_plant_holes(system, situations);
  const auto prior = std::make_shared<const learning::Model>(model);
  auto planner =
      std::make_unique<selfteach::Planner>(*sys, region, rules.arrival_speed, options.seed, prior);

  LearningEvaluation out;
  out.learned = model;
  Evaluation& e = out.evaluation;
  e.rows.resize(situations.size());
  auto data = std::make_unique<system::SystemData>(*sys);
  const int n = static_cast<int>(situations.size());
  std::vector<selfteach::PuttRecord> putts;
  std::vector<std::vector<sim::BallSample>> paths;  // kept only to relabel after a revision
  std::vector<selfteach::Label> labels;
  const auto label = [&](std::size_t k, const std::vector<sim::BallSample>& path) {
    const auto& p = putts[k];
    return selfteach::hindsight_labels(path, p.ball, p.target, hole_radius, rolling_decel, region,
                                       margin, p.angle, p.speed, static_cast<int>(k), rules);
  };
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const field::Situation& s = situations[k];
    SituationResult& r = e.rows[k];
    r.hole = s.hole;
    r.ball = s.ball;
    const auto plan = planner->plan_to_play(s);
    r.predicted = predict_hits(model, sys->field(), std::vector<field::Situation>{s})[0];
    r.predicted.angle = plan[0];
    r.predicted.speed = plan[1];
    const double a = r.predicted.angle, v = r.predicted.speed;
    r.in_envelope = system::hit_reachable(*sys, a, v);
    int added = 0;
    if (r.in_envelope) {
      control::FullPuttResult p = play_putt(*sys, *data, s, a, v, options, i);
      r.sunk = p.hit && !p.hit_refused && p.outcome.sunk;
      putts.push_back(selfteach::record_putt(s, a, v, p));
      if (reviser && reviser->observe(s, a, v, p)) {
        // Every earlier path is read again in the revised belief, by a planner built in it.
        sys = &reviser->system();
        data = std::make_unique<system::SystemData>(*sys);
        rolling_decel = belief::rolling_deceleration(sys->field());
        planner = std::make_unique<selfteach::Planner>(*sys, region, rules.arrival_speed,
                                                       options.seed, prior);
        labels.clear();
        for (std::size_t j = 0; j < paths.size(); ++j) {
          const auto ls = label(j, paths[j]);
          labels.insert(labels.end(), ls.begin(), ls.end());
        }
      }
      if (p.hit) {
        const auto ls = label(putts.size() - 1, p.outcome.trajectory);
        added = static_cast<int>(ls.size());
        labels.insert(labels.end(), ls.begin(), ls.end());
      }
      planner->update(putts, labels);
      if (reviser)
        paths.push_back(std::move(p.outcome.trajectory));  // a missed ball: an empty path
      p.outcome.trajectory.clear();
      r.outcome = std::move(p.outcome);
    }
    out.labels_added.push_back(added);
    if (std::find(options.learn_checkpoints.begin(), options.learn_checkpoints.end(), i + 1) !=
        options.learn_checkpoints.end()) {
      out.checkpoint_models.emplace_back(i + 1, planner->residual_model(labels, -1));
      out.checkpoint_beliefs.push_back(sys->belief());
    }
    if (progress) progress(i + 1, n);
  }
  out.learned = planner->residual_model(labels, -1);
  finish(out, *sys, reviser.get());
  return out;
}

LearningEvaluation evaluate_appending(const system::System& system, const learning::Model& model,
                                      const field::Situations& region,
                                      const EvaluateOptions& options,
                                      const std::function<void(int, int)>& progress) {
  check_playable_model(model, "model", &system);
  if (model.method != learning::Method::kGpr || model.prior)
    throw InputError(fmt::format(
        "--learn append: needs a plain GPR model (a {} model keeps no training data to add to)",
        model.prior ? "residual" : learning::method_name(model.method)));
  options.validate();
  if (options.perception_noise > 0.0 || options.oracle)
    throw InputError("--learn: plays without perception noise and without the oracle");
  const auto& field = system.field();
  const int ia = detail::output_index(model, "angle"), is = detail::output_index(model, "speed");
  selfteach::HindsightRules rules;
  rules.learn_speed = is >= 0;
  rules.arrival_speed = teacher::arrival_speed(field, options.teacher.strategy);
  const double margin = selfteach::label_margin(region);
  const double hole_radius = 0.5 * field.hole.diameter;
  double rolling_decel = belief::rolling_deceleration(field);
  const auto situations = region.sample_situations(field, options.situations, options.seed);
  detail::check_plant_holes(system, situations);

  LearningEvaluation out;
  out.learned = model;
  Evaluation& e = out.evaluation;
  e.rows.resize(situations.size());
  // The system the robot plans in: `system` until its belief is revised (options.revise).
  auto reviser = reviser_for(system, options);
  const system::System* sys = &system;
  auto data = std::make_unique<system::SystemData>(*sys);
  const int n = static_cast<int>(situations.size());
  Rng rng(derive_seed(options.seed, 17));
  std::vector<Eigen::Index> tuned_at;
  for (const auto& gp : model.gps) tuned_at.push_back(gp.size());
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const field::Situation& s = situations[k];
    SituationResult& r = e.rows[k];
    r.hole = s.hole;
    r.ball = s.ball;
    r.predicted = predict_hits(out.learned, sys->field(), std::vector<field::Situation>{s})[0];
    if (!region.learn_speed || out.learned.fixed_value("speed") != nullptr)
      r.predicted.speed = system::believed_club_speed(
          *sys, system::believed_situation(*sys, s),
          system::believed_fixed_speed(*sys, s, r.predicted.speed), r.predicted.angle);
    const double a = r.predicted.angle, v = r.predicted.speed;
    r.in_envelope = system::hit_reachable(*sys, a, v);
    int added = 0;
    if (r.in_envelope) {
      control::FullPuttResult p = play_putt(*sys, *data, s, a, v, options, i);
      r.sunk = p.hit && !p.hit_refused && p.outcome.sunk;
      if (reviser && reviser->observe(s, a, v, p)) {
        // Later putts and labels are read in the revised belief (the data appended stay).
        sys = &reviser->system();
        data = std::make_unique<system::SystemData>(*sys);
        rolling_decel = belief::rolling_deceleration(sys->field());
      }
      if (p.hit) {
        const auto labels =
            selfteach::hindsight_labels(p.outcome.trajectory, s.ball, s.hole, hole_radius,
                                        rolling_decel, region, margin, a, v, i, rules);
        for (const auto& l : labels) {
          Eigen::VectorXd x(out.learned.num_inputs());
          for (int col = 0; col < out.learned.num_inputs(); ++col)
            x(col) = field::situation_input(sys->field(),
                                            out.learned.input_names[static_cast<std::size_t>(col)],
                                            field::Situation{l.ball, l.hole});
          for (int o = 0; o < out.learned.num_outputs(); ++o) {
            stats::GpModel& gp = out.learned.gps[static_cast<std::size_t>(o)];
            Eigen::MatrixXd xs(gp.inputs.rows() + 1, gp.inputs.cols());
            xs << gp.inputs, x.transpose();
            Eigen::VectorXd ys(gp.targets.size() + 1);
            ys << gp.targets, (o == ia ? l.angle : o == is ? l.speed : std::nan(""));
            if (!std::isfinite(ys(ys.size() - 1))) continue;  // an output the labels do not give
            // Hyperparameters re-tuned whenever the data has grown by a third since they were.
            auto& at = tuned_at[static_cast<std::size_t>(o)];
            if (ys.size() >= at + std::max<Eigen::Index>(1, at / 3)) {
              stats::GprOptions go;
              go.restarts = 3;
              gp = stats::fit_gpr(xs, ys, rng, go);
              at = ys.size();
            } else {
              gp = stats::make_gp_model(xs, ys, gp.hyper);
            }
          }
          ++added;
        }
      }
      p.outcome.trajectory.clear();
      r.outcome = std::move(p.outcome);
    }
    out.labels_added.push_back(added);
    if (std::find(options.learn_checkpoints.begin(), options.learn_checkpoints.end(), i + 1) !=
        options.learn_checkpoints.end()) {
      out.checkpoint_models.emplace_back(i + 1, out.learned);
      out.checkpoint_beliefs.push_back(sys->belief());
    }
    if (progress) progress(i + 1, n);
  }
  finish(out, *sys, reviser.get());
  return out;
}

}  // namespace

LearningEvaluation evaluate_learning(const system::System& system, const learning::Model& model,
                                     const field::Situations& region,
                                     const EvaluateOptions& options,
                                     const std::function<void(int, int)>& progress) {
  check_playable_model(model, "model", &system);
  options.validate();
  if (options.perception_noise > 0.0 || options.oracle)
    throw InputError("--learn: plays without perception noise and without the oracle");
  return options.learn == LearnMode::kAppend
             ? evaluate_appending(system, model, region, options, progress)
             : evaluate_residual(system, model, region, options, progress);
}

}  // namespace mg::experiments
