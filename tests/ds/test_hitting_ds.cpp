#include "ds/hitting_ds.hpp"

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <new>
#include <numbers>

#include <gtest/gtest.h>
#include <Eigen/LU>

#include "core/error.hpp"
#include "core/io.hpp"
#include "ds/demonstrations.hpp"
#include "ds/hitting_model.hpp"

// Counts heap allocations so the real-time claim of the DS evaluation is tested, not assumed.
namespace {
std::atomic<long> g_allocations{0};
}  // namespace
void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace mg::ds {
namespace {

using Vec3 = Eigen::Vector3d;
constexpr double kDeg = std::numbers::pi / 180.0;

const HittingModel& shipped_model() {
  static const HittingModel m = read_hitting_model(data_dir() / "models" / "hitting-default.json");
  return m;
}

// A second, independently fitted model (small K, fresh demonstrations) so the properties below
// do not hinge on one lucky file.
const HittingModel& fresh_model() {
  static const HittingModel m = [] {
    DemoGeneratorConfig cfg;
    cfg.count = 6;
    Rng rng(42);
    HittingFitOptions opt;
    opt.seds.gaussians = 3;
    opt.seds.seed = 42;
    opt.seds.max_evaluations = 400;
    return fit_hitting_model(generate_demonstrations(cfg, rng), opt);
  }();
  return m;
}

double angle_error(const Vec3& v, double theta, const HittingModel& m) {
  return std::acos(std::clamp(v.normalized().dot(rotation_about_z(theta) * m.psi0()), -1.0, 1.0));
}

class BothModels : public ::testing::TestWithParam<int> {
 protected:
  const HittingModel& model() const { return GetParam() == 0 ? shipped_model() : fresh_model(); }
};

TEST_P(BothModels, RolloutsFromAGridAroundTheDemonstrationsReachTheBallAlongPsi0) {
  const HittingModel& m = model();
  int count = 0;
  double worst_angle = 0.0, worst_speed = 0.0, worst_pos = 0.0;
  for (double bx : {-0.5, -0.4, -0.3, -0.2, -0.12})
    for (double by : {-0.15, -0.05, 0.05, 0.15})
      for (double bz : {0.02, 0.1, 0.2, 0.3}) {
        HittingCommand c;
        c.start = m.x_star() + Vec3(bx, by, bz);
        c.speed = m.default_speed();
        const RolloutResult r = rollout(m, c);
        ASSERT_TRUE(r.reached) << "start " << c.start.transpose() << ": " << r.stop_reason
                               << " error " << r.position_error;
        worst_pos = std::max(worst_pos, r.position_error);
        EXPECT_LT(std::abs(r.velocity.norm() / c.speed - 1.0), 0.01)
            << "start " << c.start.transpose();
        worst_speed = std::max(worst_speed, std::abs(r.velocity.norm() / c.speed - 1.0));
        // The direction guarantee is for starts where the demonstrations start (>= 0.25 m behind);
        // closer starts begin inside the guidance zone, beside the ball, and only have to arrive.
        if (bx <= -0.25) {
          EXPECT_LT(angle_error(r.velocity, 0.0, m), 1.0 * kDeg) << "start " << c.start.transpose();
          worst_angle = std::max(worst_angle, angle_error(r.velocity, 0.0, m));
        } else {
          EXPECT_LT(angle_error(r.velocity, 0.0, m), 5.0 * kDeg) << "start " << c.start.transpose();
        }
        ++count;
      }
  RecordProperty("worst_angle_deg", std::to_string(worst_angle / kDeg));
  RecordProperty("worst_speed_rel", std::to_string(worst_speed));
  RecordProperty("worst_position_m", std::to_string(worst_pos));
  EXPECT_EQ(count, 80);
}

TEST_P(BothModels, RolloutsFromFarOutsideReachTheBallWithoutStallingOrDiverging) {
  const HittingModel& m = model();
  for (double r : {0.6, 1.5, 3.0})
    for (double az = 0.0; az < 2.0 * std::numbers::pi - 1e-9; az += std::numbers::pi / 4)
      for (double el : {-0.6, 0.0, 0.7}) {
        HittingCommand c;
        c.start = m.x_star() +
                  r * Vec3(std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), std::sin(el));
        c.speed = m.default_speed();
        RolloutOptions o;
        o.record = false;
        o.max_duration = 60.0;
        const RolloutResult res = rollout(m, c, o);
        EXPECT_TRUE(res.reached) << "start " << c.start.transpose() << ": " << res.stop_reason
                                 << ", error " << res.position_error << " after " << res.duration
                                 << " s";
      }
}

TEST_P(BothModels, AnyAngleAndSpeedIsHitWithinOneDegreeAndOnePercent) {
  const HittingModel& m = model();
  const std::vector<Vec3> starts{{-0.35, 0.05, 0.15}, {-0.25, -0.05, 0.08}, {-0.45, 0.12, 0.2}};
  for (const Modulator mod : {Modulator::kConstant, Modulator::kSine})
    for (double theta : {-0.5, -0.25, 0.0, 0.2, 0.5})
      for (double speed : {0.8, 1.5, 2.4})
        for (const Vec3& s : starts) {
          HittingCommand c;
          c.angle = theta;
          c.speed = speed;
          c.modulator = mod;
          c.start = m.x_star() +
                    rotation_about_z(theta) * s;  // the demonstrated region, turned with the shot
          const RolloutResult r = rollout(m, c);
          ASSERT_TRUE(r.reached) << r.stop_reason;
          EXPECT_LT(angle_error(r.velocity, theta, m), 1.0 * kDeg)
              << to_string(mod) << " theta " << theta << " v " << speed << " start "
              << s.transpose();
          EXPECT_NEAR(r.velocity.norm(), speed, 0.01 * speed)
              << to_string(mod) << " theta " << theta << " start " << s.transpose();
          EXPECT_LT(r.position_error, 0.002);
        }
}

TEST_P(BothModels, LyapunovFunctionDecreasesEverywhere) {
  // d/dt |x - x*|^2 = 2 (x - x*) . xdot < 0, also inside the guidance blend and for rotated shots.
  const HittingModel& m = model();
  HittingDsData data(m);
  for (double theta : {-0.5, 0.0, 0.4}) {
    data.set_command(m, {theta, 1.2, Modulator::kSine, m.x_star() + Vec3(-0.4, 0.1, 0.1)});
    for (double x = -0.6; x <= 0.6; x += 0.05)
      for (double y = -0.3; y <= 0.3; y += 0.05)
        for (double z = -0.1; z <= 0.3; z += 0.05) {
          const Vec3 p = m.x_star() + Vec3(x, y, z) + Vec3(1e-4, 1e-4, 1e-4);
          const Vec3 v = hitting_ds_velocity(m, data, p);
          ASSERT_TRUE(v.allFinite());
          EXPECT_LT((p - m.x_star()).dot(v), 0.0) << p.transpose();
        }
  }
}

INSTANTIATE_TEST_SUITE_P(Models, BothModels, ::testing::Values(0, 1), [](const auto& info) {
  return info.param == 0 ? std::string("Shipped") : std::string("Fresh");
});

TEST(HittingDs, ShippedModelSatisfiesTheConstraintsAndReproducesTheDemonstrations) {
  const HittingModel& m = shipped_model();
  EXPECT_LE(m.max_eigenvalue(), -1e-4);
  EXPECT_NEAR(m.default_speed(), 1.5, 0.15);
  const auto demos = read_demonstrations(data_dir() / "demos" / "default.csv");
  const ReproductionError e = reproduction_error(m, demos);
  RecordProperty("velocity_rmse", std::to_string(e.velocity_rmse));
  RecordProperty("direction_rmse_deg", std::to_string(e.direction_rmse / kDeg));
  RecordProperty("mean_path_distance", std::to_string(e.mean_path_distance));
  RecordProperty("max_path_distance", std::to_string(e.max_path_distance));
  std::printf(
      "reproduction: velocity RMSE %.4f m/s, direction RMSE %.2f deg, path distance mean %.4f m "
      "max %.4f m\n",
      e.velocity_rmse, e.direction_rmse / kDeg, e.mean_path_distance, e.max_path_distance);
  EXPECT_EQ(e.all_reached, static_cast<int>(demos.size()));
  EXPECT_LT(e.mean_path_distance, 0.02);
  EXPECT_LT(e.max_path_distance, 0.06);
}

TEST(HittingDs, SineModulatorMeetsEquations26) {
  const double d0 = 0.4;
  for (double sd : {0.5, 0.9, 1.0, 1.6, 3.0}) {
    EXPECT_DOUBLE_EQ(speed_modulator(Modulator::kSine, sd, d0, 0.0), sd);    // 2.6b
    EXPECT_NEAR(speed_modulator(Modulator::kSine, sd, d0, d0), 1.0, 1e-15);  // 2.6c
    double prev = speed_modulator(Modulator::kSine, sd, d0, 0.0);
    const double h = 1e-4;
    for (double r = h; r <= d0 + 1e-12; r += h) {  // 2.6a: monotone toward 1
      const double s = speed_modulator(Modulator::kSine, sd, d0, r);
      if (sd > 1.0) {
        EXPECT_LE(s, prev + 1e-15);
      } else if (sd < 1.0) {
        EXPECT_GE(s, prev - 1e-15);
      }
      prev = s;
    }
    // 2.6d: smooth, including the joins at 0 (zero slope) and d0 (meets the constant 1 with zero
    // slope).
    const double e = 1e-6;
    const auto deriv = [&](double r) {
      return (speed_modulator(Modulator::kSine, sd, d0, r + e) -
              speed_modulator(Modulator::kSine, sd, d0, r - e)) /
             (2 * e);
    };
    EXPECT_NEAR(deriv(d0), 0.0, 1e-4);
    EXPECT_NEAR((speed_modulator(Modulator::kSine, sd, d0, e) - sd) / e, 0.0, 1e-4);
    double max_jump = 0.0;
    for (double r = 0.001; r < d0 + 0.05; r += 0.001)
      max_jump = std::max(max_jump, std::abs(deriv(r + 0.001) - deriv(r)));
    EXPECT_LT(max_jump, 0.05 * std::abs(1.0 - sd) + 1e-9);
    EXPECT_DOUBLE_EQ(speed_modulator(Modulator::kConstant, sd, d0, 0.2), sd);
  }
}

TEST(HittingDs, RotationAboutTheVerticalThroughTheBall) {
  for (double t : {-0.5, 0.1, 0.5}) {
    const Eigen::Matrix3d r = rotation_about_z(t);
    EXPECT_TRUE((r * r.transpose()).isApprox(Eigen::Matrix3d::Identity(), 1e-14));
    EXPECT_NEAR(r.determinant(), 1.0, 1e-14);
    EXPECT_TRUE((r * Vec3::UnitX()).isApprox(Vec3(std::cos(t), std::sin(t), 0.0), 1e-14));
  }
  // Equivariance (eq. 2.10): the rotated DS at a rotated point is the rotated default DS.
  const HittingModel& m = shipped_model();
  HittingDsData d0(m), dt(m);
  const double theta = 0.37;
  d0.set_command(m, {0.0, 1.1, Modulator::kConstant, m.x_star() + Vec3(-0.3, 0, 0.1)});
  dt.set_command(m, {theta, 1.1, Modulator::kConstant, m.x_star() + Vec3(-0.3, 0, 0.1)});
  const Eigen::Matrix3d r = rotation_about_z(theta);
  for (const Vec3& y : {Vec3(-0.3, 0.05, 0.1), Vec3(-0.05, 0.01, 0.0), Vec3(0.2, -0.3, 0.4)}) {
    const Vec3 a = hitting_ds_velocity(m, dt, m.x_star() + r * y);
    const Vec3 b = r * hitting_ds_velocity(m, d0, m.x_star() + y);
    EXPECT_LT((a - b).norm(), 1e-9 * std::max(1.0, b.norm()));
  }
}

TEST(HittingDs, ConstantModulatorScalesTheWholeMotion) {
  const HittingModel& m = shipped_model();
  HittingDsData a(m), b(m);
  const Vec3 start = m.x_star() + Vec3(-0.4, 0.05, 0.15);
  a.set_command(m, {0.0, m.default_speed(), Modulator::kConstant, start});
  b.set_command(m, {0.0, 2.0 * m.default_speed(), Modulator::kConstant, start});
  for (const Vec3& p : {start, Vec3(m.x_star() + Vec3(-0.1, 0.0, 0.03))})
    EXPECT_TRUE(hitting_ds_velocity(m, b, p).isApprox(2.0 * hitting_ds_velocity(m, a, p), 1e-12));
  // The sine modulator leaves the start untouched (s(d0) = 1).
  b.set_command(m, {0.0, 2.0 * m.default_speed(), Modulator::kSine, start});
  EXPECT_TRUE(hitting_ds_velocity(m, b, start).isApprox(hitting_ds_velocity(m, a, start), 1e-12));
}

TEST(HittingDs, EvaluationAllocatesNothing) {
  const HittingModel& m = shipped_model();
  HittingDsData data(m);
  data.set_command(m, {0.3, 1.7, Modulator::kSine, m.x_star() + Vec3(-0.4, 0.1, 0.1)});
  Vec3 acc = Vec3::Zero();
  const long before = g_allocations.load();
  for (int i = 0; i < 1000; ++i) {
    const Vec3 p = m.x_star() + Vec3(-0.4 + 0.0004 * i, 0.1 - 0.0001 * i, 0.1 - 0.0001 * i);
    acc += hitting_ds_velocity(m, data, p);
    acc += hitting_velocity(m, data) * (ball_reached(m, data, p) ? 1.0 : 0.0);
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_TRUE(acc.allFinite());
}

TEST(HittingDs, FiniteAndAttractingFarFromAllComponents) {
  const HittingModel& m = shipped_model();
  HittingDsData data(m);
  data.set_command(m, {0.2, 1.5, Modulator::kConstant, m.x_star() + Vec3(-0.3, 0, 0.1)});
  for (double r : {10.0, 1e3, 1e6})
    for (const Vec3& dir :
         {Vec3(1, 0, 0), Vec3(-1, 1, 0).normalized(), Vec3(0, 0, -1), Vec3(0.3, -0.4, 0.866)}) {
      const Vec3 v = hitting_ds_velocity(m, data, m.x_star() + r * dir);
      ASSERT_TRUE(v.allFinite()) << r;
      EXPECT_LT(v.normalized().dot(dir), 0.0) << r << " " << dir.transpose();
      // Bounded speed: the strength factor is clamped, so nothing explodes far away.
      EXPECT_LE(
          v.norm(),
          1.5 / m.default_speed() * m.settings().max_strength_fraction * m.default_speed() + 1e-9);
    }
}

TEST(HittingDs, BallReachedOnlyPastTheHittingPlaneNearTheBall) {
  const HittingModel& m = shipped_model();
  HittingDsData data(m);
  data.set_command(m, {0.5, 1.0, Modulator::kConstant, m.x_star() + Vec3(-0.3, 0, 0.1)});
  const Vec3 psi = data.direction();
  EXPECT_TRUE(ball_reached(m, data, m.x_star() + 0.001 * psi));
  EXPECT_FALSE(ball_reached(m, data, m.x_star() - 0.001 * psi));
  EXPECT_FALSE(ball_reached(m, data, m.x_star() + 0.05 * psi));
  EXPECT_TRUE(hitting_velocity(m, data).isApprox(1.0 * psi));
}

TEST(HittingModelFile, RoundTripKeepsEveryBit) {
  const HittingModel& m = shipped_model();
  const auto dir = std::filesystem::temp_directory_path() / "mg_ds_test";
  std::filesystem::create_directories(dir);
  write_hitting_model(dir / "m.json", m);
  const HittingModel back = read_hitting_model(dir / "m.json");
  EXPECT_EQ(hitting_model_to_json(back).dump(), hitting_model_to_json(m).dump());
  HittingDsData a(m), b(back);
  const Vec3 p = m.x_star() + Vec3(-0.2, 0.03, 0.07);
  EXPECT_EQ(hitting_ds_velocity(m, a, p), hitting_ds_velocity(back, b, p));
}

TEST(HittingModelFile, MalformedFilesAreClearErrors) {
  const nlohmann::json good = hitting_model_to_json(shipped_model());
  const auto expect_input_error = [](const nlohmann::json& j, const std::string& needle) {
    try {
      hitting_model_from_json(j, "test.json");
      ADD_FAILURE() << "expected InputError containing '" << needle << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("test.json"), std::string::npos) << e.what();
    }
  };
  auto j = good;
  j["format_version"] = 99;
  expect_input_error(j, "format_version");
  j = good;
  j.erase("seds");
  expect_input_error(j, "seds");
  j = good;
  j["x_star"] = {0.0, 1.0};
  expect_input_error(j, "x_star");
  j = good;
  j["default_speed"] = 3.0;
  expect_input_error(j, "default_speed");
  j = good;
  j["psi0"] = {0.0, 0.0, 1.0};
  expect_input_error(j, "psi0");
  // An expanding component: the velocity block made equal to +Sigma_y (A = +I).
  j = good;
  auto& cov = j["seds"]["gmm"]["covariances"][0];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      cov[3 + r][c] = cov[r][c];
      cov[r][3 + c] = cov[r][c];
      cov[3 + r][3 + c] = cov[r][c].get<double>() + (r == c ? 1.0 : 0.0);
    }
  auto& mean = j["seds"]["gmm"]["means"][0];
  for (int r = 0; r < 3; ++r) mean[3 + r] = mean[r];
  expect_input_error(j, "lambda_max");

  const auto dir = std::filesystem::temp_directory_path() / "mg_ds_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "broken.json") << "{ not json";
  EXPECT_THROW(read_hitting_model(dir / "broken.json"), InputError);
  EXPECT_THROW(read_hitting_model(dir / "does-not-exist.json"), IoError);
}

TEST(HittingModelFit, SameSeedSameBitsAndBadDemonstrationsAreErrors) {
  DemoGeneratorConfig cfg;
  cfg.count = 3;
  Rng rng(9);
  const auto demos = generate_demonstrations(cfg, rng);
  HittingFitOptions opt;
  opt.seds.gaussians = 2;
  opt.seds.max_evaluations = 150;
  const std::string a = hitting_model_to_json(fit_hitting_model(demos, opt)).dump();
  const std::string b = hitting_model_to_json(fit_hitting_model(demos, opt)).dump();
  EXPECT_EQ(a, b);
  EXPECT_THROW(fit_hitting_model({}, opt), InputError);
  auto bad = demos;
  bad[0].x.resize(1);
  bad[0].xdot.resize(1);
  bad[0].t.resize(1);
  EXPECT_THROW(fit_hitting_model(bad, opt), InputError);
  bad = demos;
  bad[1].x.back() += Vec3(0.2, 0.0, 0.0);
  EXPECT_THROW(fit_hitting_model(bad, opt), InputError);
  bad = demos;
  bad[2].xdot[3].x() = std::nan("");
  EXPECT_THROW(fit_hitting_model(bad, opt), InputError);
}

TEST(HittingModelFit, FitOnTheShippedDemonstrationsSatisfiesTheConstraints) {
  const auto demos = read_demonstrations(data_dir() / "demos" / "default.csv");
  for (const SedsObjective obj : {SedsObjective::kLikelihood, SedsObjective::kMse}) {
    HittingFitOptions opt;
    opt.seds.gaussians = 3;
    opt.seds.objective = obj;
    HittingFitReport rep;
    const HittingModel m = fit_hitting_model(demos, opt, &rep);
    EXPECT_LE(m.max_eigenvalue(), -1e-4) << to_string(obj);
    EXPECT_LT(rep.seds.final_objective, rep.seds.initial_objective) << to_string(obj);
    for (const auto& c : rep.seds.components) EXPECT_LE(stability_eigenvalue(c.a), -1e-4);
    const ReproductionError e = reproduction_error(m, demos);
    EXPECT_EQ(e.all_reached, static_cast<int>(demos.size()));
    EXPECT_LT(e.mean_path_distance, 0.02) << to_string(obj);
  }
}

TEST(HittingModelFit, FewAndNoisyDemonstrationsStillGiveAStableModelThatHitsAlongPsi0) {
  for (const auto& [count, noise] :
       std::vector<std::pair<int, double>>{{1, 1.0}, {2, 10.0}, {5, 10.0}}) {
    DemoGeneratorConfig cfg;
    cfg.count = count;
    cfg.position_noise *= noise;
    cfg.velocity_noise *= noise;
    Rng rng(500 + static_cast<std::uint64_t>(count));
    HittingFitOptions opt;
    opt.seds.gaussians = 2;
    opt.seds.max_evaluations = 200;
    const HittingModel m = fit_hitting_model(generate_demonstrations(cfg, rng), opt);
    EXPECT_LE(m.max_eigenvalue(), -1e-4);
    for (double theta : {-0.4, 0.0, 0.4})
      for (const Vec3& s : {Vec3(-0.3, 0.0, 0.1), Vec3(-0.4, 0.1, 0.15)}) {
        HittingCommand c{theta, 1.0, Modulator::kSine, m.x_star() + rotation_about_z(theta) * s};
        const RolloutResult r = rollout(m, c);
        ASSERT_TRUE(r.reached) << count << " demos: " << r.stop_reason;
        EXPECT_LT(angle_error(r.velocity, theta, m), 1.0 * kDeg)
            << count << " demos, noise x" << noise;
        EXPECT_NEAR(r.velocity.norm(), 1.0, 0.01);
      }
  }
}

TEST(HittingDs, BadCommandsAreClearErrors) {
  const HittingModel& m = shipped_model();
  HittingDsData d(m);
  EXPECT_THROW(d.set_command(m, {0.0, -1.0, Modulator::kConstant, Vec3(-0.3, 0, 0.1)}), InputError);
  EXPECT_THROW(d.set_command(m, {std::nan(""), 1.0, Modulator::kConstant, Vec3(-0.3, 0, 0.1)}),
               InputError);
  EXPECT_THROW(d.set_command(m, {0.0, 1.0, Modulator::kSine, m.x_star()}), InputError);
  EXPECT_THROW(parse_modulator("cubic"), InputError);
}

}  // namespace
}  // namespace mg::ds
