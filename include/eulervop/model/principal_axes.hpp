// A body's axes as a scene gives them, mapped onto the principal order I1 < I2 < I3 that the
// paper's normalization (Eqs. 2-4) needs.
//
// The map is a permutation of the axes; when the permutation is odd, the third principal axis
// is also reversed, so that the principal frame stays right-handed. The map is then a proper
// rotation, under which Euler's equations (Eq. 1) keep their form: rates and torques map the
// same way, and a rate in the principal frame maps back to the user's axes exactly (the map only
// moves and negates components).
#pragma once

#include <array>
#include <stdexcept>
#include <utility>

namespace eulervop {

// Principal moments of inertia, I1 < I2 < I3 (paper Eq. 3 requires the strict order), in any
// number type (a scalar, or a ball for the certificate).
template <class T>
struct inertia {
  T I1, I2, I3;
};

// The permutation and signs alone: they apply to vectors of any number type.
class axis_permutation {
 public:
  // The identity.
  axis_permutation() = default;
  // The permutation that sorts `moments` increasingly (they must be pairwise distinct), with the
  // third axis reversed when it is odd.
  template <class T>
  static axis_permutation sorting(const std::array<T, 3>& moments) {
    axis_permutation p;
    for (int a = 0; a < 3; ++a)
      for (int b = a + 1; b < 3; ++b)
        if (moments[p.perm_[b]] < moments[p.perm_[a]]) std::swap(p.perm_[a], p.perm_[b]);
    int inversions = 0;
    for (int a = 0; a < 3; ++a)
      for (int b = a + 1; b < 3; ++b) inversions += p.perm_[a] > p.perm_[b];
    p.sign_ = {1, 1, inversions % 2 ? -1 : 1};
    return p;
  }

  // Principal axis i is the user's axis `axis(i)`, times `sign(i)` (+1 or -1).
  int axis(int i) const { return perm_[i]; }
  int sign(int i) const { return sign_[i]; }
  // True when the user's axes are already the principal ones.
  bool identity() const { return perm_ == std::array<int, 3>{0, 1, 2}; }

  // A vector (rate or torque) from the user's axes to the principal ones, and back.
  template <class N>
  std::array<N, 3> to_principal(const std::array<N, 3>& v) const {
    std::array<N, 3> p;
    for (int i = 0; i < 3; ++i) p[i] = sign_[i] < 0 ? N(-v[perm_[i]]) : v[perm_[i]];
    return p;
  }
  template <class N>
  std::array<N, 3> to_user(const std::array<N, 3>& p) const {
    std::array<N, 3> v;
    for (int i = 0; i < 3; ++i) v[perm_[i]] = sign_[i] < 0 ? N(-p[i]) : p[i];
    return v;
  }

 private:
  std::array<int, 3> perm_{0, 1, 2};  // perm_[i]: the user's axis that is principal axis i
  std::array<int, 3> sign_{1, 1, 1};
};

// The permutation of a body's moments, with the moments in the principal order.
template <class T>
class principal_axes : public axis_permutation {
 public:
  // Moments already in the principal order: the identity map.
  explicit principal_axes(const inertia<T>& I) : principal_axes(std::array<T, 3>{I.I1, I.I2, I.I3}) {}
  // Moments in the user's order: positive and pairwise distinct (std::domain_error otherwise).
  explicit principal_axes(const std::array<T, 3>& user) : axis_permutation(sorting(user)) {
    if (!(user[0] > 0 && user[1] > 0 && user[2] > 0))
      throw std::domain_error("principal_axes: the moments of inertia must be positive");
    if (user[0] == user[1] || user[1] == user[2] || user[0] == user[2])
      throw std::domain_error("principal_axes: the moments of inertia must be distinct");
    I_ = {user[axis(0)], user[axis(1)], user[axis(2)]};
  }

  // The identity map, with no moments (for physical_scaling's direct form, which needs no order).
  static principal_axes unmapped() { return principal_axes(); }

  // I1 < I2 < I3.
  const inertia<T>& moments() const { return I_; }

 private:
  principal_axes() = default;

  inertia<T> I_{};
};

}  // namespace eulervop
