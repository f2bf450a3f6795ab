// Cost of the real-time robot functions the 500 Hz controller calls every tick.
#include <benchmark/benchmark.h>

#include "robot/dynamics.hpp"
#include "robot/ik.hpp"
#include "robot/wam_model.hpp"

namespace {

using mg::robot::ArmModel;
using mg::robot::Vector7;

const ArmModel& arm() {
  static const ArmModel a{mg::robot::WamMount{}};
  return a;
}

Vector7 sample_q() { return (Vector7() << 0.1, 0.6, -0.1, 1.8, 0.2, 0.5, 0.3).finished(); }

void BM_InverseDynamics(benchmark::State& state) {
  const Vector7 q = sample_q(), qd = Vector7::Constant(0.5), qdd = Vector7::Constant(1.0);
  Vector7 tau;
  for (auto _ : state) {
    auto s = mg::robot::inverse_dynamics(arm(), q, qd, qdd, tau);
    benchmark::DoNotOptimize(s);
    benchmark::DoNotOptimize(tau);
  }
}
BENCHMARK(BM_InverseDynamics);

void BM_DhClubJacobian(benchmark::State& state) {
  const Vector7 q = sample_q();
  Eigen::Isometry3d pose;
  mg::robot::Matrix67 jac;
  for (auto _ : state) {
    mg::robot::dh_club_jacobian(arm(), q, pose, jac);
    benchmark::DoNotOptimize(jac);
  }
}
BENCHMARK(BM_DhClubJacobian);

void BM_VelocityIk(benchmark::State& state) {
  const Vector7 q = sample_q();
  Eigen::Isometry3d pose;
  mg::robot::Matrix67 jac;
  mg::robot::dh_club_jacobian(arm(), q, pose, jac);
  mg::robot::Vector6 v;
  v << 0.5, 0.1, 0.0, 0.0, 0.0, 0.2;
  const Vector7 posture = Vector7::Constant(0.05);
  const mg::robot::IkOptions options;
  Vector7 qd;
  for (auto _ : state) {
    auto s = mg::robot::velocity_ik(arm(), q, jac, v, posture, options, qd);
    benchmark::DoNotOptimize(s);
    benchmark::DoNotOptimize(qd);
  }
}
BENCHMARK(BM_VelocityIk);

// One full tick of face tracking (DH pose + Jacobian, error, velocity IK) near the rest posture.
void BM_TrackFace(benchmark::State& state) {
  const Vector7 q(mg::robot::kDefaultRestPosture.data());
  mg::robot::FaceTarget target;
  target.position =
      mg::robot::dh_club_pose(arm(), q).translation() + Eigen::Vector3d(0.001, 0.0, 0.0);
  target.velocity << 0.5, 0.0, 0.0, 0.0, 0.0, 0.0;
  const mg::robot::IkOptions options;
  Vector7 qd;
  for (auto _ : state) {
    auto s = mg::robot::track_face(arm(), q, target, q, options, qd);
    benchmark::DoNotOptimize(s);
    benchmark::DoNotOptimize(qd);
  }
}
BENCHMARK(BM_TrackFace);

// Worst case: a far target saturates joints, so the IK re-solves once per locked joint.
void BM_TrackFaceSaturated(benchmark::State& state) {
  const Vector7 q = sample_q();
  mg::robot::FaceTarget target;
  target.position =
      mg::robot::dh_club_pose(arm(), q).translation() + Eigen::Vector3d(0.2, 0.0, 0.0);
  const mg::robot::IkOptions options;
  Vector7 qd;
  for (auto _ : state) {
    auto s = mg::robot::track_face(arm(), q, target, q, options, qd);
    benchmark::DoNotOptimize(s);
    benchmark::DoNotOptimize(qd);
  }
}
BENCHMARK(BM_TrackFaceSaturated);

}  // namespace
