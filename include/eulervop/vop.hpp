// The paper's variation of parameters (Eqs. 12-16): elements (c1, c2, u) of the torque-free
// solution, their conversion to and from Omega, and their equations of motion under torque.
//
// Regime: 0 <= k = c1/c2 < 1 (rotation about the major axis, Eq. 12). Omega3 < 0 is handled by
// the symmetry (Omega2, Omega3, G2, G3) -> (-Omega2, -Omega3, -G2, -G3) of Eq. 5 (DESIGN.md
// section 1.2): a vop_frame with sigma = sign(Omega3(0)) maps to and from the Omega3 > 0 case.
// k >= 1 (the separatrix and beyond) is outside this formulation: the initial conversion refuses
// it, and the right-hand side records where a run reaches it (hard-case issue).
#pragma once

#include <eulervop/elliptic.hpp>
#include <eulervop/model.hpp>
#include <eulervop/scalar.hpp>

#include <boost/math/constants/constants.hpp>

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace eulervop {

// The frame of the Omega3 < 0 symmetry and the conversions Omega <-> (c1, c2, u).
template <class T>
class vop_frame {
 public:
  // sigma = sign(Omega3(0)). Throws std::domain_error when the state is not in 0 <= k < 1 with
  // Omega3 != 0.
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

  int sigma() const { return sigma_; }

  // (v1, sigma v2, sigma v3): maps Omega or G into the Omega3 > 0 frame and back (an involution).
  vec3<T> rotate(const vec3<T>& v) const {
    return {v[0], sigma_ > 0 ? v[1] : T(-v[1]), sigma_ > 0 ? v[2] : T(-v[2])};
  }

  // Elements (c1, c2, u) of Omega (Eqs. 7, 11): c1 = |(Omega1, Omega2)|, c2 = |(Omega2, Omega3)|,
  // am u = atan2(Omega2, Omega1) since (cn, sn) = (cos am, sin am), and u = F(am, k).
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

  // Omega from the elements (Eq. 12): (c1 cn u, c1 sn u, c2 dn u), then back to the frame of
  // the problem.
  vec3<T> Omega_of(const vec3<T>& y) const {
    const elliptic_modulus<T> m(y[0] / y[1]);
    const jacobi_values<T> j = jacobi_eval(y[2], m);
    return rotate(vec3<T>{y[0] * j.cn, y[0] * j.sn, y[1] * j.dn});
  }

 private:
  int sigma_ = 1;
};

// Right-hand side of the elements (c1, c2, u) under the torque G (given in the vop_frame):
//   c1' = cn G1 + sn G2                                                             (Eq. 13)
//   c2' = k sn G2 + dn G3                                                           (Eq. 13)
//   u'  = [k (c2^2 - c1^2) - sn dn G1 + kc^2 cn dn G2 + k^3 sn cn G3
//          + (E(u) - kc^2 u)(cn G1 + kc^2 sn G2 - k dn G3)] / (c1 kc^2)             (Eq. 16)
// with E(u) Jacobi's epsilon function (DESIGN.md section 1.3). The modulus data (K, E, the AGM
// sequence) is recomputed only when k changes.
//
// Outside 0 < k < 1 the equations are singular. The system then returns NaN derivatives, which
// stops the fixed-step driver, and records the first tau where it happened and why.
template <class T>
class vop_system {
 public:
  explicit vop_system(const vec3<T>& G) : G_(G) {}

  void operator()(const vec3<T>& y, vec3<T>& dy, const T& tau) {
    const T& c1 = y[0];
    const T& c2 = y[1];
    if (!(c1 > 0 && c1 < c2)) {
      leave_domain(tau, c1 <= 0 ? "c1 reached 0 (k = 0): Eq. 16 divides by c1"
                                : "k = c1/c2 reached 1 (the separatrix): Eq. 16 divides by kc^2");
      dy = {nan_(), nan_(), nan_()};
      return;
    }
    const T k = c1 / c2;
    if (!(k == cached_k_)) {
      modulus_.assign(k);
      cached_k_ = k;
    }
    // kc^2 = (c2 - c1)(c2 + c1) / c2^2 keeps its digits near k = 1, unlike 1 - k^2.
    const T kc2 = (c2 - c1) * (c2 + c1) / (c2 * c2);
    jacobi_eval(y[2], modulus_, j_);
    const jacobi_values<T>& j = j_;
    const T& G1 = G_[0];
    const T& G2 = G_[1];
    const T& G3 = G_[2];
    dy[0] = j.cn * G1 + j.sn * G2;
    dy[1] = k * j.sn * G2 + j.dn * G3;
    const T secular = j.E - kc2 * y[2];  // E(u) - kc^2 u
    // The torque-free term k (c2^2 - c1^2) / (c1 kc^2) of Eq. 16 is exactly c2 (k = c1/c2,
    // c2^2 - c1^2 = c2^2 kc^2): written so, torque-free motion advances u by exactly c2 tau.
    dy[2] = c2 + (-j.sn * j.dn * G1 + kc2 * j.cn * j.dn * G2 + k * k * k * j.sn * j.cn * G3 +
                  secular * (j.cn * G1 + kc2 * j.sn * G2 - k * j.dn * G3)) /
                     (c1 * kc2);
  }

  bool left_domain() const { return left_; }
  double left_domain_at() const { return left_at_; }
  const std::string& domain_message() const { return why_; }

 private:
  static T nan_() { return std::numeric_limits<T>::quiet_NaN(); }
  void leave_domain(const T& tau, const char* why) {
    if (left_) return;
    left_ = true;
    left_at_ = static_cast<double>(tau);
    why_ = why;
  }

  vec3<T> G_;
  T cached_k_ = -1;
  elliptic_modulus<T> modulus_{T(0)};
  jacobi_values<T> j_;
  bool left_ = false;
  double left_at_ = 0;
  std::string why_;
};

}  // namespace eulervop
