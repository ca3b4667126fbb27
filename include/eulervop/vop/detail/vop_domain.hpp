// Where the element equations (Eqs. 13-16) hold, 0 < c1 < c2, and the record of a stage that left
// it: the bookkeeping shared by vop_system.hpp and vop_theta_system.hpp.
#pragma once

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/core/vec3.hpp>

#include <limits>
#include <string>

namespace eulervop::detail {

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

}  // namespace eulervop::detail
