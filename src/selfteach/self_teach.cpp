#include "selfteach/self_teach.hpp"

#include "selfteach/planner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "belief/prior.hpp"
#include "core/error.hpp"
#include "core/rng.hpp"
#include "stats/gpr.hpp"
#include "system/observe.hpp"
#include "system/parallel.hpp"
#include "teacher/bank_shots.hpp"
#include "teacher/teacher.hpp"

namespace mg::selfteach {

void SelfTeachOptions::validate() const {
  system::check_threads(threads);
  if (budget < 1 || budget > 100000)
    throw InputError(
        fmt::format("self-teach: budget: expected 1..100000 full-system putts, got {}", budget));
  if (batch < 1 || batch > 64)
    throw InputError(
        fmt::format("self-teach: batch: expected 1..64 putts per round, got {}", batch));
  if (candidates < 1 || candidates > 100000)
    throw InputError(fmt::format("self-teach: candidates: expected 1..100000, got {}", candidates));
  if (!(arrival_speed >= 0.0 && arrival_speed <= 2.0))
    throw InputError(fmt::format(
        "self-teach: arrival speed: expected 0..2 m/s (0: the strategy's), got {}", arrival_speed));
  if (!(record_interval > 0.0 && record_interval <= 0.05))
    throw InputError(
        fmt::format("self-teach: record_interval: expected 0..0.05 s, got {}", record_interval));
  for (int c : checkpoints)
    if (c < 1 || c > budget)
      throw InputError(
          fmt::format("self-teach: checkpoint {}: expected 1..budget ({})", c, budget));
}

namespace {

constexpr double kElasticRatio = 1.6;  ///< launch / club speed before any putt: (1 + e), e = 0.6
constexpr double kOnTarget = 0.01;     ///< [m] a label this close to its own target is checked
constexpr double kBatchSpread = 0.05;  ///< [m] targets of one round keep apart by about this
constexpr std::size_t kMaxTrainingLabels = 400;
constexpr double kTriedRadius = 0.03;  ///< [m] an earlier target this close halves a candidate's
                                       ///< score  ///< GPR cost: thinned evenly beyond this

double median(std::vector<double> v, double fallback) {
  if (v.empty()) return fallback;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// The situations a round may aim at: with the ball on the tee the region's centre (not for a
/// list), its collection points and `n` random holes; with a ball region the centres of both,
/// the collection situations and `n` random situations.
std::vector<field::Situation> candidate_targets(const field::Field& field,
                                                const field::Situations& region, int n,
                                                std::uint64_t seed) {
  const auto b = region_bounds(region);
  const std::array<double, 2> centre{0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3])};
  std::vector<field::Situation> c;
  if (region.balls) {
    const auto bb = region.balls->bounds();
    const field::Situation middle{{0.5 * (bb[0] + bb[1]), 0.5 * (bb[2] + bb[3])}, centre};
    if (field::playable(field, middle)) c.push_back(middle);
    for (const auto& s : region.collection_situations(field)) c.push_back(s);
    for (const auto& s : region.sample_situations(field, n, derive_seed(seed, 13))) c.push_back(s);
    return c;
  }
  if (region.shape == field::RegionShape::kList) {
    for (const auto& p : region.points) c.emplace_back(field.tee, p);
  } else {
    c.emplace_back(field.tee, centre);
    for (const auto& p : region.collection_points()) c.emplace_back(field.tee, p);
  }
  for (const auto& p : region.sample(n, derive_seed(seed, 13))) c.emplace_back(field.tee, p);
  return c;
}

double squared_distance(std::array<double, 2> a, std::array<double, 2> b) {
  return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]);
}

/// [m] between two situations: the holes' distance when the balls agree.
double distance(const field::Situation& a, const field::Situation& b) {
  return std::hypot(std::hypot(a.hole[0] - b.hole[0], a.hole[1] - b.hole[1]),
                    std::hypot(a.ball[0] - b.ball[0], a.ball[1] - b.ball[1]));
}

}  // namespace

std::array<double, 2> prior_club(const field::Field& field, const field::Situations& region,
                                 const field::Situation& situation, double arrival, double bias,
                                 double ratio) {
  auto g = belief::prior_launch(field, situation.ball, situation.hole, arrival);
  // An obstacle on the line: the shortest bank shot (the teacher's first choice) instead.
  if (field::line_blocked(field, situation.ball, situation.hole, field.ball.radius))
    if (const auto banks = teacher::bank_shots(field, situation.ball, situation.hole, arrival);
        !banks.empty())
      g = {banks.front().angle, banks.front().launch_speed};
  return {g.angle - bias, region.learn_speed ? g.speed / ratio : region.speed};
}

PuttRecord record_putt(const field::Situation& situation, double angle, double speed,
                       const control::FullPuttResult& r) {
  PuttRecord p;
  p.target = situation.hole;
  p.ball = situation.ball;
  p.angle = angle;
  p.speed = speed;
  p.hit = r.hit;
  p.sunk = r.outcome.sunk;
  p.closest_approach = r.outcome.closest_approach;
  p.launch_angle = r.launch.angle;
  p.launch_speed = r.launch.speed;
  p.approach_speed = r.outcome.approach_speed;
  p.approach_lateral = r.outcome.approach_lateral;
  p.approach_along = r.outcome.approach_along;
  return p;
}

std::array<double, 2> launch_relation(const std::vector<PuttRecord>& putts) {
  std::vector<double> bias, ratio;
  for (const auto& p : putts)
    if (p.hit && p.speed > 0.0 && p.launch_speed > 0.0) {
      bias.push_back(p.launch_angle - p.angle);
      ratio.push_back(p.launch_speed / p.speed);
    }
  return {median(bias, 0.0), median(ratio, kElasticRatio)};
}

learning::Model model_from_labels(const system::System& system, const field::Situations& region,
                                  const std::vector<Label>& labels, int putts, std::uint64_t seed) {
  std::vector<const Label*> use;
  for (const auto& l : labels)
    if (putts < 0 || l.putt < putts) use.push_back(&l);
  if (use.size() < 2)
    throw InputError(
        fmt::format("self-teach: field '{}': {} hindsight label(s) in the region after {} "
                    "putts (need 2): no label yet; give a larger budget (if many putts find none, "
                    "its holes are out "
                    "of the robot's reach)",
                    system.field().name, use.size(), putts < 0 ? 0 : putts));
  if (use.size() > kMaxTrainingLabels) {
    std::vector<const Label*> thin;
    for (std::size_t k = 0; k < kMaxTrainingLabels; ++k)
      thin.push_back(use[k * use.size() / kMaxTrainingLabels]);
    use = std::move(thin);
  }
  learning::Dataset d;
  d.source = "self-teach labels";
  d.input_names = region.learner_inputs();
  d.output_names = region.learner_outputs();
  const auto n = static_cast<Eigen::Index>(use.size());
  d.inputs.resize(n, static_cast<Eigen::Index>(d.input_names.size()));
  d.outputs.resize(n, static_cast<Eigen::Index>(d.output_names.size()));
  for (Eigen::Index i = 0; i < n; ++i) {
    const Label& l = *use[static_cast<std::size_t>(i)];
    d.inputs.row(i) = input_row(system.field(), d.input_names, {l.ball, l.hole}).transpose();
    d.outputs(i, 0) = l.angle;
    if (region.learn_speed) d.outputs(i, 1) = l.speed;
  }
  learning::TrainOptions o;
  o.method = learning::Method::kGpr;
  o.seed = seed;
  learning::Model m = learning::train(d, o);
  if (!region.learn_speed) m.fixed = {{"speed", region.speed}};
  return m;
}

bool replay_label(const system::System& system, system::SystemData& data, const Label& label) {
  return system::arm_hit(system, data, {label.ball, label.hole}, label.angle, label.speed)
      .outcome.sunk;
}

SelfTeachResult self_teach(const system::System& system, const field::Situations& region,
                           const SelfTeachOptions& options,
                           const std::function<void(int, int)>& progress) {
  options.validate();
  region.validate(system.field(), "self-teach region");
  system::check_real_holes(system.field(), system.plant(), region.corners(), "self-teach region");
  // The system the robot plans in: `system`, until a revision of its belief (options.revise).
  const system::System* sys = &system;
  const auto& field = system.field();
  HindsightRules rules;
  rules.learn_speed = region.learn_speed;
  rules.arrival_speed =
      options.arrival_speed > 0.0
          ? options.arrival_speed
          : teacher::arrival_speed(field, teacher::parse_strategy(region.strategy));
  const double margin = label_margin(region);
  const double hole_radius = 0.5 * field.hole.diameter;
  double rolling_decel = belief::rolling_deceleration(field);

  SelfTeachResult res;
  res.arrival_speed = rules.arrival_speed;
  auto planner =
      std::make_unique<Planner>(*sys, region, rules.arrival_speed, options.seed, options.prior);
  // With a prior model the result is a residual over it (real labels only); else GPR on labels.
  const auto learned = [&](int putts) {
    return planner->has_model_prior()
               ? planner->residual_model(res.labels, putts)
               : model_from_labels(*sys, region, res.labels, putts, options.seed);
  };
  const auto candidates = candidate_targets(field, region, options.candidates, options.seed);
  std::vector<field::Situation> tried;
  std::vector<int> checkpoints = options.checkpoints;
  std::sort(checkpoints.begin(), checkpoints.end());
  checkpoints.erase(std::unique(checkpoints.begin(), checkpoints.end()), checkpoints.end());
  std::size_t next_checkpoint = 0;
  int failed_checks = 0;

  const auto relabel = [&] {
    res.labels.clear();
    for (std::size_t i = 0; i < res.putts.size(); ++i) {
      auto& p = res.putts[i];
      const auto ls =
          hindsight_labels(res.paths[i], p.ball, p.target, hole_radius, rolling_decel, region,
                           margin, p.angle, p.speed, static_cast<int>(i), rules);
      p.labels = static_cast<int>(ls.size());
      p.label_distance =
          ls.empty() ? -1.0 : std::hypot(ls[0].hole[0] - p.target[0], ls[0].hole[1] - p.target[1]);
      res.labels.insert(res.labels.end(), ls.begin(), ls.end());
    }
  };

  while (static_cast<int>(res.putts.size()) < options.budget) {
    const int round = std::min(options.batch, options.budget - static_cast<int>(res.putts.size()));
    // Choose the round's targets before playing any of them.
    std::vector<field::Situation> targets;
    std::vector<std::array<double, 3>> plans;
    for (int b = 0; b < round; ++b) {
      double best = -1.0;
      std::size_t pick = 0;
      std::array<double, 3> best_plan{};
      for (std::size_t c = 0; c < candidates.size(); ++c) {
        const auto& h = candidates[c];
        auto plan = planner->plan(h);
        double s = plan[2];
        for (const auto& t : tried)
          if (distance(t, h) < kTriedRadius) s *= 0.5;
        for (const auto& t : targets) {
          const double d2 = squared_distance(t.hole, h.hole) +
                            (t.ball == h.ball ? 0.0 : squared_distance(t.ball, h.ball));
          s *= 1.0 - std::exp(-0.5 * d2 / (kBatchSpread * kBatchSpread));
        }
        if (s > best) {
          best = s;
          pick = c;
          best_plan = plan;
        }
      }
      targets.push_back(candidates[pick]);
      plans.push_back(best_plan);
    }
    // The speed of each putt to play chosen in the belief (the candidates were scored without).
    for (std::size_t k = 0; k < targets.size(); ++k) {
      const double score = plans[k][2];
      plans[k] = planner->plan_to_play(targets[k]);
      plans[k][2] = score;
    }
    std::vector<control::FullPuttResult> results(static_cast<std::size_t>(round));
    system::parallel_for(
        *sys, round, system::thread_count(options.threads), [&](int i, system::SystemData& data) {
          const auto k = static_cast<std::size_t>(i);
          control::FullPuttOptions po;
          po.record_interval = options.record_interval;
          results[k] = system::arm_hit(*sys, data, targets[k], plans[k][0], plans[k][1], po);
          // Labels, launches and revisions read the putt as the robot saw it.
          system::perceive_putt(*sys, data, results[k]);
        });
    // The belief first (in putt order: the same bits for any thread count), so that this round's
    // labels are already read in it; a revision rebuilds the planner and the earlier labels.
    bool revised = false;
    if (options.revise)
      for (int b = 0; b < round; ++b) {
        const auto k = static_cast<std::size_t>(b);
        if (const system::System* now =
                options.revise(targets[k], plans[k][0], plans[k][1], results[k])) {
          sys = now;
          revised = true;
        }
      }
    if (revised) {
      rolling_decel = belief::rolling_deceleration(sys->field());
      planner =
          std::make_unique<Planner>(*sys, region, rules.arrival_speed, options.seed, options.prior);
      relabel();
    }
    for (int b = 0; b < round; ++b) {
      const auto k = static_cast<std::size_t>(b);
      const auto& r = results[k];
      PuttRecord p = record_putt(targets[k], plans[k][0], plans[k][1], r);
      const int index = static_cast<int>(res.putts.size());
      const auto ls =
          r.hit ? hindsight_labels(r.outcome.trajectory, p.ball, p.target, hole_radius,
                                   rolling_decel, region, margin, p.angle, p.speed, index, rules)
                : std::vector<Label>{};
      p.labels = static_cast<int>(ls.size());
      if (!ls.empty())
        p.label_distance = std::hypot(ls[0].hole[0] - p.target[0], ls[0].hole[1] - p.target[1]);
      res.sunk += p.sunk ? 1 : 0;
      res.labels.insert(res.labels.end(), ls.begin(), ls.end());
      res.putts.push_back(p);
      res.paths.push_back(r.outcome.trajectory);
      tried.push_back(targets[k]);
      if (p.label_distance >= 0.0 && p.label_distance < kOnTarget) {
        ++res.on_target;
        if (p.sunk)
          ++res.on_target_sunk;
        else
          ++failed_checks;
      }
    }
    // Labels at their own targets that did not sink: s* is too fast for this cup.
    if (rules.learn_speed && failed_checks >= 2 && res.on_target_sunk < 0.9 * res.on_target &&
        rules.arrival_speed > 0.2) {
      rules.arrival_speed = std::max(0.2, 0.85 * rules.arrival_speed);
      planner->set_arrival(rules.arrival_speed);
      ++res.arrival_corrections;
      failed_checks = 0;
      res.on_target = res.on_target_sunk = 0;
      relabel();
    }
    planner->update(res.putts, res.labels);
    const int used = static_cast<int>(res.putts.size());
    while (next_checkpoint < checkpoints.size() && checkpoints[next_checkpoint] <= used) {
      const int c = checkpoints[next_checkpoint++];
      try {
        res.checkpoint_models.emplace_back(c, learned(c));
        res.checkpoint_beliefs.push_back(sys->belief());
      } catch (const InputError&) {
        // Fewer than two labels so far: no model at this checkpoint (it counts as no success).
      }
    }
    if (progress) progress(used, options.budget);
  }
  res.arrival_speed = rules.arrival_speed;
  res.belief = sys->belief();
  res.trained = planner->has_model_prior() || res.labels.size() >= 2;
  if (res.trained) res.model = learned(-1);
  return res;
}

}  // namespace mg::selfteach
