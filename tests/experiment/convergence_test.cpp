// The convergence criterion (sim/experiment/convergence.h) on synthetic means.
#include "sim/experiment/convergence.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace fovsim;

namespace {

// Two methods whose means approach 30/25 dB and FLIP 0.10/0.20 as 1/spp.
ConvergenceResult synthetic(bool swap_at_16) {
  ConvergenceResult r;
  r.spps = {1, 4, 16, 64};
  r.labels = {"a", "b"};
  for (int spp : r.spps) {
    const double e = 4.0 / spp;
    // psnr, fpsnr, ssim, flip, fvvdp_jod (convergence_metrics() order); JOD not computed.
    std::vector<std::vector<double>> lvl = {{30 - e, 30 - e, 0.9, 0.10 + 0.01 * e, NAN},
                                            {25 - e, 25 - e, 0.8, 0.20 + 0.01 * e, NAN}};
    if (swap_at_16 && spp == 16) std::swap(lvl[0], lvl[1]);
    r.value.push_back(lvl);
  }
  return r;
}

}  // namespace

TEST(Convergence, ChoosesLowestLevelWithinTolerance) {
  ConvergenceResult r = synthetic(false);
  evaluate_convergence(r, ConvergenceOptions{});
  // Moves: 1->4 3 dB, 4->16 0.75 dB, 16->64 0.1875 dB: no level within 0.1 dB.
  EXPECT_EQ(r.chosen_spp, 0);
  ConvergenceOptions loose;
  loose.tol_db = 1.0;
  loose.tol_flip = 0.01;  // FLIP moves 0.0075 from 4 to 16
  evaluate_convergence(r, loose);
  EXPECT_EQ(r.chosen_spp, 4);
  EXPECT_FALSE(r.level_ok[0]);
  EXPECT_TRUE(r.level_ok[1]);
  EXPECT_TRUE(r.level_ok[2]);
  EXPECT_FALSE(r.level_ok[3]);
  EXPECT_NE(r.markdown().find("chosen spp = 4"), std::string::npos);
}

TEST(Convergence, RankingChangeBlocksALevel) {
  ConvergenceResult r = synthetic(true);
  ConvergenceOptions loose;
  loose.tol_db = 100;
  loose.tol_flip = 100;
  evaluate_convergence(r, loose);
  // The order flips at 16 only: levels 1 and 4 see a different ranking later on.
  EXPECT_FALSE(r.level_ok[0]);
  EXPECT_FALSE(r.level_ok[1]);
  EXPECT_FALSE(r.level_ok[2]);  // 16 differs from 64
  EXPECT_EQ(r.chosen_spp, 0);
}

TEST(Convergence, InfinitePsnrMovesUnlessBothInfinite) {
  ConvergenceResult r;
  r.spps = {1, 4, 16};
  r.labels = {"full"};
  const double inf = INFINITY;
  r.value = {
      {{inf, inf, 1, 0, 10}}, {{40, 40, 0.99, 0.01, 9.9}}, {{40.05, 40.05, 0.99, 0.01, 9.9}}};
  evaluate_convergence(r, ConvergenceOptions{});
  EXPECT_FALSE(r.level_ok[0]);
  EXPECT_TRUE(r.level_ok[1]);
  EXPECT_EQ(r.chosen_spp, 4);
}

TEST(Convergence, MetricsAreTheRegistrysHeadlineMetrics) {
  const auto& m = convergence_metrics();
  ASSERT_EQ(m.size(), 5u);
  EXPECT_EQ(m[0].name, "psnr");
  EXPECT_EQ(m[3].name, "flip");
  EXPECT_FALSE(m[3].higher_better);
  EXPECT_EQ(m[4].name, "fvvdp_jod");
  EXPECT_TRUE(m[4].higher_better);
  EXPECT_EQ(m[4].tol_kind, 2);
}

TEST(Convergence, JodToleranceBlocksALevel) {
  ConvergenceResult r;
  r.spps = {1, 4, 16};
  r.labels = {"a"};
  r.value = {{{30, 30, 0.9, 0.1, 9.0}}, {{30, 30, 0.9, 0.1, 9.1}}, {{30, 30, 0.9, 0.1, 9.12}}};
  evaluate_convergence(r, ConvergenceOptions{});  // tol_jod 0.05: 1 -> 4 moves 0.1 JOD
  EXPECT_FALSE(r.level_ok[0]);
  EXPECT_TRUE(r.level_ok[1]);
  EXPECT_EQ(r.chosen_spp, 4);
  EXPECT_NE(r.markdown().find("fvvdp_jod"), std::string::npos);
  EXPECT_EQ(r.csv().substr(0, r.csv().find('\n')),
            "spp,label,psnr,fpsnr,ssim,flip,fvvdp_jod,ref_seconds,level_ok");
}

TEST(Convergence, RejectsBadLevels) {
  ConvergenceOptions o;
  o.spps = {1, 8};
  EXPECT_ANY_THROW(run_convergence("none.json", {}, o));
}
