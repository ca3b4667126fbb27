// `--certify`: a scene's exact data as intervals, which scenes and precisions can be certified,
// and the radius column's text (docs/certified.md).
#pragma once

#include "compute/scene_library.hpp"

#include <eulervop/certify/certifier.hpp>
#include <eulervop/reference/integrate.hpp>
#include <eulervop/model/principal_axes.hpp>
#include <eulervop/core/scalar.hpp>

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
  if (uses_direct_form(s))
    throw input_error(fmt::format(
        "--certify: scene {} has (nearly) equal moments of inertia and is integrated in the direct form of "
        "Eq. 1, which is not certified",
        s.name));
  if (const auto* e = std::get_if<eulervop::scene::initial_elements>(&s.initial); e && e->u.value != 0)
    throw input_error(fmt::format(
        "--certify: initial u = {} needs elliptic functions of the decimals, which are not enclosed; give "
        "[initial] Omega, or u = 0",
        e->u.text));
}

// Eqs. 2-4 in intervals for a physical scene: the principal axes (the same permutation and signs
// as physical_scaling, chosen from the moments' doubles, which order them exactly as their
// decimals do), sqrt(A_i) and dtau/dt = sqrt(A1 A2 A3).
struct physical_intervals {
  principal_axes<double> axes;
  std::vector<detail::interval> I, sqrtA;  // in the principal order
  detail::interval rate;

  physical_intervals(const scene& s, mpfr_prec_t bits)
      : axes(std::array<double, 3>{(*s.inertia)[0].value, (*s.inertia)[1].value, (*s.inertia)[2].value}),
        rate(bits) {
    for (int i = 0; i < 3; ++i) {
      detail::interval x(bits);
      detail::set_decimal(x, (*s.inertia)[axes.axis(i)].text);
      I.push_back(std::move(x));
    }
    const int pair[3][2] = {{2, 1}, {2, 0}, {1, 0}};  // A_i = (I_a - I_b) / I_i (Eq. 3)
    mpfi_set_ui(rate.get(), 1);
    for (int i = 0; i < 3; ++i) {
      detail::interval A(bits);
      mpfi_sub(A.get(), I[pair[i][0]].get(), I[pair[i][1]].get());
      mpfi_div(A.get(), A.get(), I[i].get());
      mpfi_mul(rate.get(), rate.get(), A.get());
      mpfi_sqrt(A.get(), A.get());
      sqrtA.push_back(std::move(A));
    }
    mpfi_sqrt(rate.get(), rate.get());
  }
  // A user-axis decimal vector in the principal order, each component times sign(i) / div[i]
  // (div absent: 1).
  void to_principal(const eulervop::scene::decimal3& v, const std::vector<detail::interval>* div, std::vector<detail::interval>& out) const {
    for (int i = 0; i < 3; ++i) {
      detail::set_decimal(out[i], v[axes.axis(i)].text);
      if (axes.sign(i) < 0) mpfi_neg(out[i].get(), out[i].get());
      if (div) mpfi_div(out[i].get(), out[i].get(), (*div)[i].get());
    }
  }
};

// G and Omega(0) as intervals holding the scene's decimals as written: a normalized scene's own
// (c1/c2 with u = 0 is Omega = (c1, 0, c2) exactly, Eq. 12), or Eqs. 2-4 of a physical one.
inline certified_problem certified_problem_of(const scene& s, mpfr_prec_t bits) {
  certified_problem p;
  if (s.is_physical()) {
    const physical_intervals phys(s, bits);
    p.G.assign(3, detail::interval(bits));
    p.Omega0.assign(3, detail::interval(bits));
    if (s.torque) {
      // G_i = M_i / (I_i sqrt(A_i) rate)
      std::vector<detail::interval> scale(3, detail::interval(bits));
      for (int i = 0; i < 3; ++i) {
        mpfi_mul(scale[i].get(), phys.I[i].get(), phys.sqrtA[i].get());
        mpfi_mul(scale[i].get(), scale[i].get(), phys.rate.get());
      }
      phys.to_principal(*s.torque, &scale, p.G);
    }
    phys.to_principal(std::get<eulervop::scene::initial_rates>(s.initial).rates, &phys.sqrtA, p.Omega0);
    return p;
  }
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
  run_certificate(const scene& s, const eulervop::precision& p) : scene_(s), bits_(certify_bits(p)) {
    if (s.is_physical()) physical_.emplace(s, bits_);
  }

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
  // A physical scene's row: the radius of Omega (at the row's tau), and of omega in rad/s at the
  // row's t, whose exact tau = t dtau/dt differs from the row's by a rounding: the bound moves by
  // that difference times a bound of |dOmega/dtau| there. omega = the axes' map of
  // sqrt(A_i) Omega_i (Eq. 2), so |d omega| <= max sqrt(A_i) |d Omega| plus the printed digits'
  // distance to the map of P.
  template <scalar T>
  std::array<std::string, 2> physical_radii(const T& tau, const T& t, const std::array<std::string, 3>& Omega_cells,
                                            const std::array<std::string, 3>& omega_cells) {
    const physical_intervals& ph = *physical_;
    const certifier::enclosure at = cert_->enclose(tau);
    const std::string Omega_radius = upper_text(cert_->row_radius(at, Omega_cells));
    detail::interval d(bits_), x(bits_), sum(bits_), scale(bits_), err(bits_);
    detail::set_exact(d, t);
    mpfi_mul(d.get(), d.get(), ph.rate.get());
    detail::set_exact(x, tau);
    mpfi_sub(d.get(), d.get(), x.get());
    mpfi_abs(d.get(), d.get());
    mpfi_mul(x.get(), d.get(), at.rate.get());
    detail::interval Y = at.state;
    detail::to_upper_point(Y);
    if (!(mpfi_cmp(x.get(), Y.get()) < 0)) {  // never near: the difference is a rounding of tau
      outcome o;
      o.kind = outcome_kind::certification_failed;
      o.cause = outcome_kind::certify_growth;
      o.tau = static_cast<double>(tau);
      throw numerical_failure(o);
    }
    mpfi_add(err.get(), at.error.get(), x.get());  // |y(t rate) - P(tau)|
    mpfi_set_ui(scale.get(), 0);
    mpfi_set_ui(sum.get(), 0);
    for (int i = 0; i < 3; ++i) {
      mpfi_union(scale.get(), scale.get(), ph.sqrtA[i].get());
      mpfi_mul(x.get(), at.P[i].get(), ph.sqrtA[i].get());
      if (ph.axes.sign(i) < 0) mpfi_neg(x.get(), x.get());
      detail::set_decimal(d, omega_cells[ph.axes.axis(i)]);
      mpfi_sub(x.get(), x.get(), d.get());
      mpfi_sqr(x.get(), x.get());
      mpfi_add(sum.get(), sum.get(), x.get());
    }
    mpfi_sqrt(sum.get(), sum.get());
    detail::to_upper_point(scale);
    mpfi_mul(err.get(), err.get(), scale.get());
    mpfi_add(err.get(), err.get(), sum.get());
    detail::to_zero_hull(err);
    mpfi_put(max_omega_.get(), err.get());
    return {Omega_radius, upper_text(err)};
  }
  std::string max_radius() const { return upper_text(cert_->max_radius()); }
  std::string max_radius_omega() const { return upper_text(max_omega_); }
  std::string method() const {
    return fmt::format("mpfi bits={} interval Chebyshev residual, Lohner QR propagation", bits_);
  }

 private:
  const scene& scene_;
  mpfr_prec_t bits_;
  std::optional<certifier> cert_;
  std::optional<physical_intervals> physical_;
  detail::interval max_omega_{bits_};
};

}  // namespace eulervop::app
