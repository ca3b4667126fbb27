// `--certify` in the program: which scenes and precisions can be certified, the certificate of
// a streamed run, and the radius column's text (docs/certified.md; the mathematics is in
// include/eulervop/certify/).
#pragma once

#include "compute/certify_pipeline.hpp"
#include "compute/scene_library.hpp"

#include <eulervop/certify/certifier.hpp>
#include <eulervop/certify/interval.hpp>
#include <eulervop/certify/omega_radius.hpp>
#include <eulervop/certify/row_enclosure.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/segment.hpp>
#include <eulervop/scene/scene_exact_problem.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <functional>
#include <optional>
#include <string>
#include <vector>
#include <thread>
#include <variant>

#include <mpfr.h>
#include <sched.h>

namespace eulervop::app {

// The working precision of the certificate: the reference's bits plus 64, so that the interval
// arithmetic adds nothing visible to the reference's own error.
inline mpfr_prec_t certify_bits(const eulervop::precision& p) {
  const unsigned bits = p.type == eulervop::precision::kind::mpfr ? mpfr_effective_bits(p.bits) : p.bits;
  return static_cast<mpfr_prec_t>(bits + 64);
}

// Why `--certify` cannot run on this scene at this precision (an input_error, exit 2), or nothing.
inline void require_certifiable(const scene& s, const eulervop::precision& p) {
  // Every reason at once, so that one try tells the user all that stands in the way.
  std::vector<std::string> reasons;
  if (p.type == eulervop::precision::kind::binary64)
    reasons.push_back("precision double is not certified (its reference is the double run's own rounding; use quad "
                      "or mpfr:BITS)");
  if (s.couples_attitude())
    reasons.push_back("its torque reads the attitude (the gravity gradient, or a formula naming q0..q3), so the rates "
                      "and q are one problem of 7 states, which is not certified");
  else if (s.has_torque_law())
    reasons.push_back(fmt::format("its torque changes with {} (a formula or pieces); only a constant torque is certified",
                                  torque_kind_of(s) == torque_kind::of_state ? "the state" : "the time"));
  if (s.has_attitude() && !s.couples_attitude())
    reasons.push_back("it has an attitude ([initial] q), which is not certified (its rates are: leave q out)");
  if (s.is_coefficient_form())
    reasons.push_back("it is in the coefficient form ([equations] a); only Eq. 5 is certified");
  else if (uses_direct_form(s))
    reasons.push_back("its moments of inertia are (nearly) equal, so it is integrated in the direct form of Eq. 1, "
                      "which is not certified");
  if (const auto* e = std::get_if<eulervop::scene::initial_elements>(&s.initial); e && e->u.value != 0)
    reasons.push_back(fmt::format("its initial u = {} needs elliptic functions of the decimals, which are not "
                                  "enclosed (give [initial] Omega, or u = 0)",
                                  e->u.text));
  if (reasons.empty()) return;
  std::string text;
  for (std::size_t i = 0; i < reasons.size(); ++i)
    text += fmt::format("{}({}) {}", i ? "; " : "", i + 1, reasons[i]);
  throw input_error(fmt::format("--certify: scene {} cannot be certified, for {} reason{}: {}", s.name, reasons.size(),
                                reasons.size() == 1 ? "" : "s", text));
}

// The threads that prepare a certificate's segments (certify_pipeline.hpp): the cores this
// process may run on (its affinity, so that `taskset -c 0` means one), at most 4, as the
// integration and the in-order part then set the pace; none on one core, where the certificate
// runs in the integration's thread.
inline unsigned certify_workers() {
  unsigned cores = std::thread::hardware_concurrency();
  cpu_set_t allowed;
  if (sched_getaffinity(0, sizeof allowed, &allowed) == 0) cores = static_cast<unsigned>(CPU_COUNT(&allowed));
  return cores >= 2 ? std::min(cores, 4u) : 0;
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

// The certificate of one streamed run: created at the first segment (which tells the degree).
// With `workers` > 0 it runs on threads (certify_pipeline.hpp); rows then go through row().
class run_certificate {
 public:
  run_certificate(const scene& s, const eulervop::precision& p, unsigned workers)
      : scene_(s), bits_(certify_bits(p)), workers_(workers) {
    if (s.is_physical()) omega_.emplace(exact_scaling_of(s, bits_));
  }

  template <scalar T>
  void add_segment(const chebyshev_segment<T>& seg, const std::vector<T>& nodes) {
    if (!cert_) {
      cert_.emplace(bits_, nodes.size() - 1, exact_problem_of(scene_, bits_));
      if (workers_ > 0) pipeline_.emplace(*cert_, workers_, segments_in_flight(nodes.size()));
    }
    if (pipeline_)
      pipeline_->add_segment(seg);
    else
      cert_->add_segment(seg);
  }
  // Runs `task` (a row: it may call radius or physical_radii) once every segment added before
  // it is checked, and before any added after it.
  void row(std::function<void()> task) {
    if (pipeline_)
      pipeline_->add_row(std::move(task));
    else
      task();
  }
  // Waits for every segment and row (rethrowing the first failure).
  void finish() {
    if (pipeline_) pipeline_->finish();
  }
  // Stops the threads, dropping what has not run (for a run that is abandoned).
  void close() { pipeline_.reset(); }

  // The radius of a row printed as `cells` (the three state texts), at tau.
  template <scalar T>
  std::string radius(const T& tau, const std::array<std::string, 3>& cells) {
    return upper_text(cert_->row_radius(tau, cells));
  }
  // A physical scene's row: the radius of Omega (at the row's tau), and of omega in rad/s at the
  // row's t (omega_radius.hpp).
  template <scalar T>
  std::array<std::string, 2> physical_radii(const T& tau, const T& t, const std::array<std::string, 3>& Omega_cells,
                                            const std::array<std::string, 3>& omega_cells) {
    const row_enclosure at = cert_->enclose(tau);
    const std::string Omega_radius = upper_text(cert_->row_radius(at, Omega_cells));
    return {Omega_radius, upper_text(omega_->at(at, tau, t, omega_cells))};
  }
  std::string max_radius() const { return upper_text(cert_->max_radius()); }
  std::string max_radius_omega() const { return upper_text(omega_->max_radius()); }
  std::string method() const {
    return fmt::format("mpfi bits={} interval Chebyshev residual, Lohner QR propagation", bits_);
  }

 private:
  // Segments the pipeline may hold: as many as about 16 MB of checks allow (a check of n1 nodes
  // at b bits takes about 26 n1 b bytes, measured: 0.2 MB in quad), at least 2 per worker and
  // 2 more, at most 32 per worker (beyond, the runs got no faster).
  std::size_t segments_in_flight(std::size_t n1) const {
    const double check_bytes = 26.0 * static_cast<double>(n1) * static_cast<double>(bits_);
    const auto fit = static_cast<std::size_t>(16e6 / check_bytes);
    return std::clamp<std::size_t>(fit, 2 * workers_ + 2, 32 * workers_ + 2);
  }

  const scene& scene_;
  mpfr_prec_t bits_;
  unsigned workers_;
  std::optional<certifier> cert_;
  std::optional<omega_radius> omega_;
  std::optional<certify_pipeline> pipeline_;  // last: stopped before the certifier goes
};

}  // namespace eulervop::app
