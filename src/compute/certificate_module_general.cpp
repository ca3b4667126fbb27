// The certificate of a run (certified_reference.hpp): every scene, by the ball certifier of
// certify/ball_certifier.hpp. Part of the certificate module.
#include "compute/certified_reference.hpp"
#include "compute/certify_pipeline.hpp"

#include <eulervop/model/wide_formula_cells.hpp>
#include <eulervop/certify/ball_certifier.hpp>
#include <eulervop/certify/ball_row_radius.hpp>
#include <eulervop/scene/scene_certification_problem.hpp>

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace eulervop::scene {
// In certificate_module.cpp.
EULERVOP_CERTIFICATION_PROBLEM_CELL(extern, double)
EULERVOP_CERTIFICATION_PROBLEM_CELL(extern, quad)
EULERVOP_CERTIFICATION_PROBLEM_CELL(extern, mpfr_real)
}  // namespace eulervop::scene

namespace eulervop::app {
namespace {

class general_path {
 public:
  general_path(const scene& s, const eulervop::precision& p, unsigned workers)
      : scene_(s), bits_(certify_bits(p)), workers_(workers) {}

  template <scalar T, std::size_t D>
  void add_segment(const chebyshev_segment<T, D>& seg, const std::vector<T>& nodes) {
    if (!certifier_) {
      certifier_.emplace(eulervop::scene::certification_problem_of<T>(scene_, bits_), nodes.size() - 1);
      certifier_->expect_rows(row_times_);
      if (workers_ > 0)
        pipeline_.emplace(*certifier_, workers_, segments_in_flight(nodes.size(), bits_, workers_));
    }
    if (pipeline_)
      pipeline_->add_segment(seg);
    else
      certifier_->add_segment(seg);
  }

  // Before the first segment (later, the rows are evaluated when they run).
  template <scalar T>
  void expect_rows(const std::vector<T>& tau) {
    if (certifier_) return;
    auto balls = std::make_shared<std::vector<ball>>(tau.size());
    for (std::size_t k = 0; k < tau.size(); ++k) set_exact((*balls)[k], tau[k]);
    row_times_ = std::move(balls);
  }

  template <scalar T>
  certified_radii radii(const T& tau, const T& t, const certified_cells& cells);

  std::string method() const {
    return fmt::format("arb bits={} ball Chebyshev models, {}-state Lohner parallelepiped", bits_,
                       certifier_ ? certifier_->problem().dimension : 0);
  }

  std::optional<certify_pipeline<ball_certifier>>& pipeline() { return pipeline_; }

 private:
  const scene& scene_;
  mpfr_prec_t bits_;
  unsigned workers_;
  std::shared_ptr<const std::vector<ball>> row_times_;
  std::optional<ball_certifier> certifier_;
  // Last: stopped before the certifier goes.
  std::optional<certify_pipeline<ball_certifier>> pipeline_;
};

template <scalar T>
certified_radii general_path::radii(const T& tau, const T& t, const certified_cells& cells) {
  const certification_problem& p = certifier_->problem();
  const slong prec = p.prec;
  const ball_row row = certifier_->enclose(tau);
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

}  // namespace

std::unique_ptr<run_certificate> make_general_certificate(const scene& s, const eulervop::precision& p,
                                                          unsigned workers) {
  return std::make_unique<path_certificate<general_path>>(s, p, workers);
}

}  // namespace eulervop::app
