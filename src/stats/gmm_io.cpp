#include "stats/gmm_io.hpp"

#include <fmt/format.h>

#include "core/error.hpp"

namespace mg::stats {

nlohmann::json vector_to_json(const Eigen::VectorXd& v) {
  nlohmann::json a = nlohmann::json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(v(i));
  return a;
}

nlohmann::json matrix_to_json(const Eigen::MatrixXd& m) {
  nlohmann::json a = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) a.push_back(vector_to_json(m.row(i).transpose()));
  return a;
}

Eigen::VectorXd json_to_vector(const nlohmann::json& j, std::string_view where) {
  if (!j.is_array())
    throw InputError(fmt::format("{}: expected an array of numbers, got {}", where, j.type_name()));
  Eigen::VectorXd v(static_cast<Eigen::Index>(j.size()));
  for (std::size_t i = 0; i < j.size(); ++i) {
    if (!j[i].is_number())
      throw InputError(
          fmt::format("{}[{}]: expected a number, got {}", where, i, j[i].type_name()));
    v(static_cast<Eigen::Index>(i)) = j[i].get<double>();
    if (!std::isfinite(v(static_cast<Eigen::Index>(i))))
      throw InputError(fmt::format("{}[{}]: expected a finite number", where, i));
  }
  return v;
}

Eigen::MatrixXd json_to_matrix(const nlohmann::json& j, std::string_view where) {
  if (!j.is_array())
    throw InputError(fmt::format("{}: expected an array of rows, got {}", where, j.type_name()));
  const std::size_t rows = j.size();
  Eigen::MatrixXd m;
  for (std::size_t i = 0; i < rows; ++i) {
    const Eigen::VectorXd r = json_to_vector(j[i], fmt::format("{}[{}]", where, i));
    if (i == 0) m.resize(static_cast<Eigen::Index>(rows), r.size());
    if (r.size() != m.cols())
      throw InputError(fmt::format("{}[{}]: expected {} values (like row 0), got {}", where, i,
                                   m.cols(), r.size()));
    m.row(static_cast<Eigen::Index>(i)) = r.transpose();
  }
  return m;
}

nlohmann::json gmm_to_json(const Gmm& gmm) {
  nlohmann::json j;
  j["type"] = "gmm";
  j["dim"] = gmm.dim();
  j["priors"] = vector_to_json(gmm.priors);
  j["means"] = nlohmann::json::array();
  j["covariances"] = nlohmann::json::array();
  for (int k = 0; k < gmm.num_components(); ++k) {
    j["means"].push_back(vector_to_json(gmm.means[static_cast<std::size_t>(k)]));
    j["covariances"].push_back(matrix_to_json(gmm.covariances[static_cast<std::size_t>(k)]));
  }
  return j;
}

Gmm gmm_from_json(const nlohmann::json& j, std::string_view where) {
  if (!j.is_object())
    throw InputError(fmt::format("{}: expected a JSON object, got {}", where, j.type_name()));
  for (const char* key : {"priors", "means", "covariances"})
    if (!j.contains(key)) throw InputError(fmt::format("{}: missing field '{}'", where, key));
  if (j.contains("type") && (!j["type"].is_string() || j["type"].get<std::string>() != "gmm"))
    throw InputError(fmt::format("{}: type: expected \"gmm\", got {}", where, j["type"].dump()));
  Gmm gmm;
  gmm.priors = json_to_vector(j["priors"], fmt::format("{}.priors", where));
  const auto& means = j["means"];
  const auto& covs = j["covariances"];
  if (!means.is_array() || !covs.is_array())
    throw InputError(fmt::format("{}: means and covariances: expected arrays", where));
  if (means.size() != static_cast<std::size_t>(gmm.priors.size()) ||
      covs.size() != static_cast<std::size_t>(gmm.priors.size()))
    throw InputError(
        fmt::format("{}: expected {} means and covariances (one per prior), got {} and {}", where,
                    gmm.priors.size(), means.size(), covs.size()));
  for (std::size_t k = 0; k < means.size(); ++k) {
    gmm.means.push_back(json_to_vector(means[k], fmt::format("{}.means[{}]", where, k)));
    gmm.covariances.push_back(json_to_matrix(covs[k], fmt::format("{}.covariances[{}]", where, k)));
  }
  if (j.contains("dim")) {
    if (!j["dim"].is_number_integer() || j["dim"].get<int>() != gmm.dim())
      throw InputError(fmt::format("{}: dim: expected {} (the size of the means), got {}", where,
                                   gmm.dim(), j["dim"].dump()));
  }
  try {
    gmm.validate();
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", where, e.what()));
  }
  return gmm;
}

}  // namespace mg::stats
