// The frames of the VOP elements and the conversions between Omega and the elements: the
// paper's (c1, c2, u) (Eqs. 7, 11, 12) and the secular-free (c1, c2, theta)
// (docs/vop-strategies.md).
//
// Regimes (docs/vop-strategies.md). Every regime is reduced to the paper's one, 0 <= k < 1 with
// Omega3 > 0, by a signed permutation W = P Omega that is a symmetry of Eq. 5 (G maps the same way):
//   major axis, k < 1, Omega3 > 0:  W = ( Omega1,  Omega2,  Omega3)  (the paper)
//   major axis, k < 1, Omega3 < 0:  W = ( Omega1, -Omega2, -Omega3)  (rotation by pi about axis 1)
//   minor axis, k > 1, Omega1 > 0:  W = ( Omega3,  Omega2,  Omega1)
//   minor axis, k > 1, Omega1 < 0:  W = ( Omega3, -Omega2, -Omega1)
// The swap 1 <-> 3 is a symmetry: W1' = Omega3' = -W2 W3 + G3, W2' = Omega2' = W1 W3 + G2,
// W3' = Omega1' = -W1 W2 + G1, which is Eq. 5 for W with the torque (G3, G2, G1). In the W frame
// the integrals are d1 = |(W1, W2)| = c2 and d2 = |(W2, W3)| = c1, the modulus is d1/d2 = 1/k < 1,
// and the paper's solution W = (d1 cn v, d1 sn v, d2 dn v), v = d2 (tau - tau0), reads
//   Omega1 = c1 dn(v | 1/k), Omega2 = c2 sn(v | 1/k), Omega3 = c2 cn(v | 1/k),  v = c1 (tau - tau0),
// the reciprocal-modulus form of the solution. The element equations of the minor-axis regime
// are therefore Eqs. 13 and 16 in the W frame:
//   c1' = dn G1 + l sn G2,  c2' = cn G3 + sn G2 (l = 1/k; Eq. 13 in terms of Omega unchanged),
//   v'  = [l (c1^2 - c2^2) - sn dn G3 + lc^2 cn dn G2 + l^3 sn cn G1
//          + (E(v) - lc^2 v)(cn G3 + lc^2 sn G2 - l dn G1)] / (c2 lc^2),   lc^2 = 1 - l^2.
// (Omega1, Omega2, G1, G2) -> -(...) (rotation by pi about axis 3) is also a symmetry of Eq. 5;
// in the W frame of the minor regime it is the (W2, W3) flip, hence the last row.
// Checked by the chain-rule tests in tests/test_vop.cpp and tests/test_vop_theta.cpp.
//
// The separatrix d1 = d2 (k = 1) and d1 = 0 (pure spin) are singular; the comparison runs
// (runs/detail/vop_run_state.hpp) step across them with Eq. 5 and re-derive the elements.
#pragma once

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/special/elliptic.hpp>
#include <eulervop/vop/phase.hpp>

#include <sstream>
#include <stdexcept>

namespace eulervop {

// The frame W = P Omega of one regime (see the header note) and the conversions
// Omega <-> (d1, d2, u) and Omega <-> (d1, d2, theta) in it.
template <scalar T>
class vop_frame {
 public:
  // The paper's regime only (k < 1, Omega3 != 0), sigma = sign(Omega3(0)). Throws
  // std::domain_error otherwise.
  static vop_frame of(const vec3<T>& Omega0) {
    if (!(Omega0[2] != 0)) throw std::domain_error("vop: Omega3 = 0 at the start (k >= 1); the paper's VOP needs k < 1");
    vop_frame f;
    f.sigma_ = Omega0[2] > 0 ? 1 : -1;
    const vec3<T> y = f.elements_of(Omega0);
    if (!(y[0] < y[1])) {
      std::ostringstream m;
      m << "vop: k = c1/c2 = " << static_cast<double>(y[0] / y[1])
        << " >= 1 at the start (rotation near the minor axis); the paper's VOP needs k < 1";
      throw std::domain_error(m.str());
    }
    return f;
  }

  // Either regime: the major-axis frame when c1 < c2 (sigma = sign Omega3), the minor-axis frame
  // when c1 > c2 (sigma = sign Omega1). Throws std::domain_error on the separatrix c1 = c2
  // (including Omega = 0), where no frame has k < 1.
  static vop_frame for_state(const vec3<T>& Omega) {
    using std::hypot;
    const T c1 = hypot(Omega[0], Omega[1]);
    const T c2 = hypot(Omega[1], Omega[2]);
    vop_frame f;
    if (c1 < c2) {
      f.minor_ = false;
      f.sigma_ = Omega[2] > 0 ? 1 : -1;  // |Omega3| = sqrt(c2^2 - Omega2^2) > 0
    } else if (c1 > c2) {
      f.minor_ = true;
      f.sigma_ = Omega[0] > 0 ? 1 : -1;  // |Omega1| = sqrt(c1^2 - Omega2^2) > 0
    } else {
      std::ostringstream m;
      m << "vop: c1 = c2 = " << static_cast<double>(c1) << " (k = 1, the separatrix): no elements";
      throw std::domain_error(m.str());
    }
    return f;
  }

  int sigma() const { return sigma_; }
  // True in the minor-axis regime (k > 1, reciprocal modulus).
  bool minor_axis() const { return minor_; }

  // W = P v: maps Omega or G into the frame. In the major regime an involution.
  vec3<T> rotate(const vec3<T>& v) const {
    if (!minor_) return {v[0], sigma_ > 0 ? v[1] : T(-v[1]), sigma_ > 0 ? v[2] : T(-v[2])};
    return {v[2], sigma_ > 0 ? v[1] : T(-v[1]), sigma_ > 0 ? v[0] : T(-v[0])};
  }
  // v = P^-1 W.
  vec3<T> unrotate(const vec3<T>& w) const {
    if (!minor_) return rotate(w);
    return {sigma_ > 0 ? w[2] : T(-w[2]), sigma_ > 0 ? w[1] : T(-w[1]), w[0]};
  }

  // Elements (d1, d2, u) of Omega in the frame (Eqs. 7, 11): d1 = |(W1, W2)|, d2 = |(W2, W3)|,
  // am u = atan2(W2, W1) since (cn, sn) = (cos am, sin am), and u = F(am, d1/d2).
  // In the major regime (d1, d2) = (c1, c2); in the minor regime (c2, c1).
  vec3<T> elements_of(const vec3<T>& Omega) const {
    using std::atan2;
    using std::hypot;
    const vec3<T> w = rotate(Omega);
    const T c1 = hypot(w[0], w[1]);
    const T c2 = hypot(w[1], w[2]);
    if (!(c1 < c2)) return {c1, c2, T(0)};  // outside the regime: the caller checks c1 < c2
    const elliptic_modulus<T> m(c1 / c2);
    const T am = atan2(w[1], w[0]);
    return {c1, c2, elliptic_f(am, m)};
  }

  // Omega from the elements (Eq. 12): W = (d1 cn u, d1 sn u, d2 dn u), then P^-1.
  vec3<T> Omega_of(const vec3<T>& y) const {
    const elliptic_modulus<T> m(y[0] / y[1]);
    const jacobi_values<T> j = jacobi_eval(y[2], m);
    return unrotate(vec3<T>{y[0] * j.cn, y[0] * j.sn, y[1] * j.dn});
  }

  // Secular-free elements (d1, d2, theta), theta = pi u / (2K) reduced into [-pi, pi).
  vec3<T> theta_elements_of(const vec3<T>& Omega) const {
    vec3<T> y = elements_of(Omega);
    if (!(y[0] < y[1])) return y;
    const elliptic_modulus<T> m(y[0] / y[1]);
    y[2] *= pi_over_2K(m);
    long long turns = 0;
    reduce_phase(y[2], turns);
    return y;
  }

  // Omega from (d1, d2, theta): u = 2K theta / pi = theta / a_N.
  vec3<T> Omega_of_theta(const vec3<T>& y) const {
    const elliptic_modulus<T> m(y[0] / y[1]);
    const jacobi_values<T> j = jacobi_eval(T(y[2] / pi_over_2K(m)), m);
    return unrotate(vec3<T>{y[0] * j.cn, y[0] * j.sn, y[1] * j.dn});
  }

 private:
  int sigma_ = 1;
  bool minor_ = false;
};

}  // namespace eulervop
