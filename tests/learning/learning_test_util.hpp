#pragma once
// Shared helpers for the learning tests: seeded synthetic datasets and scratch directories.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "core/csv.hpp"
#include "core/io.hpp"
#include "core/rng.hpp"
#include "learning/dataset.hpp"
#include "learning/learner.hpp"

namespace mg::learning::testing {

inline const std::filesystem::path kDataDir =
    std::filesystem::path(MINIGOLF_TEST_DATA_DIR) / "learning";

// A fresh directory per test, removed afterwards.
class ScratchDir {
 public:
  ScratchDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            fmt::format("mg_learning_{}_{}_{}", ::getpid(), info->test_suite_name(), info->name());
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() { std::filesystem::remove_all(path_); }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

// The flat-field law (thesis 3.2): aim straight at the hole, theta = atan2(xi_y, xi_x); speed
// grows with the distance like sqrt(2 a d) for a constant rolling deceleration a.
inline double flat_angle(double x, double y) { return std::atan2(y, x); }
inline double flat_speed(double x, double y) {
  return std::sqrt(2.0 * 0.6 * std::hypot(x, y)) + 0.2;
}

inline Dataset flat_field(int n, std::uint64_t seed, double noise = 0.01) {
  mg::Rng rng(seed);
  std::uniform_real_distribution<double> ux(0.5, 3.0), uy(-1.2, 1.2);
  std::normal_distribution<double> eps(0.0, noise);
  Dataset d;
  d.source = "flat";
  d.input_names = {"xi_x", "xi_y"};
  d.output_names = {"angle", "speed"};
  d.inputs.resize(n, 2);
  d.outputs.resize(n, 2);
  for (int i = 0; i < n; ++i) {
    const double x = ux(rng), y = uy(rng);
    d.inputs.row(i) << x, y;
    d.outputs.row(i) << flat_angle(x, y) + eps(rng), flat_speed(x, y) + eps(rng);
  }
  return d;
}

inline Dataset linear_map(int n, std::uint64_t seed, double noise = 0.01) {
  mg::Rng rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> eps(0.0, noise);
  Dataset d;
  d.source = "linear";
  d.input_names = {"xi_x", "xi_y"};
  d.output_names = {"angle", "speed"};
  d.inputs.resize(n, 2);
  d.outputs.resize(n, 2);
  for (int i = 0; i < n; ++i) {
    const double x = u(rng), y = u(rng);
    d.inputs.row(i) << x, y;
    d.outputs.row(i) << 0.3 + 0.8 * x - 0.5 * y + eps(rng), 1.0 + 0.2 * x + 0.6 * y + eps(rng);
  }
  return d;
}

inline void write_dataset(const Dataset& d, const std::filesystem::path& path) {
  std::vector<std::string> header = d.input_names;
  header.insert(header.end(), d.output_names.begin(), d.output_names.end());
  std::vector<std::vector<double>> rows;
  for (int i = 0; i < d.size(); ++i) {
    std::vector<double> r;
    for (Eigen::Index j = 0; j < d.inputs.cols(); ++j) r.push_back(d.inputs(i, j));
    for (Eigen::Index j = 0; j < d.outputs.cols(); ++j) r.push_back(d.outputs(i, j));
    rows.push_back(r);
  }
  mg::write_file_atomic(path, mg::format_csv(header, rows));
}

// Training options of the tests: method `m`, K = k (0: chosen), seed 7.
inline TrainOptions options(Method m, int k = 0) {
  TrainOptions o;
  o.method = m;
  o.num_gaussians = k;
  o.seed = 7;
  return o;
}

inline bool same_bits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

}  // namespace mg::learning::testing
