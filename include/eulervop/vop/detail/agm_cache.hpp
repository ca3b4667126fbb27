// The elliptic functions of the element equations through the AGM (special/elliptic.hpp), with the
// modulus data cached per modulus.
#pragma once

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/special/elliptic.hpp>
#include <eulervop/vop/phase.hpp>

namespace eulervop::detail {

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
  // pi / (2K) (phase.hpp).
  const T& pi_over_2K() const { return eulervop::pi_over_2K(agm_); }
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

}  // namespace eulervop::detail
