// `--certify` in the program: which scenes and precisions can be certified and on which path,
// the certificate of a streamed run, and the radius columns' text (docs/certified.md; the
// mathematics is in include/eulervop/certify/).
//
// Two paths prove the same statement. The fast one (certify/certifier.hpp) takes Eq. 5 with a
// constant torque: the paper's problem, with kernels built for its unit coefficients. The general
// one (certify/ball_certifier.hpp) takes every other scene: the coefficient and direct forms,
// torques of any formula of time and state, pieces, the gravity gradient, and the attitude with
// the rates as one problem of 7 states.
#pragma once

#include "compute/certified_row.hpp"
#include "compute/certify_pipeline.hpp"
#include "compute/scene_library.hpp"

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/ball_certifier.hpp>
#include <eulervop/certify/ball_row_radius.hpp>
#include <eulervop/certify/certifier.hpp>
#include <eulervop/certify/interval.hpp>
#include <eulervop/certify/omega_radius.hpp>
#include <eulervop/certify/row_enclosure.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/segment.hpp>
#include <eulervop/scene/scene_certification_problem.hpp>
#include <eulervop/scene/scene_exact_problem.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <mpfr.h>

namespace eulervop::app {

// The working precision of the certificate: the reference's bits plus 64, so that the interval
// arithmetic adds nothing visible to the reference's own error.
inline mpfr_prec_t certify_bits(const eulervop::precision& p) {
  const unsigned bits = p.type == eulervop::precision::kind::mpfr ? mpfr_effective_bits(p.bits) : p.bits;
  return static_cast<mpfr_prec_t>(bits + 64);
}

// The fast path takes Eq. 5 with a constant torque and no attitude; everything else that
// --certify takes goes the general path.
inline bool takes_fast_path(const scene& s) {
  return !s.has_torque_law() && !s.has_attitude() && !s.gravity_gradient && !s.is_coefficient_form() &&
         !uses_direct_form(s);
}

// An upper bound as a decimal with three significant digits, rounded up ("2.35e-27").
inline std::string upper_text(const interval& x) {
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
inline std::string upper_text(const ball& x) {
  arf_t u;
  arf_init(u);
  arb_get_abs_ubound_arf(u, x.get(), 64);
  mpfr_t m;
  mpfr_init2(m, 64);
  arf_get_mpfr(m, u, MPFR_RNDU);
  char* text = nullptr;
  mpfr_asprintf(&text, "%.2RUe", m);
  std::string out = text;
  mpfr_free_str(text);
  mpfr_clear(m);
  arf_clear(u);
  return out;
}


// The certificate of one streamed run, the body of run_certificate (run_certificate.hpp): created
// at the first segment (which tells the degree). With `workers` > 0 it runs on threads
// (certify_pipeline.hpp); rows then go through row().
class certificate_of_run {
 public:
  certificate_of_run(const scene& s, const eulervop::precision& p, unsigned workers)
      : scene_(s), precision_(p), bits_(certify_bits(p)), workers_(workers), fast_(takes_fast_path(s)) {
    if (fast_ && s.is_physical()) omega_.emplace(exact_scaling_of(s, bits_));
  }

  template <scalar T, std::size_t D>
  void add_segment(const chebyshev_segment<T, D>& seg, const std::vector<T>& nodes);
  // Runs `task` (a row: it may call radii) once every segment added before it is checked, and
  // before any added after it.
  void row(std::function<void()> task) {
    if (fast_pipeline_)
      fast_pipeline_->add_row(std::move(task));
    else if (general_pipeline_)
      general_pipeline_->add_row(std::move(task));
    else
      task();
  }
  // Waits for every segment and row (rethrowing the first failure).
  void finish() {
    if (fast_pipeline_) fast_pipeline_->finish();
    if (general_pipeline_) general_pipeline_->finish();
  }
  // Stops the threads, dropping what has not run (for a run that is abandoned).
  void close() {
    fast_pipeline_.reset();
    general_pipeline_.reset();
  }

  // The radii of a row at tau (and t, a physical scene's time) printed as `cells`.
  template <scalar T>
  certified_radii radii(const T& tau, const T& t, const certified_cells& cells);

  const certified_maxima& maxima() const { return max_; }
  std::string method() const {
    if (fast_)
      return fmt::format(
          "mpfi bits={} Chebyshev residual by exact products on an integer grid, 3-state Lohner QR propagation "
          "(fast path)",
          bits_);
    return fmt::format("arb bits={} ball Chebyshev models, {}-state Lohner QR propagation (general path)", bits_,
                       general_ ? general_->problem().dimension : 0);
  }

 private:
  // Segments the pipeline may hold: as many as about 16 MB of checks allow (a check of n1 nodes
  // at b bits takes about 8 n1 b bytes on the fast path, measured: 60 kB in quad; the general
  // path's about 200 n1 b), at least 2 per worker and 2 more, at most 128 per worker. A deep queue
  // keeps both workers busy while the in-order part catches up: at 4 per worker the paper scene's
  // --certify took 3% longer than at 32, and at 100 2% less than at 32.
  std::size_t segments_in_flight(std::size_t n1) const {
    const double check_bytes = (fast_ ? 8.0 : 200.0) * static_cast<double>(n1) * static_cast<double>(bits_);
    const auto fit = static_cast<std::size_t>(16e6 / check_bytes);
    return std::clamp<std::size_t>(fit, 2 * workers_ + 2, 128 * workers_ + 2);
  }
  void raise(std::string& max, const std::string& text) {
    if (max.empty() || std::stod(text) > std::stod(max)) max = text;
  }
  template <scalar T>
  certified_radii fast_radii(const T& tau, const T& t, const certified_cells& cells);
  template <scalar T>
  certified_radii general_radii(const T& tau, const T& t, const certified_cells& cells);

  const scene& scene_;
  eulervop::precision precision_;
  mpfr_prec_t bits_;
  unsigned workers_;
  bool fast_;
  std::optional<certifier> fast_cert_;
  std::optional<ball_certifier> general_;
  std::optional<omega_radius> omega_;
  certified_maxima max_;
  // Last: stopped before the certifiers go.
  std::optional<certify_pipeline<certifier>> fast_pipeline_;
  std::optional<certify_pipeline<ball_certifier>> general_pipeline_;
};

template <scalar T, std::size_t D>
void certificate_of_run::add_segment(const chebyshev_segment<T, D>& seg, const std::vector<T>& nodes) {
  if (fast_) {
    if constexpr (D == 3) {
      if (!fast_cert_) {
        fast_cert_.emplace(bits_, nodes.size() - 1, exact_problem_of(scene_, bits_));
        if (workers_ > 0) fast_pipeline_.emplace(*fast_cert_, workers_, segments_in_flight(nodes.size()));
      }
      if (fast_pipeline_)
        fast_pipeline_->add_segment(seg);
      else
        fast_cert_->add_segment(seg);
    } else {
      throw std::logic_error("run_certificate: a fast-path scene with 7 states");
    }
    return;
  }
  if (!general_) {
    general_.emplace(eulervop::scene::certification_problem_of<T>(scene_, bits_), nodes.size() - 1);
    if (workers_ > 0) general_pipeline_.emplace(*general_, workers_, segments_in_flight(nodes.size()));
  }
  if (general_pipeline_)
    general_pipeline_->add_segment(seg);
  else
    general_->add_segment(seg);
}

template <scalar T>
certified_radii certificate_of_run::radii(const T& tau, const T& t, const certified_cells& cells) {
  certified_radii out = fast_ ? fast_radii(tau, t, cells) : general_radii(tau, t, cells);
  raise(max_.state, out.state);
  if (out.omega) raise(max_.omega, *out.omega);
  if (out.q) raise(max_.q, *out.q);
  return out;
}

template <scalar T>
certified_radii certificate_of_run::fast_radii(const T& tau, const T& t, const certified_cells& cells) {
  certified_radii out;
  const row_enclosure at = fast_cert_->enclose(tau);
  out.state = upper_text(fast_cert_->row_radius(at, cells.state));
  if (cells.omega) out.omega = upper_text(omega_->at(at, tau, t, *cells.omega));
  return out;
}

template <scalar T>
certified_radii certificate_of_run::general_radii(const T& tau, const T& t, const certified_cells& cells) {
  const certification_problem& p = general_->problem();
  const slong prec = p.prec;
  const ball_row row = general_->enclose(tau);
  // A physical row in the normalized form stands for t, whose exact tau is t dtau/dt.
  ball shift;
  if (cells.omega) {
    ball rate;
    arb_inv(rate.get(), p.variables.rate_inverse.get(), prec);
    set_exact(shift, t);
    arb_mul(shift.get(), shift.get(), rate.get(), prec);
    ball b;
    set_exact(b, tau);
    arb_sub(shift.get(), shift.get(), b.get(), prec);
  }
  certified_radii out;
  const std::vector<std::string> state(cells.state.begin(), cells.state.end());
  const ball none;
  try {
    out.state = upper_text(group_radius(row, 0, 3, state, none, std::nullopt, prec));
    if (cells.omega) {
      const group_map map{p.variables.axes, p.variables.state_scale};
      const std::vector<std::string> omega(cells.omega->begin(), cells.omega->end());
      out.omega = upper_text(group_radius(row, 0, 3, omega, shift, map, prec));
    }
    if (cells.q) {
      const std::vector<std::string> q(cells.q->begin(), cells.q->end());
      out.q = upper_text(group_radius(row, 3, 4, q, shift, std::nullopt, prec));
    }
  } catch (const std::domain_error&) {
    outcome o;
    o.kind = outcome_kind::certification_failed;
    o.cause = outcome_kind::certify_growth;
    o.tau = static_cast<double>(tau);
    throw numerical_failure(o);
  }
  return out;
}

}  // namespace eulervop::app
