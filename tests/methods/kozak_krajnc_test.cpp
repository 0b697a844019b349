// Tests of the Kozak–Krajnc building blocks (src/methods/kozak_krajnc.cpp): Table 3.1's
// constants, the withheld φ values of Section 3, Lemmas 2.1–2.3 as properties, the existence
// predicates of Theorems 2.4 and 2.5 on the paper's data.
#include "fairspline/methods/kozak_krajnc.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fairspline/error.hpp"
#include "test_util.hpp"

namespace fairspline {
namespace {

// Section 3, Step 1: T0 = (−4, −4), T1 = (0, 0), T2 = (4, 0), T3 = (9 + (−1)^s, (−1)^s 4).
struct PaperData {
  Vec2 d0, d3;
  int s;
};
const PaperData kData[] = {{{2, 3}, {2, -3}, 1}, {{-2, 2}, {-2, -2}, 1}, {{-2, 2}, {-1, 2}, 0}};

KozakKrajncConstants constants_of(const PaperData& d) {
  const double sign = d.s == 1 ? -1.0 : 1.0;
  return kozak_krajnc_constants({-4, -4}, {0, 0}, {4, 0}, {9 + sign, 4 * sign}, d.d0, d.d3);
}

/// The two equations (2.3) and α0 of (2.4), α3 of (2.5), written out independently.
struct System {
  double lambda1, lambda2, mu1, mu2, delta1, delta2;
  double f1(double t1, double t2) const {
    return 1 / (t1 * t1 * (1 - t1)) - (1 + mu1) / (t2 * t2 * (1 - t2)) +
           (t2 - t1) / ((1 - t1) * (1 - t2)) * (1 + mu1 * (1 + lambda1) - lambda1 / lambda2);
  }
  double f2(double t1, double t2) const {
    return 1 / (t2 * (1 - t2) * (1 - t2)) - (1 + mu2) / (t1 * (1 - t1) * (1 - t1)) +
           (t2 - t1) / (t1 * t2) * (1 + mu2 * (1 + lambda2) - lambda2 / lambda1);
  }
  double alpha0(double t1, double t2) const {
    return delta1 * t1 * t2 / (t2 - t1) *
           (1 / (t2 * t2 * (1 - t2)) - (t2 - t1) / ((1 - t1) * (1 - t2)) * (1 + lambda1));
  }
  double alpha3(double t1, double t2) const {
    return delta2 * (1 - t1) * (1 - t2) / (t2 - t1) *
           (1 / (t1 * (1 - t1) * (1 - t1)) - (t2 - t1) / (t1 * t2) * (1 + lambda2));
  }
};

TEST(KozakKrajncConstants, Table31) {
  // λ and μ as printed. δ: the table prints 1 for all data, but δ depends on the length of the
  // tangent (Remark 2.1 says only its sign does not): with the printed d0 = (2, 3),
  // d3 = (2, −3) of data 1, δ1 = D01 / det(d0, ΔT0) = −16 / −4 = 4 (δ = 1 would need
  // d0 = (8, 12)). Data 2 and 3 give δ = 1 as printed. Only the signs enter the theorems.
  const double expected[3][6] = {
      {2, 2, 3, 3, 4, 4}, {2, 2, 0.5, 0.5, 1, 1}, {0.5, -0.5, 0.5, 0.5, 1, 1}};
  for (int k = 0; k < 3; ++k) {
    const KozakKrajncConstants c = constants_of(kData[k]);
    EXPECT_DOUBLE_EQ(c.lambda1, expected[k][0]) << k;
    EXPECT_DOUBLE_EQ(c.lambda2, expected[k][1]) << k;
    EXPECT_DOUBLE_EQ(c.mu1, expected[k][2]) << k;
    EXPECT_DOUBLE_EQ(c.mu2, expected[k][3]) << k;
    EXPECT_DOUBLE_EQ(c.delta1, expected[k][4]) << k;
    EXPECT_DOUBLE_EQ(c.delta2, expected[k][5]) << k;
  }
  // Scaling a tangent scales δ, not μ (Remark 2.1).
  const KozakKrajncConstants c =
      kozak_krajnc_constants({-4, -4}, {0, 0}, {4, 0}, {8, -4}, {8, 12}, {8, -12});
  EXPECT_DOUBLE_EQ(c.delta1, 1.0);
  EXPECT_DOUBLE_EQ(c.mu1, 3.0);
}

TEST(KozakKrajncConstants, WithheldPhiValuesOfSection3) {
  // Data 1 and 2 (λ1 = λ2 = 2): φ1 = φ2 = 2.80828202755131...; data 1 has μ > φ (second case
  // of Theorem 2.4), data 2 has μ < φ (first case).
  for (int k : {0, 1}) {
    const KozakKrajncConstants c = constants_of(kData[k]);
    const double p1 = *kozak_krajnc_phi1(c.lambda1, c.lambda2);
    const double p2 = *kozak_krajnc_phi2(c.lambda1, c.lambda2);
    EXPECT_NEAR(p1, 2.80828202755131, 1e-13);
    EXPECT_NEAR(p2, 2.80828202755131, 1e-13);
    EXPECT_TRUE(kozak_krajnc_theorem_2_4(c));
    EXPECT_FALSE(kozak_krajnc_theorem_2_5(c));
  }
  // Data 3: φ3(1/2, −1/2, 1/2) = 0.25 / (0.5 (1.25 + √1.5)) = 0.2020410288672882 and
  // φ4 = 0.25 · 1.5 / (0.25 · 1.5625) = 0.96, so φ3 < μ2 = 1/2 < φ4 (Theorem 2.5).
  const KozakKrajncConstants c = constants_of(kData[2]);
  EXPECT_NEAR(kozak_krajnc_phi3(c.lambda1, c.lambda2, c.mu1),
              0.25 / (0.5 * (1.25 + std::sqrt(1.5))), 1e-15);
  EXPECT_NEAR(kozak_krajnc_phi4(c.lambda1, c.lambda2, c.mu1), 0.96, 1e-15);
  EXPECT_TRUE(kozak_krajnc_theorem_2_5(c));
  EXPECT_FALSE(kozak_krajnc_theorem_2_4(c));
}

TEST(KozakKrajncLemmas, BoundarySolutionsSolveTheSystemWithAVanishingAlpha) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> lam(0.05, 20), mu(0.1, 10);
  for (int trial = 0; trial < 2000; ++trial) {
    const double l1 = lam(rng), l2 = lam(rng);
    // Lemma 2.1: (t̃1, t̃2) solves (2.7); with μ2 = φ2 it solves (2.3) for every μ1, α0 = 0.
    const ParameterPair s = *kozak_krajnc_boundary_alpha0(l1, l2);
    ASSERT_TRUE(0 < s.t1 && s.t1 < s.t2 && s.t2 < 1) << l1 << " " << l2;
    const double t1 = s.t1, t2 = s.t2;
    ASSERT_NEAR((1 - t1) / (t2 * t2 * (t2 - t1)), 1 + l1, 1e-9 * (1 + l1));
    ASSERT_NEAR((1 - t2) / (t1 * t1 * (t2 - t1)), l1 / l2 * (1 + l2),
                1e-9 * (1 + l1 / l2 * (1 + l2)));
    const System sys{l1, l2, mu(rng), *kozak_krajnc_phi2(l1, l2), 1, 1};
    const double scale = 1 / (t1 * t1 * (1 - t1)) + 1 / (t2 * (1 - t2) * (1 - t2));
    ASSERT_NEAR(sys.f1(t1, t2), 0, 1e-9 * scale);
    ASSERT_NEAR(sys.f2(t1, t2), 0, 1e-9 * scale);
    ASSERT_NEAR(sys.alpha0(t1, t2), 0, 1e-9 * scale);
    // Lemma 2.2: the twin, α3 = 0 with μ1 = φ1.
    const ParameterPair r = *kozak_krajnc_boundary_alpha3(l1, l2);
    ASSERT_TRUE(0 < r.t1 && r.t1 < r.t2 && r.t2 < 1);
    const System twin{l1, l2, *kozak_krajnc_phi1(l1, l2), mu(rng), 1, 1};
    const double scale2 = 1 / (r.t1 * r.t1 * (1 - r.t1)) + 1 / (r.t2 * (1 - r.t2) * (1 - r.t2));
    ASSERT_NEAR(twin.f1(r.t1, r.t2), 0, 1e-9 * scale2);
    ASSERT_NEAR(twin.f2(r.t1, r.t2), 0, 1e-9 * scale2);
    ASSERT_NEAR(twin.alpha3(r.t1, r.t2), 0, 1e-9 * scale2);
    // The symmetry t ↦ 1 − t exchanges the roles: φ1(λ1, λ2) = φ2(λ2, λ1).
    ASSERT_NEAR(*kozak_krajnc_phi1(l1, l2), *kozak_krajnc_phi2(l2, l1),
                1e-12 * (1 + std::abs(*kozak_krajnc_phi1(l1, l2))));
  }
  EXPECT_FALSE(kozak_krajnc_phi2(1, -1));
  EXPECT_FALSE(kozak_krajnc_phi1(-1, 1));
}

TEST(KozakKrajncLemmas, Lemma23Properties) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> pos(0.05, 10), neg(-10, -0.05), mu(0.01, 50);
  for (int trial = 0; trial < 5000; ++trial) {
    const double l1 = pos(rng), l2 = neg(rng), m1 = mu(rng), dm = 1e-3 * m1;
    const double p3 = kozak_krajnc_phi3(l1, l2, m1), p4 = kozak_krajnc_phi4(l1, l2, m1);
    ASSERT_LT(p3, p4);
    ASSERT_GT(kozak_krajnc_phi3(l1, l2, m1 + dm), p3);  // increasing
    ASSERT_GT(kozak_krajnc_phi4(l1, l2, m1 + dm), p4);
    // φ3(λ1, λ2, μ1) = μ2 iff φ4(λ2, λ1, μ2) = μ1 (and the twin).
    ASSERT_NEAR(kozak_krajnc_phi4(l2, l1, p3), m1, 1e-8 * (1 + m1));
    ASSERT_NEAR(kozak_krajnc_phi3(l2, l1, p4), m1, 1e-8 * (1 + m1));
  }
  EXPECT_NEAR(kozak_krajnc_phi3(2, -1, 1e12), 0.5, 1e-5);
  EXPECT_NEAR(kozak_krajnc_phi4(2, -1, 1e12), (1 + 4.0) / 4, 1e-5);
}

TEST(KozakKrajncConstants, DegenerateDataThrows) {
  const Error e = testing::expect_error([] {
    kozak_krajnc_constants({0, 0}, {1, 0}, {2, 0}, {3, 1}, {1, 1}, {1, 1});
  });
  EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
  const Error f = testing::expect_error([] {
    kozak_krajnc_constants({0, 0}, {1, 0}, {2, 1}, {3, 1}, {1, 0}, {1, 1});
  });
  EXPECT_EQ(f.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(std::string(f.what()).find("d0"), std::string::npos);
}

}  // namespace
}  // namespace fairspline
