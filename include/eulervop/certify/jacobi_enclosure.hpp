// Jacobi's elliptic functions sn, cn, dn of a real argument u and modulus 0 <= k < 1, enclosed
// in balls: the initial state of Eq. 12, Omega(0) = (c1 cn u, c1 sn u, c2 dn u), when a scene
// gives its elements with u != 0.
//
// Each is a quotient of theta functions (DLMF 22.2.4-22.2.6):
//   sn u = (theta3 / theta2) theta1(z) / theta4(z),  cn u = (theta4 / theta2) theta2(z) / theta4(z),
//   dn u = (theta4 / theta3) theta3(z) / theta4(z),
// the thetas without an argument at z = 0, with the nome q = exp(-pi K'/K), K = K(k^2) and
// K' = K(1 - k^2) (DLMF 19.2.8), and z = u / (2K) in Arb's convention, where theta_j(z, tau) has
// pi z where DLMF has z (tau = i K'/K, so q = exp(pi i tau)). Arb evaluates the thetas and K with
// rigorous error bounds (acb_modular_theta, acb_elliptic_k), so each quotient is a ball that
// holds the true value. The true values are real: the real parts are the enclosures.
#pragma once

#include <eulervop/certify/ball.hpp>

#include <acb.h>
#include <acb_elliptic.h>
#include <acb_modular.h>

#include <stdexcept>

namespace eulervop {

struct jacobi_enclosures {
  ball sn, cn, dn;
};

// std::domain_error when k may lie outside [0, 1) or an enclosure is not finite.
inline jacobi_enclosures jacobi_enclosure(const ball& k, const ball& u, slong prec) {
  if (!arb_is_nonnegative(k.get()) || !arb_lt(k.get(), ball(1).get()))
    throw std::domain_error("the modulus k may lie outside [0, 1)");
  jacobi_enclosures v;
  if (arb_is_zero(k.get())) {  // a circle: sn = sin, cn = cos, dn = 1 (DLMF 22.5.3); K' is infinite
    arb_sin_cos(v.sn.get(), v.cn.get(), u.get(), prec);
    arb_one(v.dn.get());
    return v;
  }
  // A few guard bits: the quotients lose a little to the thetas' cancellation near k = 1.
  const slong wp = prec + 32;
  acb_t m, K, Kp, tau, z, t[4], t0[4];
  acb_init(m), acb_init(K), acb_init(Kp), acb_init(tau), acb_init(z);
  for (int j = 0; j < 4; ++j) acb_init(t[j]), acb_init(t0[j]);
  acb_set_arb(m, k.get());
  acb_sqr(m, m, wp);
  acb_elliptic_k(K, m, wp);
  acb_sub_ui(Kp, m, 1, wp);
  acb_neg(Kp, Kp);
  acb_elliptic_k(Kp, Kp, wp);
  acb_div(tau, Kp, K, wp);
  acb_mul_onei(tau, tau);
  acb_set_arb(z, u.get());
  acb_div(z, z, K, wp);
  acb_mul_2exp_si(z, z, -1);
  acb_modular_theta(t[0], t[1], t[2], t[3], z, tau, wp);
  acb_zero(z);
  acb_modular_theta(t0[0], t0[1], t0[2], t0[3], z, tau, wp);
  const auto quotient = [&](ball& out, const acb_t a, const acb_t b, const acb_t c, const acb_t d) {
    acb_t x;
    acb_init(x);
    acb_div(x, a, b, wp);  // theta(0) over theta(0)
    acb_mul(x, x, c, wp);
    acb_div(x, x, d, wp);  // times theta(z) over theta(z)
    arb_set_round(out.get(), acb_realref(x), prec);
    acb_clear(x);
  };
  quotient(v.sn, t0[2], t0[1], t[0], t[3]);
  quotient(v.cn, t0[3], t0[1], t[1], t[3]);
  quotient(v.dn, t0[3], t0[2], t[2], t[3]);
  acb_clear(m), acb_clear(K), acb_clear(Kp), acb_clear(tau), acb_clear(z);
  for (int j = 0; j < 4; ++j) acb_clear(t[j]), acb_clear(t0[j]);
  if (!arb_is_finite(v.sn.get()) || !arb_is_finite(v.cn.get()) || !arb_is_finite(v.dn.get()))
    throw std::domain_error("Jacobi's functions could not be enclosed there");
  return v;
}

}  // namespace eulervop
