// Shared by the VOP tests (test_vop, test_vop_theta, test_vop_varying_torque): the chain-rule
// check of an element right-hand side against Euler's equations (Eq. 5), and random states in
// both regimes.
#pragma once

#include <eulervop/model/euler_problem.hpp>
#include <eulervop/core/scalar.hpp>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

namespace vop_test {

using eulervop::quad;
using eulervop::vec3;

// d/dtau Omega(elements) along the element right-hand side at time tau, by a central difference
// in quad (step 1e-9: truncation ~1e-18, rounding ~1e-25), against Eq. 5 with the torque
// torque.value(tau, Omega). Any wrong term is O(1).
template <class System, class ToOmega, class Torque>
double chain_rule_mismatch(const vec3<quad>& y, const quad& tau, System& sys, ToOmega&& Omega_of,
                           const Torque& torque) {
  vec3<quad> dy;
  sys(y, dy, tau);
  const quad eps("1e-9");
  vec3<quad> yp, ym;
  for (int i = 0; i < 3; ++i) {
    yp[i] = y[i] + eps * dy[i];
    ym[i] = y[i] - eps * dy[i];
  }
  const vec3<quad> Om = Omega_of(y), Op = Omega_of(yp), Omn = Omega_of(ym);
  vec3<quad> f;
  eulervop::euler_rhs(Om, torque.value(tau, Om), f);
  double worst = 0;
  for (int i = 0; i < 3; ++i) {
    const quad chain = (Op[i] - Omn[i]) / (2 * eps);
    worst = std::max(worst, static_cast<double>(fabs(chain - f[i]) / (1 + fabs(f[i]))));
  }
  return worst;
}

// The same with a constant torque G, at tau = 0.
template <class System, class ToOmega>
double chain_rule_mismatch(const vec3<quad>& y, System& sys, ToOmega&& Omega_of, const vec3<quad>& G) {
  struct constant {
    vec3<quad> G;
    vec3<quad> value(const quad&, const vec3<quad>&) const { return G; }
  };
  return chain_rule_mismatch(y, quad(0), sys, Omega_of, constant{G});
}

// Random states in both regimes: built in the W frame from (d1, d2, am) with
// 0.05 <= d1/d2 <= 0.95 and 0.2 <= d2 <= d2_max, both signs of the axis that keeps its sign,
// then W -> Omega = (W1, W2, W3) (k < 1) or (W3, W2, W1) (k > 1).
inline std::vector<vec3<quad>> random_regime_states(int n, bool minor, std::uint64_t seed, double d2_max) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ang(-3.14159, 3.14159), kk(0.05, 0.95), dd(0.2, d2_max);
  std::vector<vec3<quad>> out;
  for (int i = 0; i < n; ++i) {
    const quad d2 = quad(dd(rng)), d1 = quad(kk(rng)) * d2, am = quad(ang(rng));
    const quad W2 = d1 * sin(am);
    const quad s = (i % 2) ? quad(-1) : quad(1);
    const vec3<quad> W = {d1 * cos(am), W2, s * sqrt(d2 * d2 - W2 * W2)};
    out.push_back(minor ? vec3<quad>{W[2], W[1], W[0]} : W);
  }
  return out;
}

}  // namespace vop_test
