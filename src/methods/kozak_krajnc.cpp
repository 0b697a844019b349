// Kozak–Krajnc building blocks. See include/fairspline/methods/kozak_krajnc.hpp.
#include "fairspline/methods/kozak_krajnc.hpp"

#include <cmath>
#include <string>

#include "fairspline/error.hpp"

namespace fairspline {

namespace {

double ratio(double num, double den, const char* what) {
  if (den == 0.0) {
    throw Error(ErrorCode::kInvalidArgument, std::string("kozak-krajnc: ") + what +
                                                 " is zero, so the constants (2.6) are undefined");
  }
  return num / den;
}

}  // namespace

KozakKrajncConstants kozak_krajnc_constants(Point t0, Point t1, Point t2, Point t3, Vec2 d0,
                                            Vec2 d3) {
  for (Vec2 v : {t0, t1, t2, t3, d0, d3}) {
    if (!is_finite(v)) throw Error(ErrorCode::kNonFinite, "kozak-krajnc: non-finite data");
  }
  const Vec2 a = t1 - t0, b = t2 - t1, c = t3 - t2;
  const double d01 = cross(a, b), d02 = cross(a, c), d12 = cross(b, c);
  const double e0 = cross(d0, a), e3 = cross(c, d3);
  KozakKrajncConstants k;
  k.lambda1 = ratio(d02, d01, "det(dT0, dT1) (T0, T1, T2 collinear)");
  k.lambda2 = ratio(d02, d12, "det(dT1, dT2) (T1, T2, T3 collinear)");
  k.mu1 = ratio(cross(d0, b), e0, "det(d0, dT0) (d0 along the first chord)");
  k.mu2 = ratio(cross(b, d3), e3, "det(dT2, d3) (d3 along the last chord)");
  k.delta1 = ratio(d01, e0, "det(d0, dT0) (d0 along the first chord)");
  k.delta2 = ratio(d12, e3, "det(dT2, d3) (d3 along the last chord)");
  return k;
}

std::optional<ParameterPair> kozak_krajnc_boundary_alpha0(double lambda1, double lambda2) {
  if (!(lambda1 > 0.0 && lambda2 > 0.0 && std::isfinite(lambda1) && std::isfinite(lambda2))) {
    return std::nullopt;
  }
  const double a = 1.0 + lambda1;
  auto t1_of = [a](double t2) { return (a * t2 * t2 * t2 - 1.0) / (a * t2 * t2 - 1.0); };
  // g decreases from g(lo) = λ2 > 0 to g(1) = −1 on (lo, 1) (proof of Lemma 2.1).
  auto g = [&](double t2) {
    const double p = a * t2 * t2 * t2 - 1.0, q = a * t2 * t2 - 1.0;
    return lambda2 - lambda1 * (1.0 + lambda2) * p * p / (q * q * q);
  };
  double lo = 1.0 / std::cbrt(a), hi = 1.0;
  for (int it = 0; it < 200 && hi - lo > 0.0; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (g(mid) > 0.0 ? lo : hi) = mid;
  }
  const double t2 = 0.5 * (lo + hi);
  return ParameterPair{t1_of(t2), t2};
}

std::optional<ParameterPair> kozak_krajnc_boundary_alpha3(double lambda1, double lambda2) {
  const auto s = kozak_krajnc_boundary_alpha0(lambda2, lambda1);
  if (!s) return std::nullopt;
  return ParameterPair{1.0 - s->t2, 1.0 - s->t1};
}

std::optional<double> kozak_krajnc_phi2(double lambda1, double lambda2) {
  const auto s = kozak_krajnc_boundary_alpha0(lambda1, lambda2);
  if (!s) return std::nullopt;
  const double t1 = s->t1, t2 = s->t2;
  const double num = lambda2 * (1.0 - t1) / (t2 * t2) - lambda1 * t1 / ((1.0 - t2) * (1.0 - t2));
  const double den = lambda2 * (1.0 - t2) / (t1 * t1) - lambda1 * t2 / ((1.0 - t1) * (1.0 - t1));
  return num / den - 1.0;
}

std::optional<double> kozak_krajnc_phi1(double lambda1, double lambda2) {
  const auto s = kozak_krajnc_boundary_alpha3(lambda1, lambda2);
  if (!s) return std::nullopt;
  const double t1 = s->t1, t2 = s->t2;
  const double num = lambda1 * t2 / ((1.0 - t1) * (1.0 - t1)) - lambda2 * (1.0 - t2) / (t1 * t1);
  const double den = lambda1 * t1 / ((1.0 - t2) * (1.0 - t2)) - lambda2 * (1.0 - t1) / (t2 * t2);
  return num / den - 1.0;
}

double kozak_krajnc_phi3(double lambda1, double lambda2, double mu1) {
  return lambda2 * mu1 / (lambda1 * (lambda2 * mu1 - 1.0 - std::sqrt(1.0 + mu1)));
}

double kozak_krajnc_phi4(double lambda1, double lambda2, double mu1) {
  const double lm = lambda2 * mu1;
  return lm * (lm * (1.0 + 2.0 * lambda1) - 2.0 * lambda1) /
         (lambda1 * lambda1 * (lm - 1.0) * (lm - 1.0));
}

bool kozak_krajnc_theorem_2_4(const KozakKrajncConstants& c) {
  if (!(c.lambda1 > 0 && c.lambda2 > 0 && c.delta1 > 0 && c.delta2 > 0 && c.mu1 > 0 && c.mu2 > 0)) {
    return false;
  }
  const double p1 = *kozak_krajnc_phi1(c.lambda1, c.lambda2);
  const double p2 = *kozak_krajnc_phi2(c.lambda1, c.lambda2);
  return (c.mu1 < p1 && c.mu2 < p2) || (c.mu1 > p1 && c.mu2 > p2);
}

bool kozak_krajnc_theorem_2_5(const KozakKrajncConstants& c) {
  if (!(c.delta1 > 0 && c.delta2 > 0)) return false;
  auto holds = [](double l1, double l2, double m1, double m2) {
    return l1 > 0 && l2 < 0 && m1 > 0 && kozak_krajnc_phi3(l1, l2, m1) < m2 &&
           m2 < kozak_krajnc_phi4(l1, l2, m1);
  };
  return holds(c.lambda1, c.lambda2, c.mu1, c.mu2) || holds(c.lambda2, c.lambda1, c.mu2, c.mu1);
}

}  // namespace fairspline
