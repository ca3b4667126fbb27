// The certificate of a run on the fast path (certified_reference.hpp): Eq. 5 with a constant
// torque, by the interval certifier of certify/certifier.hpp. Part of the certificate module.
#include "compute/certified_reference.hpp"
#include "compute/certify_pipeline.hpp"

#include <eulervop/model/wide_formula_cells.hpp>
#include <eulervop/certify/certifier.hpp>
#include <eulervop/certify/omega_radius.hpp>
#include <eulervop/certify/row_enclosure.hpp>
#include <eulervop/scene/scene_exact_problem.hpp>

#include <optional>
#include <stdexcept>

namespace eulervop::app {
namespace {

class fast_path {
 public:
  fast_path(const scene& s, const eulervop::precision& p, unsigned workers)
      : scene_(s), bits_(certify_bits(p)), workers_(workers) {
    if (s.is_physical()) omega_.emplace(exact_scaling_of(s, bits_));
  }

  template <scalar T, std::size_t D>
  void add_segment(const chebyshev_segment<T, D>& seg, const std::vector<T>& nodes) {
    if constexpr (D == 3) {
      if (!certifier_) {
        certifier_.emplace(bits_, nodes.size() - 1, exact_problem_of(scene_, bits_));
        if (workers_ > 0)
          pipeline_.emplace(*certifier_, workers_, segments_in_flight(8.0, nodes.size(), bits_, workers_));
      }
      if (pipeline_)
        pipeline_->add_segment(seg);
      else
        certifier_->add_segment(seg);
    } else {
      throw std::logic_error("run_certificate: a fast-path scene with 7 states");
    }
  }

  template <scalar T>
  certified_radii radii(const T& tau, const T& t, const certified_cells& cells) {
    certified_radii out;
    const row_enclosure at = certifier_->enclose(tau);
    out.state = upper_text(certifier_->row_radius(at, cells.state));
    if (cells.omega) out.omega = upper_text(omega_->at(at, tau, t, *cells.omega));
    return out;
  }

  std::string method() const {
    return fmt::format(
        "mpfi bits={} Chebyshev residual by exact products on an integer grid, 3-state Lohner QR propagation "
        "(fast path)",
        bits_);
  }

  std::optional<certify_pipeline<certifier>>& pipeline() { return pipeline_; }

 private:
  const scene& scene_;
  mpfr_prec_t bits_;
  unsigned workers_;
  std::optional<certifier> certifier_;
  std::optional<omega_radius> omega_;
  // Last: stopped before the certifier goes.
  std::optional<certify_pipeline<certifier>> pipeline_;
};

}  // namespace

std::unique_ptr<run_certificate> make_fast_certificate(const scene& s, const eulervop::precision& p, unsigned workers) {
  return std::make_unique<path_certificate<fast_path>>(s, p, workers);
}

}  // namespace eulervop::app
