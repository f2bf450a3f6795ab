#include "selfteach/planner.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "belief/prior.hpp"
#include "core/error.hpp"
#include "selfteach/self_teach.hpp"
#include "system/believed_speed.hpp"
#include "teacher/bank_shots.hpp"

namespace mg::selfteach {
namespace {

constexpr double kPseudoCover = 0.02;  ///< [m] a real label this close replaces a pseudo-label

/// [m] between a label's situation and (ball, hole): the holes' distance when the balls agree.
double situation_distance(const Label& l, std::array<double, 2> ball, std::array<double, 2> hole) {
  return std::hypot(std::hypot(l.hole[0] - hole[0], l.hole[1] - hole[1]),
                    std::hypot(l.ball[0] - ball[0], l.ball[1] - ball[1]));
}

int output_index(const learning::Model& m, const char* name) {
  for (int o = 0; o < m.num_outputs(); ++o)
    if (m.output_names[static_cast<std::size_t>(o)] == name) return o;
  return -1;
}

}  // namespace

Eigen::VectorXd input_row(const field::Field& field, const std::vector<std::string>& inputs,
                          const field::Situation& situation) {
  Eigen::VectorXd x(static_cast<Eigen::Index>(inputs.size()));
  for (std::size_t c = 0; c < inputs.size(); ++c)
    x(static_cast<Eigen::Index>(c)) = field::situation_input(field, inputs[c], situation);
  return x;
}

Eigen::VectorXd input_row(const field::Field& field, const std::vector<std::string>& inputs,
                          std::array<double, 2> hole) {
  return input_row(field, inputs, field::Situation{field.tee, hole});
}

std::optional<stats::GpHyperparameters> fixed_residual_hyper(const field::Situations& region,
                                                             int inputs, int output, int labels) {
  if (labels > kResidualLabelsToTune) return std::nullopt;
  const auto b = region_bounds(region);
  const double extent = std::max({b[1] - b[0], b[3] - b[2], 0.1});
  stats::GpHyperparameters h;
  h.length_scales = Eigen::VectorXd::Constant(inputs, extent);
  h.signal_std = output == 0 ? 0.01 : 0.05;
  h.noise_std = output == 0 ? 0.0015 : 0.01;
  return h;
}

/// The residual GP on (x, r) for output kind 0 (angle) or 1 (speed) with `labels` rows: the fixed
/// hyperparameters while they apply, else fitted with length scales of at least a quarter of the
/// region's extent.
stats::GpModel residual_gp(const field::Situations& region, const Eigen::MatrixXd& x,
                           const Eigen::VectorXd& r, int kind, Rng& rng) {
  if (auto h = fixed_residual_hyper(region, static_cast<int>(x.cols()), kind,
                                    static_cast<int>(x.rows())))
    return stats::make_gp_model(x, r, *h);
  const auto b = region_bounds(region);
  const double extent = std::max({b[1] - b[0], b[3] - b[2], 0.1});
  stats::GprOptions go;
  go.restarts = 3;
  go.initial_length_scales = Eigen::VectorXd::Constant(1, extent);
  go.length_scale_bounds = {0.25 * extent, 20.0 * extent};
  go.noise_std_bounds = {kind == 0 ? 5e-4 : 3e-3, kind == 0 ? 0.02 : 0.1};
  return stats::fit_gpr(x, r, rng, go);
}

Planner::Planner(const system::System& system, const field::Situations& region, double arrival,
                 std::uint64_t seed, std::shared_ptr<const learning::Model> prior)
    : sys_(system),
      region_(region),
      inputs_(region.learner_inputs()),
      arrival_(arrival),
      rng_(derive_seed(seed, 11)),
      prior_model_(std::move(prior)) {
  outputs_ = region_.learn_speed ? 2 : 1;
  if (prior_model_) {
    const auto& m = *prior_model_;
    // The residual reads the prior's inputs and, from balls anywhere, what the region needs
    // besides (a prior of xi alone cannot tell balls apart on a sloped lane).
    const auto needed = std::move(inputs_);
    inputs_ = m.input_names;
    if (region.balls)
      for (const auto& name : needed)
        if (std::find(inputs_.begin(), inputs_.end(), name) == inputs_.end())
          inputs_.push_back(name);
    if (output_index(m, "angle") < 0) throw InputError("prior model: expected an output 'angle'");
    if (region_.learn_speed && output_index(m, "speed") < 0)
      throw InputError(
          "prior model: the region learns the club speed, the model has no output 'speed'");
    for (const auto& name : inputs_)
      (void)field::situation_input(sys_.field(), name, sys_.field().hole.position);
  }
}

std::vector<stats::GpHyperparameters> Planner::hyperparameters(const Eigen::MatrixXd& x,
                                                               const Eigen::MatrixXd& r) {
  std::vector<stats::GpHyperparameters> out;
  if (prior_model_) {
    for (int o = 0; o < outputs_; ++o)
      out.push_back(residual_gp(region_, x, r.col(o), o, rng_).hyper);
    return out;
  }
  for (int o = 0; o < outputs_; ++o) {
    stats::GprOptions go;
    go.restarts = 3;
    out.push_back(stats::fit_gpr(x, r.col(o), rng_, go).hyper);
  }
  return out;
}

void Planner::update(const std::vector<PuttRecord>& putts, std::vector<Label> labels) {
  const auto relation = launch_relation(putts);
  bias_ = relation[0];
  ratio_ = relation[1];
  const std::size_t real = labels.size();
  sunk_.clear();
  for (std::size_t i = 0; i < putts.size(); ++i) {
    const auto& p = putts[i];
    if (p.hit && p.sunk) {
      Label l;
      l.hole = p.target;
      l.ball = p.ball;
      l.angle = p.angle;
      l.speed = p.speed;
      l.arrival_speed = arrival_;
      l.putt = static_cast<int>(i);
      sunk_.push_back(l);
    }
  }
  for (std::size_t i = 0; i < putts.size(); ++i) {
    const auto& p = putts[i];
    if (!p.hit) continue;
    bool covered = false;
    for (std::size_t k = 0; k < real && !covered; ++k)
      covered = situation_distance(labels[k], p.ball, p.target) < kPseudoCover;
    if (covered) continue;
    // With a model prior a putt that sank is moved by its Newton step towards the middle of the
    // window by at most the window's scale: the cup spoils its path (a fast ball that drops in
    // asks for a large step), and the prior is already close.
    Label l = pseudo_label(p, static_cast<int>(i));
    if (prior_model_ && p.sunk) {
      l.angle = std::clamp(l.angle, p.angle - kWindowAngle, p.angle + kWindowAngle);
      l.speed = std::clamp(l.speed, p.speed - kWindowSpeed, p.speed + kWindowSpeed);
    }
    labels.push_back(l);
  }
  gps_.clear();
  if (labels.empty()) return;
  const auto n = static_cast<Eigen::Index>(labels.size());
  Eigen::MatrixXd x(n, static_cast<Eigen::Index>(inputs_.size()));
  Eigen::MatrixXd r(n, outputs_);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Label& l = labels[static_cast<std::size_t>(i)];
    const field::Situation s{l.ball, l.hole};
    x.row(i) = input_row(sys_.field(), inputs_, s).transpose();
    const auto [a0, v0] = prior(s);
    r(i, 0) = l.angle - a0;
    if (outputs_ == 2) r(i, 1) = l.speed - v0;
  }
  // Hyperparameters are re-chosen when the label count has grown by a third (a model prior:
  // every update while they are fixed); in between the last ones are reused (the GP is then
  // rebuilt exactly, only not re-tuned).
  const bool fixed_phase =
      prior_model_ && fixed_residual_hyper(region_, 1, 0, static_cast<int>(n) - 1).has_value();
  const bool refit =
      fixed_phase || hyper_.empty() || n >= fitted_at_ + std::max<Eigen::Index>(1, fitted_at_ / 3);
  if (refit) {
    hyper_ = hyperparameters(x, r);
    fitted_at_ = n;
  }
  for (int o = 0; o < outputs_; ++o)
    gps_.push_back(stats::make_gp_model(x, r.col(o), hyper_[static_cast<std::size_t>(o)]));
}

Label Planner::pseudo_label(const PuttRecord& p, int index) const {
  const auto& f = sys_.field();
  // Newton's step on the lateral miss: the direct line's slope is -distance; a bank's flips
  // with each bounce (teacher::BankShot::lateral_gain).
  double gain = -std::max(0.1, std::hypot(p.target[0] - p.ball[0], p.target[1] - p.ball[1]));
  if (field::line_blocked(f, p.ball, p.target, f.ball.radius))
    if (const auto banks = teacher::bank_shots(f, p.ball, p.target, arrival_); !banks.empty())
      gain = banks.front().lateral_gain();
  Label l;
  l.hole = p.target;
  l.ball = p.ball;
  l.angle = p.angle - std::clamp(p.approach_lateral / gain, -0.05, 0.05);
  l.speed = p.speed;
  l.putt = index;
  if (region_.learn_speed) {
    const double a_roll = belief::rolling_deceleration(f);
    const double e =
        p.approach_speed * p.approach_speed - 2.0 * a_roll * std::max(0.0, p.approach_along);
    const double rolling_per_club = 5.0 / 7.0 * ratio_;  // ball rolling speed per club speed
    const double v2 =
        p.speed * p.speed - (e - arrival_ * arrival_) / (rolling_per_club * rolling_per_club);
    l.speed = std::clamp(std::sqrt(std::max(v2, 0.0)), 0.7 * p.speed, 1.3 * p.speed);
  }
  l.arrival_speed = arrival_;
  return l;
}

std::array<double, 2> Planner::prior(const field::Situation& situation) const {
  std::array<double, 2> club{};
  if (!prior_model_) {
    club = prior_club(sys_.field(), region_, situation, arrival_, bias_, ratio_);
  } else {
    // The model asked where the robot believes the hole is (the same bits without a belief).
    const auto& m = *prior_model_;
    const field::Situation at = system::believed_situation(sys_, situation);
    const Eigen::MatrixXd q = input_row(sys_.field(), m.input_names, at).transpose();
    const learning::Predictions p = learning::predict(m, q);
    const int ia = output_index(m, "angle"), is = output_index(m, "speed");
    double v = region_.speed;
    if (is >= 0)
      v = p.mean(0, is);
    else if (const double* fixed = m.fixed_value("speed"))
      v = *fixed;
    club = {p.mean(0, ia), v};
    // The region's fixed speed is the surveyed green's; the believed green may ask for another.
    if (!region_.learn_speed) club[1] = system::believed_fixed_speed(sys_, at, club[1]);
    return club;
  }
  // The region's fixed speed is the surveyed green's; the believed green may ask for another
  // (the same bits without a belief).
  if (!region_.learn_speed) club[1] = system::believed_fixed_speed(sys_, situation, club[1]);
  return club;
}

std::array<double, 3> Planner::plan(std::array<double, 2> hole) const {
  return plan(field::Situation{sys_.field().tee, hole});
}

std::array<double, 3> Planner::plan(const field::Situation& situation) const {
  auto [a, v] = prior(situation);
  double score = 1.0;
  if (!gps_.empty()) {
    const Eigen::VectorXd x = input_row(sys_.field(), inputs_, situation);
    const auto pa = stats::gp_predict(gps_[0], x);
    a += pa.mean;
    score = std::sqrt(pa.latent_variance) / kWindowAngle;
    if (gps_.size() > 1) {
      const auto pv = stats::gp_predict(gps_[1], x);
      v += pv.mean;
      score = std::max(score, std::sqrt(pv.latent_variance) / kWindowSpeed);
    }
  }
  // Any direction: the base turns for hits beyond the fixed arm's envelope (system::hit_pose).
  const auto& c = sys_.config();
  a = std::remainder(a, 2.0 * robot::kPi);
  if (region_.learn_speed || prior_model_) v = std::clamp(v, c.speed_min, c.speed_max);
  return {a, v, score};
}

std::array<double, 3> Planner::plan_to_play(const field::Situation& situation) const {
  auto p = plan(situation);
  if (prior_model_ && !region_.learn_speed)
    p[1] =
        system::believed_club_speed(sys_, system::believed_situation(sys_, situation), p[1], p[0]);
  return p;
}

learning::Model Planner::residual_model(const std::vector<Label>& labels, int putts) const {
  if (!prior_model_) throw InputError("residual model: needs a prior model");
  const auto& m = *prior_model_;
  std::vector<Label> use;
  for (const auto& l : labels)
    if (putts < 0 || l.putt < putts) use.push_back(l);
  const std::size_t real = use.size();
  for (const auto& l : sunk_) {
    if (putts >= 0 && l.putt >= putts) continue;
    bool covered = false;
    for (std::size_t k = 0; k < real && !covered; ++k)
      covered = situation_distance(use[k], l.ball, l.hole) < kPseudoCover;
    if (!covered) use.push_back(l);
  }
  if (use.empty()) return m;  // nothing known yet: the prior as it is
  const auto n = static_cast<Eigen::Index>(use.size());
  Eigen::MatrixXd x(n, static_cast<Eigen::Index>(inputs_.size()));
  Eigen::MatrixXd x_prior(n, m.num_inputs());
  for (Eigen::Index i = 0; i < n; ++i) {
    const field::Situation s{use[static_cast<std::size_t>(i)].ball,
                             use[static_cast<std::size_t>(i)].hole};
    x.row(i) = input_row(sys_.field(), inputs_, s).transpose();
    x_prior.row(i) = input_row(sys_.field(), m.input_names, s).transpose();
  }
  const learning::Predictions base = learning::predict(m, x_prior);
  learning::Model out;
  out.method = learning::Method::kGpr;
  out.input_names = inputs_;
  out.output_names = m.output_names;
  out.seed = m.seed;
  out.fixed = m.fixed;
  out.prior = prior_model_;
  Rng rng(derive_seed(m.seed, 29));
  for (int o = 0; o < m.num_outputs(); ++o) {
    const std::string& name = m.output_names[static_cast<std::size_t>(o)];
    const int kind = name == "angle" ? 0 : 1;
    // An output the labels do not correct (the speed of an angle-only region): a zero residual.
    const bool learned = name == "angle" || (name == "speed" && region_.learn_speed);
    Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
    if (learned)
      for (Eigen::Index i = 0; i < n; ++i) {
        const Label& l = use[static_cast<std::size_t>(i)];
        r(i) = (kind == 0 ? l.angle : l.speed) - base.mean(i, o);
      }
    stats::GpModel gp = residual_gp(region_, x, r, kind, rng);
    learning::FitReport rep;
    rep.length_scales = gp.hyper.length_scales;
    rep.signal_std = gp.hyper.signal_std;
    rep.noise_std = gp.hyper.noise_std;
    rep.log_marginal_likelihood = gp.log_marginal_likelihood;
    out.reports.push_back(rep);
    out.gps.push_back(std::move(gp));
  }
  return out;
}

}  // namespace mg::selfteach
