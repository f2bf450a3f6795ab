#include "ds/hitting_model.hpp"

#include <chrono>
#include <cmath>
#include <exception>
#include <optional>

#include <fmt/format.h>

#include "core/check.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "core/json_io.hpp"
#include "stats/gmm_io.hpp"

namespace mg::ds {
namespace {

using Vec3 = Eigen::Vector3d;

Vec3 require_vec3(const std::string& name, const Vec3& v) {
  if (!v.allFinite()) throw InputError(fmt::format("{}: expected finite coordinates", name));
  return v;
}

Vec3 checked_psi0(const Vec3& psi0) {
  require_vec3("psi0", psi0);
  if (std::abs(psi0.norm() - 1.0) > 1e-6 || std::abs(psi0.z()) > 1e-6)
    throw InputError(fmt::format("psi0: expected a horizontal unit vector, got ({}, {}, {})",
                                 psi0.x(), psi0.y(), psi0.z()));
  return psi0.normalized();
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void HittingDsSettings::validate() const {
  require_positive("blend_inner", blend_inner);
  if (!(blend_outer > blend_inner))
    throw InputError(
        fmt::format("blend_outer: expected > blend_inner ({}), got {}", blend_inner, blend_outer));
  require_in_range("cone_cos_min", cone_cos_min, 0.0, 0.99);
  if (!(cone_cos_max > cone_cos_min && cone_cos_max <= 1.0))
    throw InputError(
        fmt::format("cone_cos_max: expected in ({}, 1], got {}", cone_cos_min, cone_cos_max));
  require_in_range("line_exponent", line_exponent, 1.5, 20.0);
  require_in_range("min_strength_fraction", min_strength_fraction, 0.01, 1.0);
  require_in_range("max_strength_fraction", max_strength_fraction, 1.0, 100.0);
}

HittingModel::HittingModel(stats::Gmm seds_gmm, stats::Gmm strength_gmm, const Vec3& x_star,
                           const Vec3& psi0, const HittingDsSettings& settings, double margin)
    : seds_gmm_(std::move(seds_gmm)),
      strength_gmm_(std::move(strength_gmm)),
      x_star_(require_vec3("x_star", x_star)),
      psi0_(checked_psi0(psi0)),
      settings_(settings),
      seds_gmr_(seds_gmm_, {0, 1, 2}, {3, 4, 5}),
      strength_gmr_(strength_gmm_, {0, 1, 2}, {3}) {
  settings_.validate();
  if (seds_gmm_.dim() != 6)
    throw InputError(fmt::format("SEDS GMM: expected dimension 6, got {}", seds_gmm_.dim()));
  if (strength_gmm_.dim() != 4)
    throw InputError(
        fmt::format("strength GMM: expected dimension 4, got {}", strength_gmm_.dim()));
  double bias = 0.0;
  max_eigenvalue_ = seds_check(seds_gmm_, &bias);
  if (!(max_eigenvalue_ <= -margin))
    throw NumericalError(
        fmt::format("SEDS GMM: expected lambda_max(A_k + A_k^T) <= {} for every component, got {}",
                    -margin, max_eigenvalue_));
  if (!(bias <= 1e-6))
    throw NumericalError(
        fmt::format("SEDS GMM: expected b_k = -A_k x* (relative residual <= 1e-6), got {}", bias));
  Eigen::VectorXd v = strength_gmr_.predict(Eigen::VectorXd::Zero(3)).mean;
  default_speed_ = v[0];
  if (!(std::isfinite(default_speed_) && default_speed_ > 1e-3))
    throw NumericalError(
        fmt::format("default hitting speed v(x*): expected > 0.001 m/s, got {}", default_speed_));
}

HittingModel fit_hitting_model(const std::vector<Demonstration>& demos,
                               const HittingFitOptions& options, HittingFitReport* report) {
  const auto t0 = std::chrono::steady_clock::now();
  options.seds.validate();
  options.settings.validate();
  require_in_range("min_speed_fraction", options.min_speed_fraction, 0.0, 0.9);
  const DemoSummary summary = summarize_demonstrations(demos, options.end_tolerance);

  std::size_t total = 0;
  for (const auto& d : demos) total += d.size();
  const double min_speed = options.min_speed_fraction * summary.hitting_speed;
  SedsData data;
  data.y.resize(3, static_cast<Eigen::Index>(total));
  data.ydot.resize(3, static_cast<Eigen::Index>(total));
  Eigen::MatrixXd strength(static_cast<Eigen::Index>(total), 4);
  Eigen::Index n_seds = 0, n_all = 0;
  for (const auto& d : demos)
    for (std::size_t i = 0; i < d.size(); ++i) {
      const Vec3 y = d.x[i] - summary.x_star;
      strength.row(n_all++) << y.transpose(), d.xdot[i].norm();
      // Near-rest samples carry no direction: leave them out of SEDS (as the reference does).
      if (d.xdot[i].norm() < min_speed) continue;
      data.y.col(n_seds) = y;
      data.ydot.col(n_seds) = d.xdot[i];
      ++n_seds;
    }
  data.y.conservativeResize(3, n_seds);
  data.ydot.conservativeResize(3, n_seds);
  const int k = options.seds.gaussians;
  if (n_seds < std::max<Eigen::Index>(2 * k, 4))
    throw InputError(
        fmt::format("demonstrations: expected at least {} moving samples for {} Gaussians, got {}",
                    std::max(2 * k, 4), k, n_seds));

  // A fit on valid demonstrations must not fail: if K components cannot be fitted (the joint
  // covariance of a component is not positive definite in floating point, the constraints do
  // not hold, ...), fit K - 1 and say so.
  const int kv_requested = options.strength_gaussians > 0 ? options.strength_gaussians : k;
  if (kv_requested > n_all)
    throw InputError(
        fmt::format("strength Gaussians: expected <= {} (samples), got {}", n_all, kv_requested));
  std::vector<std::string> notes;
  std::optional<HittingModel> fitted;
  SedsResult seds;
  int kv = kv_requested;
  // Per K: the plain fit; if its model cannot be built, the same fit without the components it
  // left empty; then a refit with A_k bounded (SedsOptions::max_rate). A fit that works is
  // never altered.
  constexpr double kBoundedRate = 500.0;  // [1/s], a 2 ms time constant
  constexpr double kMinPrior = 1e-6;
  for (int kk = k; kk >= 1 && !fitted; --kk) {
    kv = options.strength_gaussians > 0 ? kv_requested : kk;
    Rng rng(derive_seed(options.seds.seed, 1));
    stats::EmOptions em;
    em.reg_covar = options.seds.covariance_floor;
    const stats::Gmm strength_gmm = stats::fit_gmm(strength, kv, rng, em).gmm;
    std::string why;
    std::exception_ptr first_error;
    bool plain_fit = false;  // attempt 0 got as far as a SEDS result
    for (int attempt = 0; attempt < 3 && !fitted; ++attempt) {
      SedsOptions so = options.seds;
      so.gaussians = kk;
      if (attempt == 2) so.max_rate = kBoundedRate;
      if (attempt == 1 && !plain_fit) continue;
      try {
        if (attempt != 1) seds = fit_seds(data, so);
        if (attempt == 0) plain_fit = true;
        if (attempt >= 1) drop_empty_components(seds, kMinPrior);
        if (attempt == 1 && seds.notes.empty())
          continue;  // nothing to drop: go to the bounded refit
        fitted.emplace(seds_to_gmm(seds.components), strength_gmm, summary.x_star, summary.psi0,
                       options.settings, options.seds.margin);
        if (attempt == 2)
          notes.push_back(
              fmt::format("K = {}: refitted with |A_ij| <= {:g} 1/s ({})", kk, kBoundedRate, why));
      } catch (const Error& e) {
        if (why.empty()) {
          why = e.what();
          first_error = std::current_exception();
        }
        seds.notes.clear();
      }
    }
    if (!fitted) {
      if (kk == 1) std::rethrow_exception(first_error);
      notes.push_back(fmt::format("K = {} failed ({}); fitting K = {}", kk, why, kk - 1));
    }
  }
  for (const auto& n : seds.notes) notes.push_back(n);
  HittingModel model = std::move(*fitted);
  model.provenance = {
      {"objective", to_string(options.seds.objective)},
      {"gaussians", static_cast<int>(seds.components.size())},
      {"gaussians_requested", k},
      {"strength_gaussians", kv},
      {"seed", options.seds.seed},
      {"demonstrations", demos.size()},
      {"samples_seds", n_seds},
      {"samples_strength", n_all},
      {"initial_objective", seds.initial_objective},
      {"final_objective", seds.final_objective},
      {"evaluations", seds.evaluations},
      {"optimizer", "NLopt LD_SLSQP, analytic gradients"},
      {"optimizer_status", seds.optimizer_status},
  };
  if (!notes.empty()) model.provenance["fit_notes"] = notes;
  if (report) {
    report->seds = std::move(seds);
    report->samples_used = static_cast<int>(n_seds);
    report->notes = notes;
    report->summary = summary;
    report->fit_seconds = seconds_since(t0);
  }
  return model;
}

nlohmann::json hitting_model_to_json(const HittingModel& m) {
  const auto& s = m.settings();
  nlohmann::json j;
  j["format_version"] = kHittingModelFormatVersion;
  j["type"] = "minigolf.hitting_model";
  j["units"] = "metres, seconds, radians; GMMs are over y = x - x_star in world axes";
  j["x_star"] = {m.x_star().x(), m.x_star().y(), m.x_star().z()};
  j["psi0"] = {m.psi0().x(), m.psi0().y(), m.psi0().z()};
  j["default_speed"] = m.default_speed();
  j["max_eigenvalue"] = m.max_eigenvalue();
  j["seds"] = {{"dims", "y_x, y_y, y_z, ydot_x, ydot_y, ydot_z"},
               {"gmm", stats::gmm_to_json(m.seds_gmm())}};
  j["strength"] = {{"dims", "y_x, y_y, y_z, |ydot|"},
                   {"gmm", stats::gmm_to_json(m.strength_gmm())}};
  j["settings"] = {{"blend_inner", s.blend_inner},
                   {"blend_outer", s.blend_outer},
                   {"cone_cos_min", s.cone_cos_min},
                   {"cone_cos_max", s.cone_cos_max},
                   {"line_exponent", s.line_exponent},
                   {"min_strength_fraction", s.min_strength_fraction},
                   {"max_strength_fraction", s.max_strength_fraction}};
  j["provenance"] = m.provenance;
  return j;
}

HittingModel hitting_model_from_json(const nlohmann::json& j, const std::string& source) {
  try {
    if (!j.is_object()) throw InputError(fmt::format("{}: expected a JSON object", source));
    if (!j.contains("format_version") || !j["format_version"].is_number_integer() ||
        j["format_version"].get<int>() != kHittingModelFormatVersion)
      throw InputError(
          fmt::format("{}: format_version: expected {}, got {}", source, kHittingModelFormatVersion,
                      j.contains("format_version") ? j["format_version"].dump() : "none"));
    const auto vec3 = [&](const char* key) {
      const auto& a = j.at(key);
      if (!a.is_array() || a.size() != 3)
        throw InputError(fmt::format("{}: {}: expected 3 numbers", source, key));
      return Vec3(a[0].get<double>(), a[1].get<double>(), a[2].get<double>());
    };
    HittingDsSettings s;
    const auto& js = j.at("settings");
    s.blend_inner = js.at("blend_inner").get<double>();
    s.blend_outer = js.at("blend_outer").get<double>();
    s.cone_cos_min = js.at("cone_cos_min").get<double>();
    s.cone_cos_max = js.at("cone_cos_max").get<double>();
    s.line_exponent = js.at("line_exponent").get<double>();
    s.min_strength_fraction = js.at("min_strength_fraction").get<double>();
    s.max_strength_fraction = js.at("max_strength_fraction").get<double>();
    stats::Gmm seds = stats::gmm_from_json(j.at("seds").at("gmm"), source + ": seds.gmm");
    stats::Gmm strength =
        stats::gmm_from_json(j.at("strength").at("gmm"), source + ": strength.gmm");
    HittingModel m(std::move(seds), std::move(strength), vec3("x_star"), vec3("psi0"), s);
    const double v0 = j.at("default_speed").get<double>();
    if (!(std::abs(v0 - m.default_speed()) <= 1e-9 * std::max(1.0, std::abs(v0))))
      throw InputError(
          fmt::format("{}: default_speed: expected v(x*) = {} from the strength GMM, got {}",
                      source, m.default_speed(), v0));
    if (j.contains("provenance")) m.provenance = j["provenance"];
    return m;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: malformed hitting model: {}", source, e.what()));
  } catch (const NumericalError& e) {
    throw InputError(fmt::format("{}: {}", source, e.what()));
  } catch (const InputError& e) {
    const std::string what = e.what();
    if (what.rfind(source, 0) == 0) throw;
    throw InputError(fmt::format("{}: {}", source, what));
  }
}

void write_hitting_model(const std::filesystem::path& path, const HittingModel& model) {
  write_file_atomic(path, hitting_model_to_json(model).dump(2) + "\n");
}

HittingModel read_hitting_model(const std::filesystem::path& path) {
  return hitting_model_from_json(read_json_file(path), path.string());
}

}  // namespace mg::ds
