// Learner model files: the JSON form of a Model (format "minigolf-learner", format_version
// kModelFormatVersion), its reading with an error naming the field, save and load.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/io.hpp"
#include "core/json_io.hpp"
#include "learning/learner.hpp"
#include "stats/gmm_io.hpp"

namespace mg::learning {
namespace {

// ---- JSON reading helpers: every failure names the field.
const nlohmann::json& field(const nlohmann::json& j, const char* key, std::string_view where) {
  if (!j.is_object())
    throw InputError(fmt::format("{}: expected a JSON object, got {}", where, j.type_name()));
  if (!j.contains(key)) throw InputError(fmt::format("{}: missing field '{}'", where, key));
  return j.at(key);
}
double number(const nlohmann::json& j, const char* key, std::string_view where) {
  const auto& v = field(j, key, where);
  if (!v.is_number())
    throw InputError(fmt::format("{}.{}: expected a number, got {}", where, key, v.type_name()));
  const double d = v.get<double>();
  if (!std::isfinite(d))
    throw InputError(fmt::format("{}.{}: expected a finite number", where, key));
  return d;
}
std::string text(const nlohmann::json& j, const char* key, std::string_view where) {
  const auto& v = field(j, key, where);
  if (!v.is_string())
    throw InputError(fmt::format("{}.{}: expected a string, got {}", where, key, v.type_name()));
  return v.get<std::string>();
}
std::vector<std::string> names(const nlohmann::json& j, const char* key, std::string_view where) {
  const auto& v = field(j, key, where);
  if (!v.is_array() || v.empty())
    throw InputError(fmt::format("{}.{}: expected a non-empty array of names", where, key));
  std::vector<std::string> out;
  for (const auto& e : v) {
    if (!e.is_string() || e.get<std::string>().empty())
      throw InputError(
          fmt::format("{}.{}: expected non-empty strings, got {}", where, key, e.dump()));
    // A name twice would feed one column to both places (every query then predicts alike).
    if (std::find(out.begin(), out.end(), e.get<std::string>()) != out.end())
      throw InputError(fmt::format("{}.{}: '{}' appears twice (expected distinct names)", where,
                                   key, e.get<std::string>()));
    out.push_back(e.get<std::string>());
  }
  return out;
}

nlohmann::json report_json(const Model& m, int o) {
  const FitReport& r = m.reports[static_cast<std::size_t>(o)];
  nlohmann::json j;
  if (m.method == Method::kGpr) {
    j["length_scales"] = stats::vector_to_json(r.length_scales);
    j["signal_std"] = r.signal_std;
    j["noise_std"] = r.noise_std;
    j["log_marginal_likelihood"] = r.log_marginal_likelihood;
  } else {
    j["n_gaussians"] = r.n_gaussians;
    j["reg_covar"] = r.reg_covar;
    j["log_likelihood"] = r.log_likelihood;
    j["bic"] = r.bic;
  }
  return j;
}

}  // namespace

nlohmann::json report_to_json(const Model& m) {
  nlohmann::json j = nlohmann::json::object();
  for (int o = 0; o < m.num_outputs(); ++o)
    j[m.output_names[static_cast<std::size_t>(o)]] = report_json(m, o);
  return j;
}

nlohmann::json model_to_json(const Model& m) {
  nlohmann::json j;
  j["format"] = "minigolf-learner";
  j["format_version"] = kModelFormatVersion;
  j["method"] = std::string(method_name(m.method));
  j["inputs"] = m.input_names;
  j["outputs"] = m.output_names;
  j["seed"] = m.seed;
  if (m.method == Method::kGpr) {
    j["training_inputs"] = stats::matrix_to_json(m.gps.front().inputs);
    j["gps"] = nlohmann::json::array();
    for (std::size_t o = 0; o < m.gps.size(); ++o) {
      const stats::GpModel& gp = m.gps[o];
      j["gps"].push_back({{"output", m.output_names[o]},
                          {"length_scales", stats::vector_to_json(gp.hyper.length_scales)},
                          {"signal_std", gp.hyper.signal_std},
                          {"noise_std", gp.hyper.noise_std},
                          {"training_targets", stats::vector_to_json(gp.targets)}});
    }
  } else {
    j["input_standardization"] = {{"mean", stats::vector_to_json(m.input_standardizer.mean)},
                                  {"scale", stats::vector_to_json(m.input_standardizer.scale)}};
    j["output_standardization"] = {{"mean", stats::vector_to_json(m.output_standardizer.mean)},
                                   {"scale", stats::vector_to_json(m.output_standardizer.scale)}};
    j["gmms"] = nlohmann::json::array();
    for (const auto& g : m.gmms) j["gmms"].push_back(stats::gmm_to_json(g));
  }
  if (!m.fixed.empty()) {
    j["fixed"] = nlohmann::json::object();
    for (const auto& [n, v] : m.fixed) j["fixed"][n] = v;
  }
  j["fit"] = report_to_json(m);
  if (m.prior) j["prior"] = model_to_json(*m.prior);
  return j;
}

namespace {
Model model_from_json_at(const nlohmann::json& j, std::string_view where, int depth);
}  // namespace

Model model_from_json(const nlohmann::json& j, std::string_view where) {
  return model_from_json_at(j, where, 0);
}

namespace {
Model model_from_json_at(const nlohmann::json& j, std::string_view where, int depth) {
  const std::string fmt_name = text(j, "format", where);
  if (fmt_name != "minigolf-learner")
    throw InputError(
        fmt::format("{}: format: expected \"minigolf-learner\", got \"{}\"", where, fmt_name));
  const auto& ver = field(j, "format_version", where);
  if (!ver.is_number_integer() || ver.get<long long>() != kModelFormatVersion)
    throw InputError(
        fmt::format("{}: format_version: expected {} (this build reads version {}), got {}", where,
                    kModelFormatVersion, kModelFormatVersion, ver.dump()));
  Model m;
  m.method = parse_method(text(j, "method", where));
  m.input_names = names(j, "inputs", where);
  m.output_names = names(j, "outputs", where);
  const auto& seed = field(j, "seed", where);
  if (!seed.is_number_unsigned() && !(seed.is_number_integer() && seed.get<long long>() >= 0))
    throw InputError(
        fmt::format("{}.seed: expected a non-negative integer, got {}", where, seed.dump()));
  m.seed = seed.get<std::uint64_t>();
  if (j.contains("fixed")) {
    const auto& fx = j["fixed"];
    if (!fx.is_object())
      throw InputError(fmt::format("{}.fixed: expected an object of numbers", where));
    for (auto it = fx.begin(); it != fx.end(); ++it) {
      if (!it.value().is_number() || !std::isfinite(it.value().get<double>()))
        throw InputError(fmt::format("{}.fixed.{}: expected a finite number, got {}", where,
                                     it.key(), it.value().dump()));
      for (const auto& o : m.output_names)
        if (o == it.key())
          throw InputError(fmt::format("{}.fixed.{}: is also an output", where, it.key()));
      m.fixed.emplace_back(it.key(), it.value().get<double>());
    }
  }
  const int ni = m.num_inputs();
  const int no = m.num_outputs();
  const std::string w(where);

  if (m.method == Method::kGpr) {
    const Eigen::MatrixXd x =
        stats::json_to_matrix(field(j, "training_inputs", where), w + ".training_inputs");
    if (x.cols() != ni || x.rows() < 1)
      throw InputError(fmt::format("{}.training_inputs: expected rows of {} values, got {} x {}",
                                   where, ni, x.rows(), x.cols()));
    const auto& gps = field(j, "gps", where);
    if (!gps.is_array() || static_cast<int>(gps.size()) != no)
      throw InputError(
          fmt::format("{}.gps: expected an array of {} GPs (one per output)", where, no));
    for (int o = 0; o < no; ++o) {
      const std::string gw = fmt::format("{}.gps[{}]", where, o);
      const auto& g = gps[static_cast<std::size_t>(o)];
      if (text(g, "output", gw) != m.output_names[static_cast<std::size_t>(o)])
        throw InputError(fmt::format("{}.output: expected \"{}\"", gw,
                                     m.output_names[static_cast<std::size_t>(o)]));
      stats::GpHyperparameters h;
      h.length_scales = stats::json_to_vector(field(g, "length_scales", gw), gw + ".length_scales");
      h.signal_std = number(g, "signal_std", gw);
      h.noise_std = number(g, "noise_std", gw);
      const Eigen::VectorXd y =
          stats::json_to_vector(field(g, "training_targets", gw), gw + ".training_targets");
      try {
        m.gps.push_back(stats::make_gp_model(x, y, h));
      } catch (const Error& e) {
        throw InputError(fmt::format("{}: {}", gw, e.what()));
      }
    }
  } else {
    auto standardizer = [&](const char* key, int dim) {
      const auto& s = field(j, key, where);
      const std::string sw = fmt::format("{}.{}", where, key);
      Standardizer st;
      st.mean = stats::json_to_vector(field(s, "mean", sw), sw + ".mean");
      st.scale = stats::json_to_vector(field(s, "scale", sw), sw + ".scale");
      if (st.mean.size() != dim || st.scale.size() != dim || !(st.scale.array() > 0.0).all())
        throw InputError(fmt::format("{}: expected {} means and {} positive scales", sw, dim, dim));
      return st;
    };
    m.input_standardizer = standardizer("input_standardization", ni);
    m.output_standardizer = standardizer("output_standardization", no);
    const auto& gmms = field(j, "gmms", where);
    const int expected = m.method == Method::kGmr ? no : 1;
    const int dim = m.method == Method::kGmr ? ni + 1 : ni + no;
    if (!gmms.is_array() || static_cast<int>(gmms.size()) != expected)
      throw InputError(fmt::format("{}.gmms: expected an array of {} GMMs", where, expected));
    for (int g = 0; g < expected; ++g) {
      const std::string gw = fmt::format("{}.gmms[{}]", where, g);
      m.gmms.push_back(stats::gmm_from_json(gmms[static_cast<std::size_t>(g)], gw));
      if (m.gmms.back().dim() != dim)
        throw InputError(
            fmt::format("{}: expected dimension {}, got {}", gw, dim, m.gmms.back().dim()));
    }
  }

  // Fit summaries: recorded at training time (informational).
  const auto& fit = field(j, "fit", where);
  m.reports.resize(static_cast<std::size_t>(no));
  for (int o = 0; o < no; ++o) {
    const std::string& name = m.output_names[static_cast<std::size_t>(o)];
    const std::string fw = fmt::format("{}.fit.{}", where, name);
    const auto& r = field(fit, name.c_str(), fmt::format("{}.fit", where));
    FitReport& rep = m.reports[static_cast<std::size_t>(o)];
    if (m.method == Method::kGpr) {
      rep.length_scales =
          stats::json_to_vector(field(r, "length_scales", fw), fw + ".length_scales");
      rep.signal_std = number(r, "signal_std", fw);
      rep.noise_std = number(r, "noise_std", fw);
      rep.log_marginal_likelihood = number(r, "log_marginal_likelihood", fw);
    } else {
      const auto& k = field(r, "n_gaussians", fw);
      if (!k.is_number_integer())
        throw InputError(fmt::format("{}.n_gaussians: expected an integer", fw));
      rep.n_gaussians = k.get<int>();
      if (r.is_object() && r.contains("reg_covar")) rep.reg_covar = number(r, "reg_covar", fw);
      rep.log_likelihood = number(r, "log_likelihood", fw);
      rep.bic = number(r, "bic", fw);
    }
  }
  if (j.contains("prior")) {
    if (depth + 1 >= kMaxPriorDepth)
      throw InputError(
          fmt::format("{}.prior: residual models nest at most {} deep", where, kMaxPriorDepth));
    auto prior = std::make_shared<Model>(
        model_from_json_at(j["prior"], fmt::format("{}.prior", where), depth + 1));
    for (const auto& name : prior->input_names)
      if (std::find(m.input_names.begin(), m.input_names.end(), name) == m.input_names.end())
        throw InputError(
            fmt::format("{}.prior: input '{}': expected among the residual's inputs", where, name));
    if (prior->output_names != m.output_names)
      throw InputError(fmt::format("{}.prior: expected the residual's outputs", where));
    if (prior->fixed != m.fixed)
      throw InputError(fmt::format("{}.prior: expected the residual's fixed values", where));
    m.prior = std::move(prior);
  }
  return m;
}
}  // namespace

void save_model(const Model& model, const std::filesystem::path& path) {
  write_file_atomic(path, model_to_json(model).dump(2) + "\n");
}

Model load_model(const std::filesystem::path& path) {
  return model_from_json(read_json_file(path), path.string());
}

}  // namespace mg::learning
