#include "experiments/learning_curves.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

#include <fmt/format.h>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/rng.hpp"
#include "experiments/revise.hpp"
#include "experiments/wire.hpp"
#include "selfteach/crkr.hpp"
#include "selfteach/self_teach.hpp"
#include "system/distributed.hpp"
#include "system/parallel.hpp"

namespace mg::experiments {

std::string to_string(CurveLearner l) {
  switch (l) {
    case CurveLearner::kSelfTeach:
      return "self-teach";
    case CurveLearner::kTeacherGpr:
      return "teacher-gpr";
    case CurveLearner::kCrkr:
      return "crkr";
    case CurveLearner::kAdapt:
      return "adapt";
    case CurveLearner::kAdaptPlay:
      return "adapt-play";
    case CurveLearner::kAppend:
      return "append";
  }
  return "?";
}

CurveLearner parse_curve_learner(const std::string& name) {
  for (CurveLearner l : {CurveLearner::kSelfTeach, CurveLearner::kTeacherGpr, CurveLearner::kCrkr,
                         CurveLearner::kAdapt, CurveLearner::kAdaptPlay, CurveLearner::kAppend})
    if (to_string(l) == name) return l;
  throw InputError(fmt::format(
      "--learner: expected self-teach, teacher-gpr, crkr, adapt, adapt-play or append, got '{}'",
      name));
}

bool needs_prior(CurveLearner l) {
  return l == CurveLearner::kAdapt || l == CurveLearner::kAdaptPlay || l == CurveLearner::kAppend;
}

void CurveOptions::validate() const {
  system::check_threads(threads);
  if (checkpoints.empty()) throw InputError("learning curves: no checkpoints");
  for (int c : checkpoints)
    if (c < 0 || c > 100000)
      throw InputError(fmt::format("learning curves: checkpoint {}: expected 0..100000", c));
  if (checkpoints.back() < 1)
    throw InputError("learning curves: the last checkpoint must be >= 1 putt");
  if (std::adjacent_find(checkpoints.begin(), checkpoints.end(), std::greater_equal<int>()) !=
      checkpoints.end())
    throw InputError(
        "learning curves: checkpoints must be strictly increasing (each a different putt count)");
  if (seeds < 1 || seeds > 1000)
    throw InputError(fmt::format("learning curves: seeds: expected 1..1000, got {}", seeds));
  if (situations < 1 || situations > 100000)
    throw InputError(
        fmt::format("learning curves: situations: expected 1..100000, got {}", situations));
}

namespace {

EvaluateOptions test_options(const CurveOptions& o) {
  EvaluateOptions e;
  e.situations = o.situations;
  e.seed = o.test_seed;
  e.threads = 1;
  e.oracle = false;
  return e;
}

int play_model(const system::System& sys, const field::Situations& region, const learning::Model& m,
               const CurveOptions& o) {
  return evaluate_model(sys, m, region, test_options(o)).sunk;
}

/// Checkpoints of at least one putt (the learners' own checkpoints).
std::vector<int> positive_checkpoints(const CurveOptions& o) {
  std::vector<int> out;
  for (int k : o.checkpoints)
    if (k > 0) out.push_back(k);
  return out;
}

/// The run's curve from the models at its checkpoints; checkpoint 0 plays the prior (if any).
/// A checkpoint's model is played in its belief (`beliefs`, the same order; empty: `sys`'s).
CurveRun curve_of(const system::System& sys, const field::Situations& region, const CurveOptions& o,
                  const std::vector<std::pair<int, learning::Model>>& models,
                  const std::vector<plant::Plant>& beliefs = {}) {
  CurveRun c;
  for (int k : o.checkpoints) {
    int sunk = 0;
    if (k == 0 && o.prior) sunk = play_model(sys, region, *o.prior, o);
    for (std::size_t j = 0; j < models.size(); ++j) {
      if (models[j].first != k) continue;
      if (j < beliefs.size() &&
          plant::plant_to_yaml(beliefs[j]) != plant::plant_to_yaml(sys.belief()))
        sunk = play_model(*system_in_belief(sys, beliefs[j]), region, models[j].second, o);
      else
        sunk = play_model(sys, region, models[j].second, o);
    }
    c.putts.push_back(k);
    c.sunk.push_back(sunk);
  }
  return c;
}

CurveRun self_teach_run(const system::System& sys, const field::Situations& region, int run,
                        const CurveOptions& o, bool from_prior) {
  selfteach::SelfTeachOptions so;
  so.budget = o.checkpoints.back();
  so.seed = derive_seed(o.seed, static_cast<std::uint64_t>(run));
  so.threads = 1;
  so.checkpoints = positive_checkpoints(o);
  std::unique_ptr<BeliefReviser> reviser;
  if (from_prior) {
    so.prior = o.prior;
    if (o.revise) reviser = revise_hook(sys, so);
  }
  const auto r = selfteach::self_teach(sys, region, so);
  return curve_of(sys, region, o, r.checkpoint_models, r.checkpoint_beliefs);
}

CurveRun play_learning_run(const system::System& sys, const field::Situations& region, int run,
                           const CurveOptions& o, LearnMode mode) {
  EvaluateOptions e;
  e.situations = o.checkpoints.back();
  e.seed = derive_seed(o.seed, static_cast<std::uint64_t>(run));
  e.threads = 1;
  e.oracle = false;
  e.teacher = o.teacher;
  e.learn = mode;
  e.learn_checkpoints = positive_checkpoints(o);
  e.revise = o.revise;
  const auto r = evaluate_learning(sys, *o.prior, region, e);
  return curve_of(sys, region, o, r.checkpoint_models, r.checkpoint_beliefs);
}

CurveRun teacher_run(const system::System& sys, const field::Situations& region, int run,
                     const CurveOptions& o) {
  system::SystemData data(sys);
  const std::uint64_t seed = derive_seed(o.seed, static_cast<std::uint64_t>(run));
  Rng rng(derive_seed(seed, 31));
  std::vector<teacher::Example> found;
  std::vector<int> spent_at;  // putts spent when example k was done
  int spent = 0;
  const int budget = o.checkpoints.back();
  while (spent < budget) {
    teacher::TeacherOptions t = o.teacher;
    t.max_full_putts = std::min(t.max_full_putts, budget - spent);
    const teacher::Example e =
        teacher::teach(sys, data, region.sample_situation(sys.field(), rng), t);
    spent += e.full_putts;
    if (e.full_putts == 0) break;  // cannot happen (a budget >= 1 spends a putt); guards the loop
    if (e.found) {
      found.push_back(e);
      spent_at.push_back(spent);
    }
  }
  CurveRun c;
  const auto inputs = region.learner_inputs();
  const auto outputs = region.learner_outputs();
  for (int k : o.checkpoints) {
    std::vector<const teacher::Example*> use;
    for (std::size_t i = 0; i < found.size(); ++i)
      if (spent_at[i] <= k) use.push_back(&found[i]);
    int sunk = 0;
    if (use.size() >= 2) {
      learning::Dataset d;
      d.source = "teacher examples";
      d.input_names = inputs;
      d.output_names = outputs;
      d.inputs.resize(static_cast<Eigen::Index>(use.size()),
                      static_cast<Eigen::Index>(inputs.size()));
      d.outputs.resize(static_cast<Eigen::Index>(use.size()),
                       static_cast<Eigen::Index>(outputs.size()));
      for (std::size_t i = 0; i < use.size(); ++i) {
        const auto r = static_cast<Eigen::Index>(i);
        for (std::size_t c2 = 0; c2 < inputs.size(); ++c2)
          d.inputs(r, static_cast<Eigen::Index>(c2)) =
              field::situation_input(sys.field(), inputs[c2], {use[i]->ball, use[i]->hole});
        d.outputs(r, 0) = use[i]->angle;
        if (outputs.size() > 1) d.outputs(r, 1) = use[i]->speed;
      }
      learning::TrainOptions to;
      to.method = learning::Method::kGpr;
      to.seed = seed;
      learning::Model m = learning::train(d, to);
      if (!region.learn_speed) m.fixed = {{"speed", region.speed}};
      sunk = play_model(sys, region, m, o);
    }
    c.putts.push_back(k);
    c.sunk.push_back(sunk);
    c.examples = static_cast<int>(use.size());
  }
  return c;
}

CurveRun crkr_run(const system::System& sys, const field::Situations& region, int run,
                  const CurveOptions& o) {
  selfteach::CrkrOptions co;
  co.budget = o.checkpoints.back();
  co.seed = derive_seed(o.seed, static_cast<std::uint64_t>(run));
  co.checkpoints = positive_checkpoints(o);
  const auto r = selfteach::crkr_learn(sys, region, co);
  CurveRun c;
  for (const auto& [k, policy] : r.checkpoint_policies) {
    const Policy play = [&, &pol = policy](const std::vector<field::Situation>& situations) {
      std::vector<Prediction> out;
      for (const auto& s : situations) {
        const auto a = pol.act(sys.field(), region, s.hole);  // the region has no ball region
        out.push_back({a[0], a[1], 0.0, 0.0});
      }
      return out;
    };
    c.putts.push_back(k);
    c.sunk.push_back(evaluate_policy(sys, play, region, test_options(o)).sunk);
  }
  return c;
}

}  // namespace

std::vector<CurveRun> learning_curves(const system::System& system, const field::Situations& region,
                                      CurveLearner learner, const CurveOptions& options,
                                      const std::function<void(int, int)>& progress) {
  options.validate();
  // CRKR's policy acts from the tee.
  if (region.balls && learner == CurveLearner::kCrkr)
    throw InputError(fmt::format(
        "learning curves: --learner {} plays from the tee; this region has a ball region (not "
        "supported)",
        to_string(learner)));
  if (needs_prior(learner) && !options.prior)
    throw InputError(fmt::format("learning curves: --learner {} needs a prior model (--prior)",
                                 to_string(learner)));
  std::vector<CurveRun> runs(static_cast<std::size_t>(options.seeds));
  int done = 0;
  // Runs are independent: over MPI processes too (the same bits as one process).
  system::distributed_for(
      system, runs, system::thread_count(options.threads),
      [&](int i, system::SystemData&) {
        CurveRun r;
        switch (learner) {
          case CurveLearner::kSelfTeach:
            r = self_teach_run(system, region, i, options, false);
            break;
          case CurveLearner::kTeacherGpr:
            r = teacher_run(system, region, i, options);
            break;
          case CurveLearner::kCrkr:
            r = crkr_run(system, region, i, options);
            break;
          case CurveLearner::kAdapt:
            r = self_teach_run(system, region, i, options, true);
            break;
          case CurveLearner::kAdaptPlay:
            r = play_learning_run(system, region, i, options, LearnMode::kResidual);
            break;
          case CurveLearner::kAppend:
            r = play_learning_run(system, region, i, options, LearnMode::kAppend);
            break;
        }
        r.learner = learner;
        r.run = i;
        r.situations = options.situations;
        runs[static_cast<std::size_t>(i)] = std::move(r);
      },
      [&](int) {
        if (progress) progress(++done, options.seeds);
      });
  return runs;
}

std::string curves_csv(const std::vector<CurveRun>& runs) {
  std::string out = "learner,run,putts,sunk,situations,success\n";
  for (const auto& r : runs)
    for (std::size_t k = 0; k < r.putts.size(); ++k)
      out += fmt::format("{},{},{},{},{},{}\n", to_string(r.learner), r.run, r.putts[k], r.sunk[k],
                         r.situations, static_cast<double>(r.sunk[k]) / r.situations);
  return out;
}

CurveSummary summarize(const std::vector<CurveRun>& runs) {
  CurveSummary s;
  if (runs.empty()) return s;
  s.putts = runs.front().putts;
  const auto quantile = [](std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    const double pos = q * static_cast<double>(v.size() - 1);
    const auto lo = static_cast<std::size_t>(std::floor(pos));
    const std::size_t hi = std::min(lo + 1, v.size() - 1);
    return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
  };
  for (std::size_t k = 0; k < s.putts.size(); ++k) {
    std::vector<double> v;
    for (const auto& r : runs) v.push_back(static_cast<double>(r.sunk[k]) / r.situations);
    s.median.push_back(quantile(v, 0.5));
    s.q10.push_back(quantile(v, 0.1));
    s.q90.push_back(quantile(v, 0.9));
  }
  return s;
}

}  // namespace mg::experiments
