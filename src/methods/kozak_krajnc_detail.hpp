// Internals of the Kozak–Krajnc single-piece solver that the tests check directly.
#pragma once

#include <vector>

namespace fairspline::detail {

/// The Lie derivatives L_0..L_n at (t1, t2) of G along the level curves of F, for the system
/// (2.3) cleared of denominators, F = t2²(1−t2) − (1+μ1) t1²(1−t1) + A1 (t2−t1) t1² t2² and
/// G = t1(1−t1)² − (1+μ2) t2(1−t2)² + A2 (t2−t1)(1−t1)²(1−t2)²: L_0 = G,
/// L_{j+1} = F_t1 ∂L_j/∂t2 − F_t2 ∂L_j/∂t1 (docs/methods/kozak-krajnc.md, step 5), as the solver
/// forms them to resolve multiple solutions.
std::vector<double> kozak_krajnc_lie_derivatives(double mu1, double mu2, double a1, double a2,
                                                 double t1, double t2, int n);

}  // namespace fairspline::detail
