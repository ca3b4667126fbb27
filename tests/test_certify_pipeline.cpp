// The certificate on threads (src/compute/certify_pipeline.hpp) against the same certificate on
// one thread (ball_certifier::add_segment): every row's radius must be the same ball, bit for bit,
// whatever the number of threads; a failure must reach the caller, and the one reported must be
// the first in segment order.
#include "compute/certify_pipeline.hpp"

#include <eulervop/certify/ball_certifier.hpp>
#include <eulervop/certify/ball_row_radius.hpp>
#include <eulervop/core/numerical_failure.hpp>
#include <eulervop/reference/integrate.hpp>
#include <eulervop/scene/scene.hpp>
#include <eulervop/scene/scene_certification_problem.hpp>
#include <eulervop/scene/scene_problem.hpp>

#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace {

namespace sc = eulervop::scene;
using eulervop::ball;
using eulervop::ball_certifier;
using eulervop::quad;
using eulervop::vec3;
using eulervop::app::certify_pipeline;

constexpr slong working_bits = 113 + 64;

// x exactly (Arb's decimal text with enough digits for its midpoint and radius).
std::string exact_text(const ball& x) {
  char* t = arb_get_str(x.get(), 60, ARB_STR_MORE);
  std::string out = t;
  flint_free(t);
  return out;
}

// The paper scene (G = (1, 1, 1), Omega(0) = (0.5, 0, 1)) in quad to tau = 12, 49 rows, certified
// with `workers` threads (0: on this thread, with ball_certifier::add_segment). `tamper` may alter
// a segment before the sampler and the certificate see it. With `rows_expected` the certifier is
// told the rows' times first, so that each segment's check evaluates its rows' parts when it is
// prepared. Returns each row's radius, exactly.
std::vector<std::string> radii(unsigned workers,
                               const std::function<void(eulervop::chebyshev_segment<quad>&, std::size_t)>& tamper = {},
                               bool rows_expected = false) {
  const sc::scene s = sc::parse_scene(R"(name = "paper"
[torque]
G = [1, 1, 1]
[initial]
Omega = [0.5, 0, 1]
[span]
tau_end = 12
samples = 49
)", "test");
  const eulervop::euler_problem<quad> run = sc::to_problem<quad>(s);
  std::vector<quad> taus;
  for (int i = 0; i <= 48; ++i) taus.push_back(quad(12) * i / 48);
  std::optional<ball_certifier> cert;
  std::optional<certify_pipeline<ball_certifier>> pipeline;
  std::vector<std::string> out;
  eulervop::segment_sampler<quad> sampler(taus, [&](std::size_t, const quad& tau, const vec3<quad>& Om) {
    const std::vector<std::string> cells = {eulervop::to_text(Om[0]), eulervop::to_text(Om[1]),
                                            eulervop::to_text(Om[2])};
    const auto row = [&out, &cert, tau, cells] {
      out.push_back(exact_text(eulervop::group_radius(cert->enclose(tau), 0, 3, cells, ball(), std::nullopt,
                                                      working_bits)));
    };
    if (pipeline) pipeline->add_row(row); else row();
  });
  eulervop::chebyshev_picard<eulervop::euler_problem<quad>> integrator(eulervop::picard_settings{});
  std::size_t index = 0;
  integrator.run_segments(run, quad(12), [&](const eulervop::chebyshev_segment<quad>& seg,
                                             const std::vector<quad>& nodes) {
    eulervop::chebyshev_segment<quad> c = seg;
    if (tamper) tamper(c, index);
    ++index;
    sampler(c, nodes);
    if (!cert) {
      cert.emplace(sc::certification_problem_of<quad>(s, working_bits), nodes.size() - 1);
      if (rows_expected) {
        auto times = std::make_shared<std::vector<ball>>(taus.size());
        for (std::size_t k = 0; k < taus.size(); ++k) eulervop::set_exact((*times)[k], taus[k]);
        cert->expect_rows(times);
      }
      if (workers > 0) pipeline.emplace(*cert, workers, 4 * workers);
    }
    if (pipeline) pipeline->add_segment(c); else cert->add_segment(c);
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

// A row's part evaluated with its segment's check (on a worker, before the segments between
// are prepared) is the ball the row evaluates when it runs: the same radii, bit for bit.
TEST(CertifyPipeline, RowsPreparedWithTheirSegmentGiveTheRadiiOfRowsEvaluatedWhenTheyRun) {
  const std::vector<std::string> when_run = radii(0);
  ASSERT_EQ(when_run.size(), 49u);
  for (unsigned workers : {0u, 2u}) EXPECT_EQ(radii(workers, {}, true), when_run) << workers << " workers";
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
