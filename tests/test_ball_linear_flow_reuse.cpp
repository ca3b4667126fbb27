// The linear flow of the general path (certify/detail/ball_linear_flow.hpp, node_picard.hpp) as
// the certifier runs it: one flow per check, reused from segment to segment, and sweeps whose
// sums stay in registers for the common dimensions. The certificate must not depend on either:
//   - the register sweeps (gauss_seidel_sweep<N>) give the bits of the loop over memory
//     (gauss_seidel_sweep<0>), and whole iterations those of the iteration written out here as
//     it stood before (one sum per entry through a std::vector, from k = 0 up);
//   - a flow that has certified other segments (longer and shorter residuals, other Jacobians,
//     other weights) gives the same bits as a fresh one.
// Both are exact comparisons: the same double operations in the same order, and Arb's results
// for the same inputs, leave no rounding to tolerate. (That the flow's bounds hold the exact
// Phi and u is BallLinearFlow.PhiAndUHoldTheExactSolutions in test_ball_arithmetic.cpp.)
#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/ball_linear_flow.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/certify/detail/node_picard.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

namespace {

using eulervop::ball;
using eulervop::detail::chebyshev_model;

chebyshev_model random_model(std::mt19937_64& rng, slong n, double size, double rho) {
  chebyshev_model m(n);
  std::uniform_real_distribution<double> u(-1, 1);
  for (slong k = 0; k < n; ++k) arb_set_d(m.coeff(k), size * u(rng) * std::pow(rho, static_cast<double>(k)));
  return m;
}

// The sweeps of u as ball_linear_flow.hpp ran them before the register kernels (a copy, the
// reference here): Y = hl S (J (Y + r)), Gauss-Seidel over the nodes.
std::vector<double> u_sweeps_over_memory(const eulervop::detail::chebyshev_basis<double>& b, const std::vector<double>& Jn,
                                         const std::vector<double>& rn, std::size_t D, double hl) {
  const std::size_t m = b.nodes.size(), DD = D * D;
  std::vector<double> Y(m * D, 0.0), F(m * D, 0.0), acc(D);
  const auto product_at = [&](std::size_t l) {
    for (std::size_t i = 0; i < D; ++i) {
      double a = 0;
      for (std::size_t k = 0; k < D; ++k) a += Jn[l * DD + i * D + k] * (Y[l * D + k] + rn[l * D + k]);
      F[l * D + i] = a;
    }
  };
  for (std::size_t l = 0; l < m; ++l) product_at(l);
  for (int sweep = 0; sweep < 400; ++sweep) {
    double change = 0, size = 0;
    for (std::size_t l = 0; l < m; ++l) {
      std::fill(acc.begin(), acc.end(), 0.0);
      for (std::size_t k = 0; k < m; ++k)
        for (std::size_t i = 0; i < D; ++i) acc[i] += b.integral[l * m + k] * F[k * D + i];
      for (std::size_t i = 0; i < D; ++i) {
        const double next = hl * acc[i];
        change = std::max(change, std::abs(next - Y[l * D + i]));
        size = std::max(size, std::abs(next));
        Y[l * D + i] = next;
      }
      product_at(l);
    }
    if (change <= 1e-10 * size || size == 0) break;
  }
  return Y;
}

// One sweep of gauss_seidel_sweep<N> against gauss_seidel_sweep<0>, with a finish that feeds
// each node's sums back into F's row (as the iterations do), so that the order of the updates is
// tested along with the order of the sums.
template <std::size_t N>
void expect_sweep_matches_loop(std::mt19937_64& rng, std::size_t m) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> S(m * m), F0(m * N);
  for (double& x : S) x = u(rng);
  for (double& x : F0) x = std::ldexp(u(rng), static_cast<int>(rng() % 40) - 20);  // sums that round
  std::vector<double> F[2] = {F0, F0}, out[2] = {std::vector<double>(m * N), std::vector<double>(m * N)}, acc;
  const auto finish = [&](int which) {
    return [&, which](std::size_t l, const double* a) {
      for (std::size_t i = 0; i < N; ++i) {
        out[which][l * N + i] = a[i];
        F[which][l * N + i] = 0.3 * a[i] + F[which][l * N + (i + 1) % N];
      }
    };
  };
  eulervop::detail::gauss_seidel_sweep<N>(S.data(), F[0].data(), m, N, acc, finish(0));
  eulervop::detail::gauss_seidel_sweep<0>(S.data(), F[1].data(), m, N, acc, finish(1));
  for (std::size_t q = 0; q < m * N; ++q) ASSERT_EQ(out[0][q], out[1][q]) << "N " << N << " m " << m << " at " << q;
}

TEST(NodePicard, RegisterSweepsAreTheLoopsBits) {
  std::mt19937_64 rng(3);
  for (const std::size_t m : {1, 2, 5, 15, 66, 93}) {  // blocks of 4 and 2, full and partial
    expect_sweep_matches_loop<3>(rng, m);
    expect_sweep_matches_loop<7>(rng, m);
    expect_sweep_matches_loop<9>(rng, m);
  }
}

TEST(NodePicard, IntegralTermSweepsAreTheLoopsBits) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const std::size_t D : {3, 4, 7}) {  // 3 and 7 in registers, 4 over memory
    for (const std::size_t nodes : {33, 65}) {
      const eulervop::detail::chebyshev_basis<double>& b = eulervop::detail::lobatto_basis(nodes);
      const std::size_t m = b.nodes.size();
      std::vector<double> Jn(m * D * D), rn(m * D), Y;
      for (double& x : Jn) x = 2 * u(rng);
      for (double& x : rn) x = u(rng);
      eulervop::detail::node_picard picard;
      ASSERT_TRUE(picard.integral_term_sweeps(b, Jn.data(), rn.data(), D, 0.7, Y));
      const std::vector<double> reference = u_sweeps_over_memory(b, Jn, rn, D, 0.7);
      ASSERT_EQ(Y.size(), reference.size());
      for (std::size_t q = 0; q < Y.size(); ++q) ASSERT_EQ(Y[q], reference[q]) << "D " << D << " nodes " << nodes << " at " << q;
    }
  }
}

// One segment's inputs: J (some entries zero), r, the weights and hl.
struct flow_input {
  std::vector<chebyshev_model> J, r;
  std::vector<double> weight;
  ball hl;
  double jh = 0;
};

flow_input random_input(std::mt19937_64& rng, std::size_t D, slong r_length, double j_size, double hl, int q_weight) {
  flow_input in;
  in.J.resize(D * D);
  for (std::size_t q = 0; q < D * D; ++q)
    if (rng() % 4 != 0) in.J[q] = random_model(rng, 1 + static_cast<slong>(rng() % 14), j_size, 0.4);
  for (std::size_t i = 0; i < D; ++i) in.r.push_back(random_model(rng, r_length, 1e-33, 0.9));
  in.weight.assign(D, 1.0);
  for (std::size_t i = 3; i < D; ++i) in.weight[i] = std::ldexp(1.0, -q_weight);
  arb_set_d(in.hl.get(), hl);
  in.jh = 2 * hl * j_size * static_cast<double>(D);
  return in;
}

void run(eulervop::detail::ball_linear_flow& flow, const flow_input& in) {
  flow.load_jacobian(in.J, in.weight);
  ASSERT_TRUE(flow.variational(in.hl, in.jh));
  ASSERT_TRUE(flow.integral_term(in.r, in.hl));
}

void expect_same_balls(const std::vector<ball>& a, const std::vector<ball>& b, const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t q = 0; q < a.size(); ++q) EXPECT_TRUE(arb_equal(a[q].get(), b[q].get())) << what << " entry " << q;
}

TEST(BallLinearFlow, ReusedFlowGivesAFreshOnesBits) {
  std::mt19937_64 rng(7);
  for (const std::size_t D : {3, 7}) {
    // The segments the reused flow sees first: longer and shorter residuals, a larger |J| h.
    const std::vector<flow_input> before = {random_input(rng, D, 120, 1.5, 2.0, 3), random_input(rng, D, 20, 0.3, 0.5, 0),
                                            random_input(rng, D, 84, 0.8, 1.0, 5)};
    const flow_input last = random_input(rng, D, 60, 0.6, 0.9, 2);
    eulervop::detail::ball_linear_flow reused(D, 200), fresh(D, 200);
    for (const flow_input& in : before) run(reused, in);
    run(reused, last);
    run(fresh, last);
    EXPECT_TRUE(mag_equal(reused.phi_residual(), fresh.phi_residual())) << "D " << D;
    EXPECT_TRUE(mag_equal(reused.u_residual(), fresh.u_residual())) << "D " << D;
    expect_same_balls(reused.Phi1(), fresh.Phi1(), "Phi(1)");
    expect_same_balls(reused.u1(), fresh.u1(), "u(1)");
    ASSERT_EQ(reused.max_length(), fresh.max_length());
    for (const double s : {-1.0, -0.3, 0.45}) {
      ball sb;
      arb_set_d(sb.get(), s);
      const eulervop::detail::chebyshev_values T(reused.max_length(), sb, 200);
      std::vector<ball> a, b;
      reused.Phi_at(T, a);
      fresh.Phi_at(T, b);
      expect_same_balls(a, b, "Phi(s)");
      reused.u_at(T, a);
      fresh.u_at(T, b);
      expect_same_balls(a, b, "u(s)");
    }
  }
}

}  // namespace
