// The certificate on threads (src/compute/certify_pipeline.hpp) against the same certificate on
// one thread (certifier::add_segment): every row's radius must be the same interval, bit for bit,
// whatever the number of threads; a failure must reach the caller, and the one reported must be
// the first in segment order.
#include "compute/certify_pipeline.hpp"

#include <eulervop/certify/certifier.hpp>
#include <eulervop/certify/exact_problem.hpp>
#include <eulervop/core/numerical_failure.hpp>
#include <eulervop/reference/integrate.hpp>

#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace {

using eulervop::certifier;
using eulervop::quad;
using eulervop::vec3;
using eulervop::app::certify_pipeline;

constexpr mpfr_prec_t working_bits = 113 + 64;

// The right end of x, exactly (hexadecimal).
std::string exact_text(const eulervop::interval& x) {
  mpfr_t r;
  mpfr_init2(r, x.bits());
  mpfi_get_right(r, x.get());
  char* text = nullptr;
  mpfr_asprintf(&text, "%Ra", r);
  std::string out = text;
  mpfr_free_str(text);
  mpfr_clear(r);
  return out;
}

// The paper scene (G = (1, 1, 1), Omega(0) = (0.5, 0, 1)) in quad to tau = 12, 49 rows, certified
// with `workers` threads (0: on this thread, with certifier::add_segment). `tamper` may alter a
// segment before the sampler and the certificate see it. Returns each row's radius, exactly.
std::vector<std::string> radii(unsigned workers,
                               const std::function<void(eulervop::chebyshev_segment<quad>&, std::size_t)>& tamper = {}) {
  eulervop::euler_problem<quad> run;
  run.torque.G = {quad(1), quad(1), quad(1)};
  run.Omega0 = {quad(0.5), quad(0), quad(1)};
  const eulervop::exact_problem exact = eulervop::exact_problem_of({"1", "1", "1"}, {"0.5", "0", "1"}, working_bits);
  std::vector<quad> taus;
  for (int i = 0; i <= 48; ++i) taus.push_back(quad(12) * i / 48);
  std::optional<certifier> cert;
  std::optional<certify_pipeline<certifier>> pipeline;
  std::vector<std::string> out;
  eulervop::segment_sampler<quad> sampler(taus, [&](std::size_t, const quad& tau, const vec3<quad>& Om) {
    const std::array<std::string, 3> cells = {eulervop::to_text(Om[0]), eulervop::to_text(Om[1]),
                                              eulervop::to_text(Om[2])};
    const auto row = [&out, &cert, tau, cells] { out.push_back(exact_text(cert->row_radius(tau, cells))); };
    if (pipeline) pipeline->add_row(row); else row();
  });
  eulervop::chebyshev_picard<eulervop::euler_problem<quad>> integrator(eulervop::picard_settings{});
  std::size_t index = 0;
  integrator.run_segments(run, quad(12), [&](const eulervop::chebyshev_segment<quad>& seg,
                                             const std::vector<quad>& nodes) {
    eulervop::chebyshev_segment<quad> s = seg;
    if (tamper) tamper(s, index);
    ++index;
    sampler(s, nodes);
    if (!cert) {
      cert.emplace(working_bits, nodes.size() - 1, exact);
      if (workers > 0) pipeline.emplace(*cert, workers, 4 * workers);
    }
    if (pipeline) pipeline->add_segment(s); else cert->add_segment(s);
  });
  sampler.finish();
  if (pipeline) pipeline->finish();
  return out;
}

TEST(CertifyPipeline, ThreadsGiveTheRadiiOfOneThread) {
  const std::vector<std::string> one = radii(0);
  ASSERT_EQ(one.size(), 49u);
  for (unsigned workers : {1u, 2u, 3u}) EXPECT_EQ(radii(workers), one) << workers << " workers";
}

// Two segments made non-finite: the failure reported is the first one's, at its start, as on one
// thread; later segments may already be prepared (and fail) on other threads.
TEST(CertifyPipeline, TheFirstFailureInSegmentOrderReachesTheCaller) {
  double tau_at_failure[2] = {0, 0};
  std::size_t failing[2] = {7, 8};
  double first_begin = 0;
  for (unsigned workers : {0u, 2u}) {
    try {
      radii(workers, [&](eulervop::chebyshev_segment<quad>& s, std::size_t index) {
        if (index == failing[0]) first_begin = static_cast<double>(s.tau_begin);
        if (index == failing[0] || index == failing[1]) s.values[3][1] = std::numeric_limits<quad>::quiet_NaN();
      });
      ADD_FAILURE() << workers << " workers: a non-finite node value was certified";
    } catch (const eulervop::numerical_failure& e) {
      EXPECT_EQ(e.status().cause, eulervop::outcome_kind::certify_non_finite);
      ASSERT_TRUE(e.status().tau.has_value());
      tau_at_failure[workers > 0] = *e.status().tau;
    }
  }
  EXPECT_EQ(tau_at_failure[0], first_begin);
  EXPECT_EQ(tau_at_failure[1], first_begin);
}

}  // namespace
