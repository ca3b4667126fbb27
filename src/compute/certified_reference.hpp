// `--certify` in the program: the certificate of a streamed run and the radius columns' text
// (docs/certified.md; the mathematics is in include/eulervop/certify/).
//
// One proof stands behind the flag, in ball arithmetic (certify/ball_certifier.hpp): it takes
// every scene, Eq. 5 and the coefficient and direct forms, torques of any formula of time and
// state, pieces, the gravity gradient, and the attitude with the rates as one problem of 7 states.
// Its certificate is compiled in a unit of its own (certificate_module_general.cpp).
#pragma once

#include "compute/certified_row.hpp"
#include "compute/run_certificate.hpp"
#include "compute/scene_library.hpp"

#include <eulervop/certify/ball.hpp>
#include <eulervop/core/scalar.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <mpfr.h>

namespace eulervop::app {

// The working precision of the certificate: the reference's bits plus 64, so that the interval
// arithmetic adds nothing visible to the reference's own error.
inline mpfr_prec_t certify_bits(const eulervop::precision& p) {
  const unsigned bits = p.type == eulervop::precision::kind::mpfr ? mpfr_effective_bits(p.bits) : p.bits;
  return static_cast<mpfr_prec_t>(bits + 64);
}

// m (>= 0) as a decimal with three significant digits, rounded up ("2.35e-27"), as printf's "%.2e"
// writes it (MPFR's "%.2RUe"): the digits from mpfr_get_str, which rounds them up itself, and the
// exponent of at least two digits. Zero and non-finite m go through mpfr_asprintf; the regular
// ones do not, as its format machinery took three times as long.
inline std::string rounded_up_text(const mpfr_t m) {
  std::string out;
  if (mpfr_regular_p(m)) {
    mpfr_exp_t e = 0;  // m rounds up to 0.d1d2d3 10^e
    char* digits = mpfr_get_str(nullptr, &e, 10, 3, m, MPFR_RNDU);
    const long exponent = static_cast<long>(e) - 1;
    out = fmt::format("{}.{}{}e{}{:02d}", digits[0], digits[1], digits[2], exponent < 0 ? '-' : '+',
                      exponent < 0 ? -exponent : exponent);
    mpfr_free_str(digits);
  } else {
    char* text = nullptr;
    mpfr_asprintf(&text, "%.2RUe", m);
    out = text;
    mpfr_free_str(text);
  }
  return out;
}

// An upper bound of |x| as rounded_up_text writes it.
inline std::string upper_text(const ball& x) {
  arf_t u;
  arf_init(u);
  arb_get_abs_ubound_arf(u, x.get(), 64);
  mpfr_t m;
  mpfr_init2(m, 64);
  arf_get_mpfr(m, u, MPFR_RNDU);
  std::string out = rounded_up_text(m);
  mpfr_clear(m);
  arf_clear(u);
  return out;
}

// A column's largest radius, of the texts upper_text writes, compared as values: by their three
// digits and exponent where they have rounded_up_text's regular form (d.dd 10^x orders exactly as
// (x, ddd), with no parse), else in MPFR, whose 64 bits keep apart the three-digit decimals that
// differ even below a double's range (radii in mpfr:1024 reach 1e-308, where std::stod throws).
class largest_radius_text {
 public:
  // max = text where text is the larger (or the first).
  void raise(std::string& max, const std::string& text) {
    const std::optional<long> key = regular_key(text);
    if (max.empty() || (key && key_ ? *key > *key_ : mpfr_greater(text, max))) {
      max = text;
      key_ = key;
    }
  }
  // (x, ddd) as one number, for "d.dde±x" with d.dd in [1, 10): what rounded_up_text writes for
  // a regular m.
  static std::optional<long> regular_key(const std::string& t) {
    if (t.size() < 8 || t.size() > 12 || t[0] < '1' || t[0] > '9' || t[1] != '.' || t[4] != 'e' ||
        (t[5] != '+' && t[5] != '-'))
      return std::nullopt;
    long x = 0;
    for (std::size_t i = 6; i < t.size(); ++i) {
      if (t[i] < '0' || t[i] > '9') return std::nullopt;
      x = 10 * x + (t[i] - '0');
    }
    if (!std::isdigit(static_cast<unsigned char>(t[2])) || !std::isdigit(static_cast<unsigned char>(t[3])))
      return std::nullopt;
    const long ddd = 100 * (t[0] - '0') + 10 * (t[2] - '0') + (t[3] - '0');
    return (t[5] == '-' ? -x : x) * 1000 + ddd;
  }

 private:
  static bool mpfr_greater(const std::string& a, const std::string& b) {
    mpfr_t x, y;
    mpfr_init2(x, 64);
    mpfr_init2(y, 64);
    mpfr_set_str(x, a.c_str(), 10, MPFR_RNDU);
    mpfr_set_str(y, b.c_str(), 10, MPFR_RNDU);
    const bool greater = mpfr_greater_p(x, y) != 0;
    mpfr_clear(x);
    mpfr_clear(y);
    return greater;
  }
  std::optional<long> key_;
};

// Segments a certificate's pipeline may hold: as many as about 16 MB of checks allow, a check of
// n1 nodes at `bits` taking about 200 x n1 x bits bytes, at least 2 per worker and 2 more, at most
// 128 per worker. A deep queue keeps both workers busy while the in-order part catches up (on the
// former fast path, the paper scene's --certify took 3% longer at 4 per worker than at 32, and 2%
// less at 100).
inline std::size_t segments_in_flight(std::size_t n1, mpfr_prec_t bits, unsigned workers) {
  const double check_bytes = 200.0 * static_cast<double>(n1) * static_cast<double>(bits);
  const auto fit = static_cast<std::size_t>(16e6 / check_bytes);
  return std::clamp<std::size_t>(fit, 2 * workers + 2, 128 * workers + 2);
}

// The certificate of one streamed run, as run_certificate: created at the first segment (which
// tells the degree). Path holds the certifier and its pipeline (certify_pipeline.hpp, an optional
// that pipeline() returns, empty without workers), and has add_segment<T, D>, expect_rows<T>,
// radii<T> and method;
// this keeps the largest radii.
template <class Path>
class path_certificate final : public run_certificate {
 public:
  path_certificate(const scene& s, const eulervop::precision& p, unsigned workers) : path_(s, p, workers) {}

  void add_segment(const chebyshev_segment<double, 3>& seg, const std::vector<double>& nodes) override {
    path_.add_segment(seg, nodes);
  }
  void add_segment(const chebyshev_segment<double, 7>& seg, const std::vector<double>& nodes) override {
    path_.add_segment(seg, nodes);
  }
  void add_segment(const chebyshev_segment<quad, 3>& seg, const std::vector<quad>& nodes) override {
    path_.add_segment(seg, nodes);
  }
  void add_segment(const chebyshev_segment<quad, 7>& seg, const std::vector<quad>& nodes) override {
    path_.add_segment(seg, nodes);
  }
  void add_segment(const chebyshev_segment<mpfr_real, 3>& seg, const std::vector<mpfr_real>& nodes) override {
    path_.add_segment(seg, nodes);
  }
  void add_segment(const chebyshev_segment<mpfr_real, 7>& seg, const std::vector<mpfr_real>& nodes) override {
    path_.add_segment(seg, nodes);
  }
  void expect_rows(const std::vector<double>& tau) override { path_.expect_rows(tau); }
  void expect_rows(const std::vector<quad>& tau) override { path_.expect_rows(tau); }
  void expect_rows(const std::vector<mpfr_real>& tau) override { path_.expect_rows(tau); }
  void row(std::function<void()> task) override {
    if (auto& pipeline = path_.pipeline())
      pipeline->add_row(std::move(task));
    else
      task();
  }
  void finish() override {
    if (auto& pipeline = path_.pipeline()) pipeline->finish();
  }
  // Stops the threads, dropping what has not run.
  void close() override { path_.pipeline().reset(); }
  certified_radii radii(const double& tau, const double& t, const certified_cells& cells) override {
    return kept(path_.radii(tau, t, cells));
  }
  certified_radii radii(const quad& tau, const quad& t, const certified_cells& cells) override {
    return kept(path_.radii(tau, t, cells));
  }
  certified_radii radii(const mpfr_real& tau, const mpfr_real& t, const certified_cells& cells) override {
    return kept(path_.radii(tau, t, cells));
  }
  const certified_maxima& maxima() const override { return max_; }
  std::string method() const override { return path_.method(); }

 private:
  certified_radii kept(certified_radii out) {
    state_max_.raise(max_.state, out.state);
    if (out.omega) omega_max_.raise(max_.omega, *out.omega);
    if (out.q) q_max_.raise(max_.q, *out.q);
    return out;
  }
  largest_radius_text state_max_, omega_max_, q_max_;

  // Before the path: a row still running while the path's pipeline stops may raise the maxima.
  certified_maxima max_;
  Path path_;
};

// The certificate (certificate_module_general.cpp).
std::unique_ptr<run_certificate> make_general_certificate(const scene& s, const eulervop::precision& p,
                                                          unsigned workers);

}  // namespace eulervop::app
