// Shared by tests/test_vop.cpp and tests/test_vop_theta.cpp: the chain-rule check of an element
// right-hand side against Euler's equations (Eq. 5).
#pragma once

#include <eulervop/model/euler_problem.hpp>
#include <eulervop/core/scalar.hpp>

#include <algorithm>

namespace vop_test {

using eulervop::quad;
using eulervop::vec3;

// d/dtau Omega(elements) along the element right-hand side, by a central difference in quad
// (step 1e-9: truncation ~1e-18, rounding ~1e-25), against Eq. 5. Any wrong term is O(1).
template <class System, class ToOmega>
double chain_rule_mismatch(const vec3<quad>& y, System& sys, ToOmega&& Omega_of, const vec3<quad>& G) {
  vec3<quad> dy;
  sys(y, dy, quad(0));
  const quad eps("1e-9");
  vec3<quad> yp, ym;
  for (int i = 0; i < 3; ++i) {
    yp[i] = y[i] + eps * dy[i];
    ym[i] = y[i] - eps * dy[i];
  }
  const auto Op = Omega_of(yp), Omn = Omega_of(ym);
  vec3<quad> f;
  eulervop::euler_rhs(Omega_of(y), G, f);
  double worst = 0;
  for (int i = 0; i < 3; ++i) {
    const quad chain = (Op[i] - Omn[i]) / (2 * eps);
    worst = std::max(worst, static_cast<double>(fabs(chain - f[i]) / (1 + fabs(f[i]))));
  }
  return worst;
}

}  // namespace vop_test
