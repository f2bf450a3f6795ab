#pragma once
/// JSON form of a GMM: {"type": "gmm", "dim": D, "priors": [K], "means": [[D] x K],
/// "covariances": [[[D] x D] x K]}. Numbers are written in shortest round-trip form, so
/// `gmm_from_json(gmm_to_json(g))` gives back the same bits.
#include <string_view>

#include <nlohmann/json.hpp>

#include "stats/gmm.hpp"

namespace mg::stats {

nlohmann::json gmm_to_json(const Gmm& gmm);

/// Parses and validates (`Gmm::validate`); throws `mg::InputError` naming the field on any problem.
/// `where` prefixes error messages (e.g. the file and key the object came from).
Gmm gmm_from_json(const nlohmann::json& j, std::string_view where = "GMM");

// Helpers for other JSON readers of this part; all throw `mg::InputError` naming `where`.
Eigen::VectorXd json_to_vector(const nlohmann::json& j, std::string_view where);
Eigen::MatrixXd json_to_matrix(const nlohmann::json& j, std::string_view where);
nlohmann::json vector_to_json(const Eigen::VectorXd& v);
nlohmann::json matrix_to_json(const Eigen::MatrixXd& m);  ///< row-major nested arrays

}  // namespace mg::stats
