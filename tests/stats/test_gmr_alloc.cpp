// The GMR hot path must not touch the heap. We interpose malloc for this test binary (glibc) and
// count calls while the measured region runs. Eigen allocates through malloc, so this sees it.
#include <atomic>
#include <cstdlib>

#include <gtest/gtest.h>

#include "stats/gmr.hpp"
#include "stats/gpr.hpp"
#include "test_util.hpp"

#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
#define MG_COUNT_MALLOC 1
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

namespace mg::stats {
namespace {

TEST(StatsGmrAlloc, PredictDoesNotAllocate) {
#ifndef MG_COUNT_MALLOC
  GTEST_SKIP() << "malloc interposition needs glibc without sanitizers";
#else
  mg::Rng rng(31);
  const Gmm g = testing::random_gmm(5, 6, rng);
  const GmrConditioner cond(g, {0, 1, 2}, {3, 4, 5});
  auto ws = cond.make_workspace();
  Eigen::VectorXd x = Eigen::VectorXd::Random(3);
  Eigen::VectorXd mean(3), h(5);
  Eigen::MatrixXd cov(3, 3);
  // Sanity check that the counter works at all.
  g_counting = true;
  void* p = std::malloc(64);
  g_counting = false;
  std::free(p);
  ASSERT_EQ(g_mallocs.load(), 1);
  g_mallocs = 0;

  g_counting = true;
  for (int i = 0; i < 100; ++i) {
    x(0) = 0.1 * i;
    cond.predict_mean(x, mean, ws);
    cond.predict(x, mean, cov, ws);
    cond.responsibilities(x, h, ws);
  }
  g_counting = false;
  EXPECT_EQ(g_mallocs.load(), 0);
  EXPECT_TRUE(mean.allFinite() && cov.allFinite());
#endif
}

TEST(StatsGprAlloc, GpPredictDoesNotAllocate) {
#ifndef MG_COUNT_MALLOC
  GTEST_SKIP() << "malloc interposition needs glibc without sanitizers";
#else
  const Eigen::MatrixXd x = Eigen::MatrixXd::Random(20, 2);
  const Eigen::VectorXd y = x.col(0) + x.col(1);
  const GpModel m = make_gp_model(x, y, GpHyperparameters{Eigen::Vector2d(0.5, 0.7), 1.0, 0.1});
  GpWorkspace ws = make_gp_workspace(m);
  Eigen::Vector2d q(0.1, 0.2);
  double sum = 0.0;
  g_mallocs = 0;
  g_counting = true;
  for (int i = 0; i < 100; ++i) {
    q(0) = 0.01 * i;
    sum += gp_predict(m, q, ws).mean;
  }
  g_counting = false;
  EXPECT_EQ(g_mallocs.load(), 0);
  EXPECT_TRUE(std::isfinite(sum));
#endif
}

}  // namespace
}  // namespace mg::stats
