#include "experiments/evaluate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <fmt/format.h>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/rng.hpp"
#include "experiments/evaluate_detail.hpp"
#include "experiments/wire.hpp"
#include "system/believed_speed.hpp"
#include "system/distributed.hpp"
#include "system/parallel.hpp"

namespace mg::experiments {

std::array<double, 2> wilson_interval(int k, int n, double z) {
  if (n <= 0) return {0.0, 1.0};
  const double p = static_cast<double>(k) / n, z2 = z * z;
  const double centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
  const double half = z / (1.0 + z2 / n) * std::sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n));
  // At k = 0 or k = n one end is 0 or 1 exactly (rounding would leave 1 - 1e-16).
  return {k == 0 ? 0.0 : std::max(0.0, centre - half), k == n ? 1.0 : std::min(1.0, centre + half)};
}

int detail::output_index(const learning::Model& m, std::string_view name) {
  for (int o = 0; o < m.num_outputs(); ++o)
    if (m.output_names[static_cast<std::size_t>(o)] == name) return o;
  return -1;
}

void check_playable_model(const learning::Model& model, const std::string& source,
                          const system::System* system) {
  for (const auto& n : model.input_names)
    if (std::find(field::kSituationInputs.begin(), field::kSituationInputs.end(), n) ==
        field::kSituationInputs.end())
      throw InputError(fmt::format("{}: model input '{}' does not match a situation (expected {})",
                                   source, n, fmt::join(field::kSituationInputs, ", ")));
  if (detail::output_index(model, "angle") < 0)
    throw InputError(fmt::format("{}: the model has no output 'angle' (outputs: {})", source,
                                 fmt::join(model.output_names, ", ")));
  if (detail::output_index(model, "speed") < 0 && model.fixed_value("speed") == nullptr)
    throw InputError(
        fmt::format("{}: the model has neither an output 'speed' nor a fixed speed", source));
  if (const double* v = model.fixed_value("speed")) {
    if (!std::isfinite(*v) || !(*v > 0.0))
      throw InputError(
          fmt::format("{}: fixed.speed: expected a club speed > 0 m/s, got {}", source, *v));
    if (system) system->check_speed(*v, source + ": fixed.speed");
  }
}

std::vector<Prediction> predict_hits(const learning::Model& model, const field::Field& field,
                                     const std::vector<std::array<double, 2>>& holes) {
  std::vector<field::Situation> situations;
  situations.reserve(holes.size());
  for (const auto& h : holes) situations.push_back({field.tee, h});
  return predict_hits(model, field, situations);
}

std::vector<Prediction> predict_hits(const learning::Model& model, const field::Field& field,
                                     const std::vector<field::Situation>& situations) {
  check_playable_model(model, "model");
  Eigen::MatrixXd q(static_cast<Eigen::Index>(situations.size()), model.num_inputs());
  for (std::size_t i = 0; i < situations.size(); ++i)
    for (int c = 0; c < model.num_inputs(); ++c) {
      q(static_cast<Eigen::Index>(i), c) = field::situation_input(
          field, model.input_names[static_cast<std::size_t>(c)], situations[i]);
    }
  std::vector<Prediction> out(situations.size());
  if (situations.empty()) return out;
  const learning::Predictions p = learning::predict(model, q);
  const int ia = detail::output_index(model, "angle"), is = detail::output_index(model, "speed");
  const double* fixed = model.fixed_value("speed");
  for (std::size_t i = 0; i < situations.size(); ++i) {
    const auto r = static_cast<Eigen::Index>(i);
    out[i].angle = p.mean(r, ia);
    out[i].angle_std = p.std(r, ia);
    out[i].speed = is >= 0 ? p.mean(r, is) : *fixed;
    out[i].speed_std = is >= 0 ? p.std(r, is) : 0.0;
  }
  return out;
}

game::HitModel round_hit_model(std::shared_ptr<const learning::Model> model,
                               const field::Field& field) {
  if (!model) throw InputError("round model: no model");
  check_playable_model(*model, "model");
  bool absolute = false, knows_ball = false;
  for (const auto& n : model->input_names) {
    absolute = absolute || n == "hole_x" || n == "hole_y";
    knows_ball = knows_ball || n == "ball_x" || n == "ball_y";
  }
  constexpr double kTeeTolerance = 0.01;  // [m]
  return [model, field, absolute, knows_ball](
             std::array<double, 2> ball,
             std::array<double, 2> hole) -> std::optional<game::ModelHit> {
    if (absolute && !knows_ball &&
        std::hypot(ball[0] - field.tee[0], ball[1] - field.tee[1]) > kTeeTolerance)
      return std::nullopt;
    // A model of the ball's position is asked at the ball; one of xi only, as from the tee.
    const field::Situation s =
        knows_ball || absolute
            ? field::Situation{ball, hole}
            : field::Situation{
                  field.tee, {field.tee[0] + hole[0] - ball[0], field.tee[1] + hole[1] - ball[1]}};
    const Prediction p = predict_hits(*model, field, std::vector<field::Situation>{s}).front();
    if (!std::isfinite(p.angle) || !std::isfinite(p.speed)) return std::nullopt;
    return game::ModelHit{p.angle, p.speed};
  };
}

void EvaluateOptions::validate() const {
  system::check_threads(threads);
  if (situations < 1 || situations > 100000)
    throw InputError(fmt::format("--situations: expected 1..100000, got {}", situations));
  if (!(perception_noise >= 0.0 && perception_noise <= 0.1))
    throw InputError(fmt::format("perception noise: expected 0..0.1 m, got {}", perception_noise));
  if (!(torque_noise >= 0.0 && torque_noise <= 0.1))
    throw InputError(
        fmt::format("torque noise: expected 0..0.1 of the limits, got {}", torque_noise));
}

/// The plant's real holes of every test situation, before the first putt (not after others ran).
void detail::check_plant_holes(const system::System& system,
                               const std::vector<field::Situation>& situations) {
  std::vector<std::array<double, 2>> holes;
  for (const auto& s : situations) holes.push_back(s.hole);
  system::check_real_holes(system.field(), system.plant(), holes, "evaluate");
}

Evaluation evaluate_model(const system::System& system, const learning::Model& model,
                          const field::Situations& region, const EvaluateOptions& options,
                          const std::function<void(int, int)>& progress) {
  check_playable_model(model, "model", &system);
  return evaluate_policy(
      system,
      [&](const std::vector<field::Situation>& seen) {
        // The model is asked where the robot believes the hole is (the same bits without a
        // belief).
        std::vector<field::Situation> situations;
        for (const auto& s : seen) situations.push_back(system::believed_situation(system, s));
        auto hits = predict_hits(model, system.field(), situations);
        // A fixed speed is one the model learned on the surveyed green: played as the arrival
        // speed it gave there. So is the speed of an angle-only region, however the model
        // carries it.
        if (!region.learn_speed || model.fixed_value("speed") != nullptr)
          for (std::size_t i = 0; i < hits.size(); ++i)
            hits[i].speed = system::believed_club_speed(
                system, situations[i],
                system::believed_fixed_speed(system, situations[i], hits[i].speed), hits[i].angle);
        return hits;
      },
      region, options, progress);
}

Evaluation evaluate_policy(const system::System& system, const Policy& policy,
                           const field::Situations& region, const EvaluateOptions& options,
                           const std::function<void(int, int)>& progress) {
  options.validate();
  const auto& field = system.field();
  const auto situations = region.sample_situations(field, options.situations, options.seed);
  detail::check_plant_holes(system, situations);
  std::vector<field::Situation> perceived = situations;
  if (options.perception_noise > 0.0)
    for (std::size_t i = 0; i < situations.size(); ++i) {
      Rng rng(derive_seed(options.noise_seed, i));
      std::normal_distribution<double> n(0.0, options.perception_noise);
      const double hx = n(rng), hy = n(rng), bx = n(rng), by = n(rng);
      const auto& [ball, hole] = situations[i];
      // xi = hole - ball: the hole's and the ball's errors both enter it. A ball on the tee is
      // seen there and the hole off by both errors (the same xi).
      perceived[i] =
          ball == field.tee
              ? field::Situation{ball, {hole[0] + hx - bx, hole[1] + hy - by}}
              : field::Situation{{ball[0] + bx, ball[1] + by}, {hole[0] + hx, hole[1] + hy}};
    }
  const auto predictions = policy(perceived);
  if (predictions.size() != situations.size())
    throw Error(fmt::format("policy: {} predictions for {} situations", predictions.size(),
                            situations.size()));
  Evaluation e;
  e.rows.resize(situations.size());
  const int n = static_cast<int>(situations.size());
  int done = 0;
  system::distributed_for(
      system, e.rows, options.threads,
      [&](int i, system::SystemData& data) {
        SituationResult& r = e.rows[static_cast<std::size_t>(i)];
        r.hole = situations[static_cast<std::size_t>(i)].hole;
        r.ball = situations[static_cast<std::size_t>(i)].ball;
        r.predicted = predictions[static_cast<std::size_t>(i)];
        const double a = r.predicted.angle, v = r.predicted.speed;
        r.in_envelope = system::hit_reachable(system, a, v);
        if (r.in_envelope) {
          control::FullPuttOptions po;
          po.seed = derive_seed(options.noise_seed, static_cast<std::uint64_t>(i) + 1000003);
          control::PlantEffectValues noise;  // (a plant may add its own: the seed is set)
          noise.torque_noise = options.torque_noise;
          const control::FullPuttResult p =
              system::arm_hit(system, data, {r.ball, r.hole}, a, v, po, noise);
          r.sunk = p.hit && !p.hit_refused && p.outcome.sunk;
          r.outcome = p.outcome;
        }
        if (options.oracle) {
          // The oracle knows the world: an angle-only teacher hits at the club speed that
          // arrives there as the fixed speed arrived on the surveyed green.
          teacher::TeacherOptions oracle = options.teacher;
          if (!oracle.learn_speed)
            oracle.fixed_speed =
                system::true_fixed_speed(system, {r.ball, r.hole}, oracle.fixed_speed);
          const teacher::Example ex =
              teacher::teach(system, data, field::Situation{r.ball, r.hole}, oracle);
          r.oracle_found = ex.found;
          r.oracle_full_putts = ex.full_putts;
          r.oracle_ball_putts = ex.ball_putts;
        }
      },
      [&](int) {
        if (progress) progress(++done, n);
      });
  for (const auto& r : e.rows) {
    e.sunk += r.sunk;
    e.oracle_found += r.oracle_found;
  }
  e.success_ratio = static_cast<double>(e.sunk) / n;
  e.ci95 = wilson_interval(e.sunk, n);
  e.oracle_ceiling = options.oracle ? static_cast<double>(e.oracle_found) / n
                                    : std::numeric_limits<double>::quiet_NaN();
  return e;
}

std::string evaluation_csv(const Evaluation& e, const field::Field& field) {
  std::vector<std::vector<double>> rows;
  for (const auto& r : e.rows)
    rows.push_back(
        {r.hole[0], r.hole[1], r.hole[0] - r.ball[0], r.hole[1] - r.ball[1], r.predicted.angle,
         r.predicted.speed, r.predicted.angle_std, r.predicted.speed_std, r.in_envelope ? 1.0 : 0.0,
         r.sunk ? 1.0 : 0.0, r.in_envelope ? r.outcome.closest_approach : 1e3,
         r.outcome.rest_position[0], r.outcome.rest_position[1], r.oracle_found ? 1.0 : 0.0,
         static_cast<double>(r.oracle_full_putts), static_cast<double>(r.oracle_ball_putts)});
  // Balls off the tee (a ball region): their positions as two more columns.
  bool off_tee = false;
  for (const auto& r : e.rows) off_tee = off_tee || r.ball != field.tee;
  if (off_tee)
    for (std::size_t i = 0; i < rows.size(); ++i)
      rows[i].insert(rows[i].end(), {e.rows[i].ball[0], e.rows[i].ball[1]});
  for (auto& row : rows)
    for (auto& v : row)
      if (!std::isfinite(v)) v = 0.0;
  std::vector<std::string> columns{"hole_x",
                                   "hole_y",
                                   "xi_x",
                                   "xi_y",
                                   "angle",
                                   "speed",
                                   "angle_std",
                                   "speed_std",
                                   "in_envelope",
                                   "sunk",
                                   "closest_approach",
                                   "rest_x",
                                   "rest_y",
                                   "oracle_found",
                                   "oracle_full_putts",
                                   "oracle_ball_putts"};
  if (off_tee) columns.insert(columns.end(), {"ball_x", "ball_y"});
  return format_csv(columns, rows);
}

}  // namespace mg::experiments
