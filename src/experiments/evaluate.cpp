#include "experiments/evaluate.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "experiments/wire.hpp"
#include "system/distributed.hpp"

namespace mg::experiments {

std::array<double, 2> wilson_interval(int k, int n, double z) {
  if (n <= 0) return {0.0, 1.0};
  const double p = static_cast<double>(k) / n, z2 = z * z;
  const double centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
  const double half = z / (1.0 + z2 / n) * std::sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n));
  // At k = 0 or k = n one end is 0 or 1 exactly (rounding would leave 1 - 1e-16).
  return {k == 0 ? 0.0 : std::max(0.0, centre - half), k == n ? 1.0 : std::min(1.0, centre + half)};
}

namespace {

int output_index(const learning::Model& m, std::string_view name) {
  for (int o = 0; o < m.num_outputs(); ++o)
    if (m.output_names[static_cast<std::size_t>(o)] == name) return o;
  return -1;
}

}  // namespace

void check_playable_model(const learning::Model& model, const std::string& source) {
  for (const auto& n : model.input_names)
    if (n != "xi_x" && n != "xi_y" && n != "hole_x" && n != "hole_y")
      throw InputError(fmt::format("{}: model input '{}' does not match a situation (expected xi_x, "
                                   "xi_y, hole_x or hole_y)", source, n));
  if (output_index(model, "angle") < 0)
    throw InputError(fmt::format("{}: the model has no output 'angle' (outputs: {})", source,
                                 fmt::join(model.output_names, ", ")));
  if (output_index(model, "speed") < 0 && model.fixed_value("speed") == nullptr)
    throw InputError(fmt::format("{}: the model has neither an output 'speed' nor a fixed speed", source));
}

std::vector<Prediction> predict_hits(const learning::Model& model, const field::Field& field,
                                     const std::vector<std::array<double, 2>>& holes) {
  check_playable_model(model, "model");
  Eigen::MatrixXd q(static_cast<Eigen::Index>(holes.size()), model.num_inputs());
  for (std::size_t i = 0; i < holes.size(); ++i)
    for (int c = 0; c < model.num_inputs(); ++c) {
      const auto& n = model.input_names[static_cast<std::size_t>(c)];
      const auto& h = holes[i];
      q(static_cast<Eigen::Index>(i), c) = n == "xi_x"   ? h[0] - field.tee[0]
                                           : n == "xi_y" ? h[1] - field.tee[1]
                                           : n == "hole_x" ? h[0]
                                                           : h[1];
    }
  std::vector<Prediction> out(holes.size());
  if (holes.empty()) return out;
  const learning::Predictions p = learning::predict(model, q);
  const int ia = output_index(model, "angle"), is = output_index(model, "speed");
  const double* fixed = model.fixed_value("speed");
  for (std::size_t i = 0; i < holes.size(); ++i) {
    const auto r = static_cast<Eigen::Index>(i);
    out[i].angle = p.mean(r, ia);
    out[i].angle_std = p.std(r, ia);
    out[i].speed = is >= 0 ? p.mean(r, is) : *fixed;
    out[i].speed_std = is >= 0 ? p.std(r, is) : 0.0;
  }
  return out;
}

Evaluation evaluate_model(const system::System& system, const learning::Model& model,
                          const field::Situations& region, const EvaluateOptions& options,
                          const std::function<void(int, int)>& progress) {
  if (options.situations < 1 || options.situations > 100000)
    throw InputError(fmt::format("--situations: expected 1..100000, got {}", options.situations));
  const auto holes = region.sample(options.situations, options.seed);
  const auto predictions = predict_hits(model, system.field(), holes);
  Evaluation e;
  e.rows.resize(holes.size());
  const auto& c = system.config();
  const int n = static_cast<int>(holes.size());
  int done = 0;
  system::distributed_for(
      system, e.rows, options.threads,
      [&](int i, system::SystemData& data) {
        SituationResult& r = e.rows[static_cast<std::size_t>(i)];
        r.hole = holes[static_cast<std::size_t>(i)];
        r.predicted = predictions[static_cast<std::size_t>(i)];
        const double a = r.predicted.angle, v = r.predicted.speed;
        r.in_envelope = std::isfinite(a) && std::isfinite(v) && a >= c.angle_min && a <= c.angle_max &&
                        v >= c.speed_min && v <= c.speed_max;
        if (r.in_envelope) {
          const control::FullPuttResult p = system::arm_putt(system, data, r.hole, a, v);
          r.sunk = p.hit && !p.hit_refused && p.outcome.sunk;
          r.outcome = p.outcome;
        }
        if (options.oracle) {
          const teacher::Example ex = teacher::teach(system, data, r.hole, options.teacher);
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
    rows.push_back({r.hole[0], r.hole[1], r.hole[0] - field.tee[0], r.hole[1] - field.tee[1],
                    r.predicted.angle, r.predicted.speed, r.predicted.angle_std, r.predicted.speed_std,
                    r.in_envelope ? 1.0 : 0.0, r.sunk ? 1.0 : 0.0,
                    r.in_envelope ? r.outcome.closest_approach : 1e3, r.outcome.rest_position[0],
                    r.outcome.rest_position[1], r.oracle_found ? 1.0 : 0.0,
                    static_cast<double>(r.oracle_full_putts), static_cast<double>(r.oracle_ball_putts)});
  for (auto& row : rows)
    for (auto& v : row)
      if (!std::isfinite(v)) v = 0.0;
  return format_csv({"hole_x", "hole_y", "xi_x", "xi_y", "angle", "speed", "angle_std", "speed_std",
                     "in_envelope", "sunk", "closest_approach", "rest_x", "rest_y", "oracle_found",
                     "oracle_full_putts", "oracle_ball_putts"},
                    rows);
}

}  // namespace mg::experiments
