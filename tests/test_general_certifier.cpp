// The general path of --certify (include/eulervop/certify/ball_certifier.hpp) as a library:
// the same radii on any number of threads, the closed form near the separatrix, and planted errors
// in the integration alone, which the radii must cover (or the certificate refuse).
//
// Truth: Enright and Pryce's B5 in closed form, (sn, cn, dn)(t | m = 0.51) (DLMF 22.13), from
// Boost.Math's jacobi_elliptic in MPFR at 256 bits (dn as sqrt(1 - m sn^2), Boost's own dn being a
// ratio; 256 bits put its error near 1e-75, far below the quad radii here); torque-free motion
// near the separatrix by Eq. 12 in closed form (torque_free_truth.hpp) at 354 bits.
#include "compute/certify_pipeline.hpp"

#include <eulervop/certify/ball_certifier.hpp>
#include <eulervop/certify/ball_row_radius.hpp>
#include <eulervop/reference/integrate.hpp>
#include <eulervop/scene/expression_parser.hpp>
#include <eulervop/scene/scene.hpp>
#include <eulervop/scene/scene_certification_problem.hpp>
#include <eulervop/scene/scene_problem.hpp>

#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <gtest/gtest.h>

#include "torque_free_truth.hpp"

#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <type_traits>
#include <string>
#include <vector>

namespace {

namespace sc = eulervop::scene;
using eulervop::ball;
using eulervop::mpfr_real;
using eulervop::quad;
using eulervop::vec3;

const std::string source_dir = EULERVOP_SOURCE_DIR;
constexpr slong working_bits = 113 + 64;

// One row: its time, the state as printed, and the radius of that state.
struct certified_row {
  quad tau;
  std::array<std::string, 3> cells;
  ball radius;
};

// The rows of a 3-state scene's reference at `taus`, certified on the general path with `workers`
// threads (0: in this thread); `tamper` may alter the segments the sampler and the certificate
// see, `problem` the problem the reference integrates, and `integrated` its scene (the certificate
// keeps `s`'s).
std::vector<certified_row> general_rows(
    const sc::scene& s, const std::vector<quad>& taus, unsigned workers,
    const std::function<void(eulervop::chebyshev_segment<quad>&, std::size_t)>& tamper = {},
    const std::function<void(eulervop::euler_problem<quad>&)>& problem = {}, const sc::scene* integrated = nullptr) {
  std::optional<eulervop::ball_certifier> cert;
  std::optional<eulervop::app::certify_pipeline<eulervop::ball_certifier>> pipeline;
  std::vector<certified_row> out;
  eulervop::segment_sampler<quad> sampler(taus, [&](std::size_t, const quad& tau, const vec3<quad>& y) {
    certified_row row{tau, {eulervop::to_text(y[0]), eulervop::to_text(y[1]), eulervop::to_text(y[2])}, ball()};
    auto task = [&out, &cert, row]() mutable {
      const eulervop::ball_row at = cert->enclose(row.tau);
      row.radius = eulervop::group_radius(at, 0, 3, {row.cells.begin(), row.cells.end()}, ball(), std::nullopt,
                                          working_bits);
      out.push_back(row);
    };
    if (pipeline) pipeline->add_row(task); else task();
  });
  std::size_t index = 0;
  sc::with_problem<quad>(integrated ? *integrated : s, [&](auto run) {
    if constexpr (std::is_same_v<decltype(run), eulervop::euler_problem<quad>>)
      if (problem) problem(run);
    eulervop::chebyshev_picard<decltype(run)> integrator(eulervop::picard_settings{});
    integrator.run_segments(run, sc::tau_end_of<quad>(s), [&](const eulervop::chebyshev_segment<quad>& seg,
                                                              const std::vector<quad>& nodes) {
      eulervop::chebyshev_segment<quad> c = seg;
      if (tamper) tamper(c, index);
      ++index;
      sampler(c, nodes);
      if (!cert) {
        cert.emplace(sc::certification_problem_of<quad>(s, working_bits), nodes.size() - 1);
        if (workers > 0) pipeline.emplace(*cert, workers, 4 * workers);
      }
      if (pipeline) pipeline->add_segment(c); else cert->add_segment(c);
    });
    return 0;
  });
  sampler.finish();
  if (pipeline) pipeline->finish();
  return out;
}

std::vector<quad> equally_spaced(const quad& end, int n) {
  std::vector<quad> t;
  for (int i = 0; i + 1 < n; ++i) t.push_back(end * i / (n - 1));
  t.push_back(end);
  return t;
}

// The radii as exact texts, for comparisons bit for bit.
std::vector<std::string> texts(const std::vector<certified_row>& rows) {
  std::vector<std::string> out;
  for (const certified_row& r : rows) {
    char* t = arb_get_str(r.radius.get(), 60, ARB_STR_MORE);
    out.emplace_back(t);
    flint_free(t);
  }
  return out;
}

sc::scene scene_at(const std::string& relative) { return sc::load_scene_file(source_dir + "/" + relative); }

TEST(GeneralCertifier, ThreadsGiveTheRadiiOfOneThread) {
  const sc::scene s = scene_at("data/scenes/problems/tumbling-brick-damped.toml");
  sc::scene rates = s;
  rates.attitude.reset();  // the rates alone: a state torque of time, 3 states
  const std::vector<quad> taus = equally_spaced(sc::tau_end_of<quad>(rates), 31);
  const std::vector<std::string> one = texts(general_rows(rates, taus, 0));
  ASSERT_EQ(one.size(), 31u);
  for (unsigned workers : {1u, 2u, 3u}) EXPECT_EQ(texts(general_rows(rates, taus, workers)), one) << workers;
}

// Near the separatrix (hard/near-separatrix-free.toml: Omega(0) = (0.999999, 0, 1), k = 1 - 1e-6,
// where an error of the phase becomes an O(1) error of Omega every half period), every row holds
// the closed form and the largest radius is within 10 times the largest true error (measured:
// 7.06e-28 against 6.86e-28, 1.03 times, over 401 rows to tau = 100).
TEST(GeneralCertifier, NearTheSeparatrixTheRadiusIsWithinTenTimesTheTrueError) {
  const sc::scene s = scene_at("data/scenes/hard/near-separatrix-free.toml");
  const std::vector<certified_row> rows = general_rows(s, equally_spaced(sc::tau_end_of<quad>(s), 401), 0);
  const eulervop::mpfr_precision_scope scope(2 * working_bits);
  const mpfr_real c1("0.999999"), c2(1);
  double worst_radius = 0, worst_error = 0;
  for (const certified_row& r : rows) {
    const vec3<mpfr_real> exact = eulervop::test::torque_free_exact(c1, c2, mpfr_real(r.tau));
    mpfr_real e2 = 0;
    for (int i = 0; i < 3; ++i) {
      const mpfr_real d = *eulervop::from_text<mpfr_real>(r.cells[i]) - exact[i];
      e2 += d * d;
    }
    const double error = static_cast<double>(sqrt(e2)), radius = eulervop::magnitude_up(r.radius);
    ASSERT_LE(error, radius) << "tau " << static_cast<double>(r.tau);
    worst_radius = std::max(worst_radius, radius);
    worst_error = std::max(worst_error, error);
  }
  std::printf("near the separatrix: worst radius %.3e, worst error %.3e, ratio %.2f\n", worst_radius, worst_error,
              worst_radius / worst_error);
  EXPECT_LE(worst_radius, 10 * worst_error);
}

// B5's exact solution at t (closed form, see the header), in MPFR at 256 bits.
std::array<mpfr_real, 3> b5_truth(const quad& t) {
  const eulervop::mpfr_precision_scope scope(256);
  const mpfr_real m("0.51"), k = sqrt(m);
  mpfr_real cn, dn;
  const mpfr_real sn = boost::math::jacobi_elliptic(k, mpfr_real(t), &cn, &dn);
  return {sn, cn, sqrt(1 - m * sn * sn)};
}

// The largest true error and whether every row lies within its radius.
struct b5_outcome {
  double worst_error = 0, worst_radius = 0;
  bool covered = true;
};

b5_outcome against_b5(const std::vector<certified_row>& rows) {
  const eulervop::mpfr_precision_scope scope(256);
  b5_outcome o;
  for (const certified_row& r : rows) {
    const auto truth = b5_truth(r.tau);
    mpfr_real e2 = 0;
    for (int i = 0; i < 3; ++i) {
      const mpfr_real d = *eulervop::from_text<mpfr_real>(r.cells[i]) - truth[i];
      e2 += d * d;
    }
    const double error = static_cast<double>(sqrt(e2)), radius = eulervop::magnitude_up(r.radius);
    o.worst_error = std::max(o.worst_error, error);
    o.worst_radius = std::max(o.worst_radius, radius);
    if (!(error <= radius)) o.covered = false;
  }
  return o;
}

const sc::scene& b5() {
  static const sc::scene s = scene_at("data/scenes/problems/enright-pryce-b5.toml");
  return s;
}

// The clean run, for the planted errors to be compared with: covered, and tight.
TEST(GeneralCertifier, B5IsCoveredAndTight) {
  const b5_outcome o = against_b5(general_rows(b5(), equally_spaced(quad(20), 41), 0));
  EXPECT_TRUE(o.covered);
  EXPECT_LT(o.worst_radius, 30 * o.worst_error);
}

// A node value moved by a few ulps (2^-110, four ulps of quad at 1) and by 2^-90 (about 2^22
// ulps): the radii move with the rows (the certificate sees the values as they are), or the
// certificate refuses; the larger move visibly moves the rows.
TEST(GeneralCertifier, APlantedNodeValueIsCovered) {
  const b5_outcome clean = against_b5(general_rows(b5(), equally_spaced(quad(20), 41), 0));
  for (const int shift : {-110, -90})
    for (const std::size_t segment : {1u, 3u, 9u}) {  // segments with rows inside (not only on nodes)
      const b5_outcome o =
          against_b5(general_rows(b5(), equally_spaced(quad(20), 41), 0,
                                  [segment, shift](eulervop::chebyshev_segment<quad>& c, std::size_t index) {
                                    if (index == segment) c.values[5][1] += ldexp(quad(1), shift);
                                  }));
      EXPECT_TRUE(o.covered) << "segment " << segment << ", 2^" << shift;
      if (shift == -90) EXPECT_GT(o.worst_error, 100 * clean.worst_error) << "the planted error is visible";
    }
}

// The integration's coefficient a3 = -0.51 off by one ulp (quad), and by 2^20 of them, the
// certificate keeping -0.51: every row stays covered; the larger change visibly moves the rows.
TEST(GeneralCertifier, ACoefficientOffByAnUlpIsCovered) {
  const b5_outcome clean = against_b5(general_rows(b5(), equally_spaced(quad(20), 41), 0));
  for (const int ulps : {1, 1 << 20}) {
    const b5_outcome o = against_b5(general_rows(b5(), equally_spaced(quad(20), 41), 0, {},
                                                 [ulps](eulervop::euler_problem<quad>& p) {
                                                   for (int k = 0; k < ulps; k += std::max(1, ulps / 16))
                                                     p.a[2] += std::max(1, ulps / 16) *
                                                               (nextafter(p.a[2], quad(0)) - p.a[2]);
                                                 }));
    EXPECT_TRUE(o.covered) << ulps << " ulps";
    if (ulps > 1) EXPECT_GT(o.worst_error, 100 * clean.worst_error) << "the planted error is visible";
  }
}

// SciML's rigid body against its oracle (tools/oracles/forced_taylor.py, 95 digits), at t = 0..10.
struct oracle_outcome {
  double worst_error = 0, worst_radius = 0;
  bool covered = true;
};
oracle_outcome against_sciml(const std::vector<certified_row>& rows) {
  const eulervop::mpfr_precision_scope scope(400);
  std::ifstream in(source_dir + "/tests/data/general_oracles/sciml_10.csv");
  std::map<int, std::array<mpfr_real, 3>> truth;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#' || line[0] == 't') continue;
    std::stringstream cells(line);
    std::string c;
    std::getline(cells, c, ',');
    const int t = std::stoi(c);
    for (int i = 0; i < 3; ++i) {
      std::getline(cells, c, ',');
      truth[t][i] = mpfr_real(c);
    }
  }
  oracle_outcome o;
  for (const certified_row& r : rows) {
    const auto& y = truth.at(static_cast<int>(r.tau));
    mpfr_real e2 = 0;
    for (int i = 0; i < 3; ++i) {
      const mpfr_real d = *eulervop::from_text<mpfr_real>(r.cells[i]) - y[i];
      e2 += d * d;
    }
    const double error = static_cast<double>(sqrt(e2)), radius = eulervop::magnitude_up(r.radius);
    o.worst_error = std::max(o.worst_error, error);
    o.worst_radius = std::max(o.worst_radius, radius);
    if (!(error <= radius)) o.covered = false;
  }
  return o;
}

// The forcing's coefficient 0.25 off by one ulp of quad and by 2^20 of them in the integration
// alone (the certificate keeps 0.25): every row stays covered, and the larger change visibly moves
// the rows.
TEST(GeneralCertifier, AForcingCoefficientOffByAnUlpIsCovered) {
  const sc::scene s = scene_at("data/scenes/problems/sciml-rigid-body.toml");
  const std::vector<quad> taus = equally_spaced(quad(10), 11);
  const oracle_outcome clean = against_sciml(general_rows(s, taus, 0));
  EXPECT_TRUE(clean.covered);
  // One ulp of 0.25 in quad is 2^-114; 2^20 ulps, 2^-94.
  for (const char* coefficient : {"0.250000000000000000000000000000000048148248609680896326399448564623183",
                                  "0.250000000000000000000000000050487097934144755546350628178098318699085"}) {
    sc::scene changed = s;
    const auto law = std::make_shared<eulervop::torque_law>(*s.torque_law);
    const sc::expression_variables vars{{"t", "y1", "y2", "y3", "q0", "q1", "q2", "q3"}};
    law->base[2] = sc::parse_expression(std::string(coefficient) + "*sin(t)^2", vars);
    changed.torque_law = law;
    const oracle_outcome o = against_sciml(general_rows(s, taus, 0, {}, {}, &changed));
    EXPECT_TRUE(o.covered) << coefficient;
    if (coefficient[30] != '0') EXPECT_GT(o.worst_error, 100 * clean.worst_error) << "the planted error is visible";
  }
}

// A breakpoint moved in the integration alone (the piece's end 1e-25 later): the certificate's
// windows then lie inside a segment, and it refuses rather than prove a bound of other formulas.
TEST(GeneralCertifier, AMovedBreakpointIsRefused) {
  const sc::scene s = sc::parse_scene(R"(name = "kick"
[torque]
G = [0.0, 0.0, 0.0]
[[torque.piece]]
from = 1.0
to = "pi/2"
G = ["0.5 + tau", -0.25, 0.0]
[initial]
Omega = [0.5, 0.0, 1.0]
[span]
tau_end = 4.0
samples = 9
)", "test");
  const std::vector<quad> taus = equally_spaced(quad(4), 9);
  // The scene as written certifies, and covers an mpfr:256 run of it.
  EXPECT_NO_THROW(sc::with_problem<quad>(s, [&](const auto&) { return 0; }));
  sc::scene moved = s;
  const auto moved_law = std::make_shared<eulervop::torque_law>(*s.torque_law);
  moved_law->pieces[0].to = eulervop::constant_expression("1.5707963267948966192313216916397515");
  moved.torque_law = moved_law;
  // The certificate of `s` on the segments of `moved`.
  std::optional<eulervop::ball_certifier> cert;
  bool refused = false;
  try {
    sc::with_problem<quad>(moved, [&](const auto& problem) {
      eulervop::chebyshev_picard<std::decay_t<decltype(problem)>> integrator(eulervop::picard_settings{});
      integrator.run_segments(problem, quad(4), [&](const eulervop::chebyshev_segment<quad>& seg,
                                                    const std::vector<quad>& nodes) {
        if (!cert) cert.emplace(sc::certification_problem_of<quad>(s, working_bits), nodes.size() - 1);
        cert->add_segment(seg);
      });
      return 0;
    });
  } catch (const eulervop::numerical_failure& e) {
    refused = true;
    EXPECT_EQ(e.status().cause, eulervop::outcome_kind::certify_formula);
    EXPECT_NE(std::string(e.what()).find("inside a segment"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(refused);
}

}  // namespace
