// Models on one common binary grid for the linear flow's residuals (ball_linear_flow.hpp): each
// model's coefficients as integers n_k with f = 2^e sum n_k T_k + (a remainder that holds its move
// to the grid, to_grid() in chebyshev_model.hpp, and its own remainder), so that the products of
// two such sets are exact in integers. Also as short_integer_series where every coefficient fits
// 62 bits, for the 128-bit sums of short_integer_series.hpp.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/certify/detail/short_integer_series.hpp>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace eulervop::detail {

// Models on one common binary grid 2^e: integer polynomials, each with a remainder (its move to
// the grid and its own remainder) and the sum of its magnitudes.
class grid_models {
 public:
  explicit grid_models(std::size_t count) : n_(count), rem_(count), mag_(count) {}

  // The models `m`, each times 2^shift[q] (no shifts: 1), on the grid `bits` bits below their
  // largest coefficient (a model's integers on 2^(e - shift) are its scaled ones' on 2^e).
  void load(const std::vector<chebyshev_model>& m, slong bits, const std::vector<slong>& shift = {}) {
    const auto by = [&](std::size_t q) { return shift.empty() ? 0 : shift[q]; };
    slong top = WORD_MIN;
    for (std::size_t q = 0; q < m.size(); ++q) {
      if (m[q].is_zero()) continue;
      const slong e = midpoint_top(m[q]);  // scaled; 0 where every midpoint is 0, as grid_exponent
      top = std::max(top, e == WORD_MIN ? 0 : e + by(q));
    }
    e_ = top == WORD_MIN ? 0 : top - bits;
    for (std::size_t q = 0; q < m.size(); ++q) {
      to_grid(n_[q].p, rem_[q].m, m[q], e_ - by(q));
      mag_add(rem_[q].m, rem_[q].m, m[q].remainder());
      mag_mul_2exp_si(rem_[q].m, rem_[q].m, by(q));
      grid_magnitude(mag_[q].m, n_[q].p, e_);
    }
    short_.resize(m.size());
    short_ok_ = true;
    short_bits_ = 0;
    short_len_ = 0;
    for (std::size_t q = 0; q < m.size() && short_ok_; ++q) {
      short_ok_ = short_[q].load(n_[q].p);
      short_bits_ = std::max(short_bits_, short_[q].bits);
      short_len_ = std::max(short_len_, short_[q].c.size());
    }
  }

  slong exponent() const { return e_; }
  // The models as short_integer_series (short_integer_series.hpp), where all fit 62 bits.
  bool short_form() const { return short_ok_; }
  const short_integer_series& short_series(std::size_t q) const { return short_[q]; }
  unsigned short_bits() const { return short_bits_; }
  std::size_t short_length() const { return short_len_; }
  const fmpz_poly_struct* poly(std::size_t q) const { return n_[q].p; }
  fmpz_poly_struct* poly(std::size_t q) { return n_[q].p; }
  const mag_value& remainder(std::size_t q) const { return rem_[q]; }
  const mag_value& magnitude(std::size_t q) const { return mag_[q]; }
  std::size_t length() const {  // the longest polynomial's
    std::size_t n = 0;
    for (const integer_poly& x : n_) n = std::max(n, static_cast<std::size_t>(x.p->length));
    return n;
  }
  bool zero(std::size_t q) const { return n_[q].p->length == 0 && mag_is_zero(rem_[q].m); }

 private:
  std::vector<integer_poly> n_;
  std::vector<mag_value> rem_, mag_;
  slong e_ = 0;
  std::vector<short_integer_series> short_;
  bool short_ok_ = false;
  unsigned short_bits_ = 0;
  std::size_t short_len_ = 0;
};

}  // namespace eulervop::detail
