// The functions the 500 Hz controller calls must not touch the heap. We interpose malloc for this
// test binary (glibc) and count calls while the measured region runs; Eigen allocates through it.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>

#include "robot/dynamics.hpp"
#include "robot/ik.hpp"
#include "robot_test_util.hpp"

#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
#define MG_ROBOT_COUNT_MALLOC 1
namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_mallocs{0};
}  // namespace
extern "C" void* __libc_malloc(std::size_t size);
extern "C" void* malloc(std::size_t size) {
  if (g_counting.load(std::memory_order_relaxed)) g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}
#endif

namespace mg::robot {
namespace {

using testing::WamFixture;

TEST_F(WamFixture, RealTimeFunctionsDoNotAllocate) {
#ifndef MG_ROBOT_COUNT_MALLOC
  GTEST_SKIP() << "malloc interposition needs glibc without sanitizers";
#else
  const IkOptions options;
  FaceTarget target;
  target.position = {-0.2, 0.0, 0.1};
  Vector7 q = testing::rest_posture(), qd, tau;
  Matrix7 mass;
  Matrix67 jac;
  Vector6 e;
  g_counting = true;
  void* p = std::malloc(64);
  g_counting = false;
  std::free(p);
  ASSERT_EQ(g_mallocs.load(), 1);
  g_mallocs = 0;

  g_counting = true;
  for (int k = 0; k < 100; ++k) {
    (void)track_face(*arm_, q, target, testing::rest_posture(), options, qd, &e);
    (void)inverse_dynamics(*arm_, q, qd, Vector7::Ones(), tau);
    (void)gravity_torque(*arm_, q, tau);
    (void)mass_matrix(*arm_, q, mass);
    set_joint_positions(ids_, data_.get(), q);
    mj_kinematics(model_.get(), data_.get());
    mj_comPos(model_.get(), data_.get());
    club_jacobian(ids_, model_.get(), data_.get(), jac);
    (void)club_pose(ids_, data_.get());
    q += options.dt * qd;
  }
  g_counting = false;
  EXPECT_EQ(g_mallocs.load(), 0);
  EXPECT_TRUE(q.allFinite() && tau.allFinite() && jac.allFinite());
#endif
}

}  // namespace
}  // namespace mg::robot
