// `--certify`: a scene's exact data as intervals, which scenes and precisions can be certified,
// and the radius column's text (docs/certified.md).
#pragma once

#include "scene_library.hpp"

#include <eulervop/certified_bound.hpp>
#include <eulervop/chebyshev_picard.hpp>
#include <eulervop/scalar.hpp>

#include <fmt/format.h>

#include <memory>
#include <optional>
#include <string>
#include <variant>

#include <mpfr.h>

namespace eulervop::app {

// The working precision of the certificate: the reference's bits plus 64, so that the interval
// arithmetic adds nothing visible to the reference's own error.
inline mpfr_prec_t certify_bits(const eulervop::precision& p) {
  const unsigned bits = p.type == eulervop::precision::kind::mpfr ? mpfr_effective_bits(p.bits) : p.bits;
  return static_cast<mpfr_prec_t>(bits + 64);
}

// Why `--certify` cannot run on this scene at this precision (an input_error, exit 2), or nothing.
inline void require_certifiable(const scene& s, const eulervop::precision& p) {
  if (p.type == eulervop::precision::kind::binary64)
    throw input_error(
        "--certify: precision double is not certified (its reference is the double run's own "
        "rounding); use quad or mpfr:BITS");
  if (s.is_physical())
    throw input_error(fmt::format(
        "--certify: scene {} is physical (inertia, M, omega); certification covers normalized scenes "
        "(G, Omega, tau) only",
        s.name));
  if (const auto* e = std::get_if<eulervop::scene::initial_elements>(&s.initial); e && e->u.value != 0)
    throw input_error(fmt::format(
        "--certify: initial u = {} needs elliptic functions of the decimals, which are not enclosed; give "
        "[initial] Omega, or u = 0",
        e->u.text));
}

// G and Omega(0) of a normalized scene as intervals holding the decimals as written (c1/c2 with
// u = 0 is Omega = (c1, 0, c2) exactly, Eq. 12).
inline certified_problem certified_problem_of(const scene& s, mpfr_prec_t bits) {
  certified_problem p;
  auto add = [&](std::vector<detail::interval>& out, const std::string& text) {
    detail::interval x(bits);
    detail::set_decimal(x, text);
    out.push_back(std::move(x));
  };
  for (int i = 0; i < 3; ++i) add(p.G, s.torque ? (*s.torque)[i].text : "0");
  if (const auto* r = std::get_if<eulervop::scene::initial_rates>(&s.initial)) {
    for (int i = 0; i < 3; ++i) add(p.Omega0, r->rates[i].text);
  } else {
    const auto& e = std::get<eulervop::scene::initial_elements>(s.initial);
    add(p.Omega0, e.c1.text);
    add(p.Omega0, "0");
    add(p.Omega0, e.c2.text);
  }
  return p;
}

// An upper bound as a decimal with three significant digits, rounded up ("2.35e-27").
inline std::string upper_text(const detail::interval& x) {
  mpfr_t hi;
  mpfr_init2(hi, x.bits());
  mpfi_get_right(hi, x.get());
  char* text = nullptr;
  mpfr_asprintf(&text, "%.2RUe", hi);
  std::string out = text;
  mpfr_free_str(text);
  mpfr_clear(hi);
  return out;
}

// The certificate of one streamed run: created at the first segment (which tells the degree).
class run_certificate {
 public:
  run_certificate(const scene& s, const eulervop::precision& p) : scene_(s), bits_(certify_bits(p)) {}

  template <scalar T>
  void add_segment(const chebyshev_segment<T>& seg, const std::vector<T>& nodes) {
    if (!cert_) cert_.emplace(bits_, nodes.size() - 1, certified_problem_of(scene_, bits_));
    cert_->add_segment(seg);
  }
  // The radius of a row printed as `cells` (the three state texts), at tau.
  template <scalar T>
  std::string radius(const T& tau, const std::array<std::string, 3>& cells) {
    return upper_text(cert_->row_radius(tau, cells));
  }
  std::string max_radius() const { return upper_text(cert_->max_radius()); }
  std::string method() const {
    return fmt::format("mpfi bits={} interval Chebyshev residual, Lohner QR propagation", bits_);
  }

 private:
  const scene& scene_;
  mpfr_prec_t bits_;
  std::optional<certifier> cert_;
};

}  // namespace eulervop::app
