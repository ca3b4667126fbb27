// Variation of parameters for Euler's equations (Eq. 5): the paper's elements (c1, c2, u)
// (Eqs. 12-16), the secular-free elements (c1, c2, theta) (docs/vop-strategies.md), their
// conversions to and from Omega, and their equations of motion under torque.
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
// The separatrix d1 = d2 (k = 1) and d1 = 0 (pure spin) are singular; the run driver
// (comparison_run.hpp) steps across them with Eq. 5 and re-derives the elements.
#pragma once

#include <eulervop/special/elliptic.hpp>
#include <eulervop/special/jacobi_theta.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/core/scalar.hpp>

#include <boost/math/constants/constants.hpp>

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

namespace eulervop {

// pi / (2 K(k)) = a_N, the AGM mean (K = pi / (2 a_N), A&S 17.6.3): the rate of
// theta = pi u / (2K) per unit u, without rounding K or pi.
template <scalar T>
const T& pi_over_2K(const elliptic_modulus<T>& m) {
  return m.a(m.levels());
}

// Keeps a phase theta in [-pi, pi): subtracts whole turns 2 pi j and adds j to `turns`.
// For |j| = 1 (the only case in a run) theta - 2 pi is exact (Sterbenz), so the reduced phase
// carries no rounding beyond its own ulp; the theta right-hand side has period 2 pi exactly in
// the value of pi used here, so nothing drifts.
template <scalar T>
void reduce_phase(T& theta, long long& turns) {
  using std::floor;
  const T pi = boost::math::constants::pi<T>();
  if (theta >= -pi && theta < pi) return;
  const T j = floor((theta + pi) / (2 * pi));
  theta -= j * (2 * pi);
  if (theta >= pi) {  // rounding at the edge
    theta -= 2 * pi;
    turns += 1;
  } else if (theta < -pi) {
    theta += 2 * pi;
    turns -= 1;
  }
  turns += static_cast<long long>(static_cast<double>(j));
}

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

namespace detail {

// Domain bookkeeping shared by the two element systems.
template <scalar T>
class vop_domain {
 public:
  bool left_domain() const { return left_; }
  double left_domain_at() const { return left_at_; }
  const std::string& domain_message() const { return why_; }
  // Forget a recorded exit (the run driver does, after stepping across the band with Eq. 5).
  void reset_domain() {
    left_ = false;
    why_.clear();
  }

 protected:
  static T nan_() { return std::numeric_limits<T>::quiet_NaN(); }
  // True (and NaN derivatives) outside 0 < d1 < d2; d1 = 0 is allowed without torque.
  [[gnu::always_inline]] bool outside(const T& c1, const T& c2, const T& tau, bool torque_free, vec3<T>& dy) {
    if (c1 < c2 && (c1 > 0 || (torque_free && c1 == 0))) [[likely]]
      return false;
    record_exit(!(c1 > 0), static_cast<double>(tau));
    dy = {nan_(), nan_(), nan_()};
    return true;
  }

  // Out of line and by value: nothing of the stage's state escapes through it.
  [[gnu::noinline, gnu::cold]] void record_exit(bool at_zero, double tau) {
    if (left_) return;
    left_ = true;
    left_at_ = tau;
    why_ = at_zero ? "c1 reached 0 (k = 0): Eq. 16 divides by c1"
                   : "k = c1/c2 reached 1 (the separatrix): Eq. 16 divides by kc^2";
  }

 private:
  bool left_ = false;
  double left_at_ = 0;
  std::string why_;
};

// The AGM modulus data of the last k seen, and evaluation of sn, cn, dn, Z, E(u) for it:
// recomputed only when k changes (between the stages of a Runge-Kutta step it does; within a
// stage it is reused). Values are held here so that MPFR values are reused rather than
// allocated per call.
template <scalar T>
class agm_cache {
 public:
  void set(const T& k) {
    if (k == k_) return;
    agm_.assign(k);
    k_ = k;
  }
  // pi / (2K) = a_N, the AGM mean (K = pi / (2 a_N), A&S 17.6.3).
  const T& pi_over_2K() const { return agm_.a(agm_.levels()); }
  // sn, cn, dn, Z, E(u) at u (not am), valid until the next call.
  const jacobi_values<T>& eval(const T& u) {
    jacobi_eval<T, jacobi_outputs::without_amplitude>(u, agm_, values_);
    return values_;
  }

 private:
  T k_ = -1;
  elliptic_modulus<T> agm_{T(0)};
  jacobi_values<T> values_;
};

// What the two element systems share: the torque (in the vop_frame), the elliptic functions of
// Eqs. 13-16 at the current modulus, Eq. 13 and the torque bracket of Eq. 16.
template <scalar T>
class vop_equations : public vop_domain<T> {
 public:
  // pi / (2K) of the modulus of the last evaluation (the adaptive runs' error weight).
  const T& last_pi_over_2K() const { return last_rate_; }

 protected:
  explicit vop_equations(const vec3<T>& G) : G_(G), torque_free_(G[0] == 0 && G[1] == 0 && G[2] == 0) {}

  // Calls tail(j, rate) with sn, cn, dn, Z (and E(u) for Theta = false) at the modulus k
  // (kc2 = 1 - k^2 to full relative accuracy) and rate = pi/(2K). The argument is u, or with
  // Theta the phase theta = pi u / (2K) itself. In double, for k <= theta_max_k, through the nome
  // and theta functions with every constant in a local (jacobi_theta.hpp: the modulus and the
  // evaluation fused, so nothing goes through memory between them); otherwise, and in every
  // other type, through the AGM (elliptic.hpp), cached per modulus.
  template <bool Theta, class Tail>
  [[gnu::always_inline]] void with_functions(const T& k, const T& kc2, const T& arg, Tail&& tail) {
    if constexpr (std::is_same_v<T, double>) {
      if (k >= 0 && k <= theta_max_k) [[likely]] {
        const theta_constants m = theta_constants_of(k, kc2);
        jacobi_values<double> j;
        if constexpr (Theta) theta_values_at_phase(arg, m, j);
        else theta_values_at_u(arg, m, j);
        last_rate_ = m.rate;
        tail(static_cast<const jacobi_values<double>&>(j), m.rate);
        return;
      }
    }
    agm_.set(k);
    const T& rate = agm_.pi_over_2K();
    last_rate_ = rate;
    if constexpr (Theta) tail(agm_.eval(T(arg / rate)), rate);
    else tail(agm_.eval(arg), rate);
  }

  // pi / (2K) alone (torque-free motion needs no more).
  T rate_of(const T& k, const T& kc2) {
    if constexpr (std::is_same_v<T, double>)
      if (k >= 0 && k <= theta_max_k) return last_rate_ = theta_constants_of(k, kc2).rate;
    agm_.set(k);
    return last_rate_ = agm_.pi_over_2K();
  }

  // c1' = cn G1 + sn G2,  c2' = k sn G2 + dn G3                                       (Eq. 13)
  [[gnu::always_inline]] void element_rates(const jacobi_values<T>& j, const T& k, vec3<T>& dy) const {
    dy[0] = j.cn * G_[0] + j.sn * G_[1];
    dy[1] = k * j.sn * G_[1] + j.dn * G_[2];
  }
  // - sn dn G1 + kc^2 cn dn G2 + k^3 sn cn G3 + w (cn G1 + kc^2 sn G2 - k dn G3), the torque
  // part of the bracket of Eq. 16; w = E(u) - kc^2 u for u, Z(u) for theta.
  [[gnu::always_inline]] T torque_bracket(const jacobi_values<T>& j, const T& k, const T& kc2, const T& w) const {
    const T& G1 = G_[0];
    const T& G2 = G_[1];
    const T& G3 = G_[2];
    return -j.sn * j.dn * G1 + kc2 * j.cn * j.dn * G2 + k * k * k * j.sn * j.cn * G3 +
           w * (j.cn * G1 + kc2 * j.sn * G2 - k * j.dn * G3);
  }

  vec3<T> G_;
  bool torque_free_;
  agm_cache<T> agm_;
  T last_rate_ = T(1);
};

}  // namespace detail

// Right-hand side of the elements (c1, c2, u) under the torque G (given in the vop_frame):
//   c1' = cn G1 + sn G2                                                             (Eq. 13)
//   c2' = k sn G2 + dn G3                                                           (Eq. 13)
//   u'  = [k (c2^2 - c1^2) - sn dn G1 + kc^2 cn dn G2 + k^3 sn cn G3
//          + (E(u) - kc^2 u)(cn G1 + kc^2 sn G2 - k dn G3)] / (c1 kc^2)             (Eq. 16)
// with E(u) = integral_0^u dn^2 Jacobi's epsilon function (E(am u | k)). In double the
// functions come from the theta route with every constant in registers; otherwise from the AGM,
// whose modulus data (K, E, the sequence) is recomputed only when k changes.
//
// Outside 0 < k < 1 the equations are singular. The system then returns NaN derivatives, which
// stops the fixed-step driver, and records the first tau where it happened and why. Without
// torque, c1 = 0 is allowed (u' = c2 exactly).
template <scalar T>
class vop_system : public detail::vop_equations<T> {
 public:
  explicit vop_system(const vec3<T>& G) : detail::vop_equations<T>(G) {}

  [[gnu::always_inline]] void operator()(const vec3<T>& y, vec3<T>& dy, const T& tau) {
    const T& c1 = y[0];
    const T& c2 = y[1];
    if (this->outside(c1, c2, tau, this->torque_free_, dy)) return;
    if (this->torque_free_) {  // Eq. 13 and 16 with G = 0, also at c1 = 0
      dy = {T(0), T(0), c2};
      return;
    }
    const T k = c1 / c2;
    // kc^2 = (c2 - c1)(c2 + c1) / c2^2 keeps its digits near k = 1, unlike 1 - k^2.
    const T kc2 = (c2 - c1) * (c2 + c1) / (c2 * c2);
    // The divisor of Eq. 16, inverted while the elliptic functions are evaluated (off the path).
    const T inv_c1_kc2 = 1 / (c1 * kc2);
    this->template with_functions<false>(k, kc2, y[2], [&](const jacobi_values<T>& j, const T&) __attribute__((always_inline)) {
      const T secular = j.E - kc2 * y[2];  // E(u) - kc^2 u
      // The torque-free term k (c2^2 - c1^2) / (c1 kc^2) of Eq. 16 is exactly c2 (k = c1/c2,
      // c2^2 - c1^2 = c2^2 kc^2): written so, torque-free motion advances u by exactly c2 tau.
      T du = c2 + this->torque_bracket(j, k, kc2, secular) * inv_c1_kc2;
      this->element_rates(j, k, dy);
      dy[2] = std::move(du);
    });
  }
};

// Right-hand side of the secular-free elements (c1, c2, theta), theta = pi u / (2K(k)), under the
// torque G (in the vop_frame). c1', c2' are Eq. 13 at u = 2K theta / pi, and
//   theta' = pi/(2K) u' - (pi u / (2K^2)) dK/dk k',   dK/dk = (E - kc^2 K) / (k kc^2)  (A&S 17.3.11)
// With k' = P / c2 (Eq. 15, P = cn G1 + kc^2 sn G2 - k dn G3) and k c2 = c1, the second term is
// pi/(2K) u (E/K - kc^2) P / (c1 kc^2); subtracted from the secular term of Eq. 16 it leaves
// E(u) - kc^2 u - (E/K) u + kc^2 u = Z(u), the Jacobi zeta function:
//   theta' = pi/(2K) [c2 + (- sn dn G1 + kc^2 cn dn G2 + k^3 sn cn G3 + Z(u) P) / (c1 kc^2)].
// Every term has period 2 pi in theta (sn, cn: 4K in u; dn, Z: 2K), so the run keeps theta in
// [-pi, pi) and counts whole turns apart (reduce_phase). pi/(2K) is a_N, the AGM mean, and
// torque-free motion advances theta by exactly a_N c2 per unit tau (c2 in Eq. 16, times a_N).
template <scalar T>
class vop_theta_system : public detail::vop_equations<T> {
 public:
  explicit vop_theta_system(const vec3<T>& G) : detail::vop_equations<T>(G) {}

  [[gnu::always_inline]] void operator()(const vec3<T>& y, vec3<T>& dy, const T& tau) {
    const T& c1 = y[0];
    const T& c2 = y[1];
    if (this->outside(c1, c2, tau, this->torque_free_, dy)) return;
    const T k = c1 / c2;
    const T kc2 = (c2 - c1) * (c2 + c1) / (c2 * c2);
    if (this->torque_free_) {
      dy = {T(0), T(0), this->rate_of(k, kc2) * c2};
      return;
    }
    // The divisor of Eq. 16, inverted while the elliptic functions are evaluated (off the path).
    const T inv_c1_kc2 = 1 / (c1 * kc2);
    this->template with_functions<true>(k, kc2, y[2], [&](const jacobi_values<T>& j, const T& rate) __attribute__((always_inline)) {
      T dtheta = rate * c2 + rate * (this->torque_bracket(j, k, kc2, j.Z) * inv_c1_kc2);
      this->element_rates(j, k, dy);
      dy[2] = std::move(dtheta);
    });
  }
};

}  // namespace eulervop
