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
// Phi and u is BallLinearFlow.PhiAndUHoldTheExactSolutions in test_ball_linear_flow.cpp.)
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

// The iteration of Phi as node_picard.hpp ran it before its flat layout (a copy, the reference
// here): every entry of Y over all D^2 columns, each product through the vectors `entries` and
// `through`, the sums of the loop over memory.
std::vector<double> phi_sweeps_over_memory(const eulervop::detail::chebyshev_basis<double>& b, const std::vector<double>& Jn,
                                           std::size_t D, double hl, const std::vector<std::size_t>& entries,
                                           const std::vector<std::vector<std::size_t>>& through) {
  const std::size_t m = b.nodes.size(), DD = D * D;
  std::vector<double> Y(m * DD, 0.0), F(m * DD, 0.0), acc(DD);
  for (std::size_t l = 0; l < m; ++l)
    for (std::size_t i = 0; i < D; ++i) Y[l * DD + i * D + i] = 1;
  const auto product_at = [&](std::size_t l) {
    for (const std::size_t q : entries) {
      double a = 0;
      for (const std::size_t k : through[q]) a += Jn[l * DD + q / D * D + k] * Y[l * DD + k * D + q % D];
      F[l * DD + q] = a;
    }
  };
  for (std::size_t l = 0; l < m; ++l) product_at(l);
  for (int sweep = 0; sweep < 400; ++sweep) {
    double change = 0, size = 0;
    for (std::size_t l = 0; l < m; ++l) {
      std::fill(acc.begin(), acc.end(), 0.0);
      for (std::size_t k = 0; k < m; ++k)
        for (std::size_t q = 0; q < DD; ++q) acc[q] += b.integral[l * m + k] * F[k * DD + q];
      for (const std::size_t q : entries) {
        const double next = (q % (D + 1) == 0 ? 1.0 : 0.0) + hl * acc[q];
        change = std::max(change, std::abs(next - Y[l * DD + q]));
        size = std::max(size, std::abs(next));
        Y[l * DD + q] = next;
      }
      product_at(l);
    }
    if (change <= 1e-13 * size) break;
  }
  return Y;
}

// u by variation of constants as node_picard.hpp computed it before its transposed sums (a copy,
// the reference here): g = Phi^-1 hl J r at each node, w = S g by the loop over memory, u = Phi w.
std::vector<double> u_by_variation_over_memory(const eulervop::detail::chebyshev_basis<double>& b,
                                               const std::vector<double>& Jn, const std::vector<double>& rn,
                                               const std::vector<double>& Pn, std::size_t D, double hl) {
  const std::size_t m = b.nodes.size(), DD = D * D;
  std::vector<double> g(m * D), lu(DD), Y(m * D), acc;
  for (std::size_t l = 0; l < m; ++l) {
    for (std::size_t i = 0; i < D; ++i) {
      double a = 0;
      for (std::size_t k = 0; k < D; ++k) a += Jn[l * DD + i * D + k] * rn[l * D + k];
      g[l * D + i] = hl * a;
    }
    std::copy(Pn.begin() + static_cast<std::ptrdiff_t>(l * DD), Pn.begin() + static_cast<std::ptrdiff_t>((l + 1) * DD), lu.begin());
    EXPECT_TRUE(eulervop::detail::solve_in_place<0>(lu.data(), g.data() + l * D, D));
  }
  eulervop::detail::gauss_seidel_sweep<0>(b.integral.data(), g.data(), m, D, acc, [&](std::size_t l, const double* w) {
    for (std::size_t i = 0; i < D; ++i) {
      double u = 0;
      for (std::size_t k = 0; k < D; ++k) u += Pn[l * DD + i * D + k] * w[k];
      Y[l * D + i] = u;
    }
  });
  return Y;
}

// The grid's coefficients as node_picard.hpp computed them before its transposed sums (a copy, the
// reference here): c_k = sum_l coeffs_kl values_l, then trunc(ldexp(c, -e)).
slong grid_coefficients_over_memory(const eulervop::detail::chebyshev_basis<double>& b, const std::vector<double>& values,
                                    std::size_t count, std::vector<eulervop::detail::integer_poly>& out, slong bits) {
  const std::size_t m = b.nodes.size();
  std::vector<double> c(count * m);
  double big = 0;
  for (std::size_t q = 0; q < count; ++q)
    for (std::size_t k = 0; k < m; ++k) {
      double acc = 0;
      for (std::size_t l = 0; l < m; ++l) acc += b.coeffs[k * m + l] * values[l * count + q];
      c[q * m + k] = acc;
      big = std::max(big, std::abs(acc));
    }
  const slong e = big > 0 ? static_cast<slong>(std::ilogb(big)) + 1 - bits : 0;
  out.resize(count);
  for (std::size_t q = 0; q < count; ++q) {
    fmpz_poly_zero(out[q].p);
    for (std::size_t k = 0; k < m; ++k) {
      fmpz_t x;
      fmpz_init(x);
      fmpz_set_d(x, std::trunc(std::ldexp(c[q * m + k], static_cast<int>(-e))));
      fmpz_poly_set_coeff_fmpz(out[q].p, static_cast<slong>(k), x);
      fmpz_clear(x);
    }
  }
  return e;
}

// One sweep of gauss_seidel_sweep<N> (W = 0) or chunked_sweep<W> (rows of Stride entries, padded
// with zeros) against gauss_seidel_sweep<0>, with a finish that feeds each node's sums back into
// F's row (as the iterations do), so that the order of the updates is tested along with the order
// of the sums.
template <std::size_t N, std::size_t Stride = N, std::size_t W = 0>
void expect_sweep_matches_loop(std::mt19937_64& rng, std::size_t m) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> S(m * m), F0(m * N);
  for (double& x : S) x = u(rng);
  for (double& x : F0) x = std::ldexp(u(rng), static_cast<int>(rng() % 40) - 20);  // sums that round
  const std::size_t stride[2] = {Stride, N};
  std::vector<double> F[2] = {std::vector<double>(m * Stride, 0.0), F0};
  for (std::size_t l = 0; l < m; ++l) std::copy(F0.begin() + l * N, F0.begin() + (l + 1) * N, F[0].begin() + l * Stride);
  std::vector<double> out[2] = {std::vector<double>(m * N), std::vector<double>(m * N)}, acc;
  const auto finish = [&](int which) {
    return [&, which](std::size_t l, const double* a) {
      for (std::size_t i = 0; i < N; ++i) {
        out[which][l * N + i] = a[i];
        F[which][l * stride[which] + i] = 0.3 * a[i] + F[which][l * stride[which] + (i + 1) % N];
      }
    };
  };
  if constexpr (W == 0)
    eulervop::detail::gauss_seidel_sweep<N>(S.data(), F[0].data(), m, N, acc, finish(0));
  else
    eulervop::detail::chunked_sweep<W>(S.data(), F[0].data(), m, Stride, acc, finish(0));
  eulervop::detail::gauss_seidel_sweep<0>(S.data(), F[1].data(), m, N, acc, finish(1));
  for (std::size_t q = 0; q < m * N; ++q)
    ASSERT_EQ(out[0][q], out[1][q]) << "N " << N << " stride " << Stride << " m " << m << " at " << q;
}

TEST(NodePicard, RegisterSweepsAreTheLoopsBits) {
  std::mt19937_64 rng(3);
  for (const std::size_t m : {1, 2, 5, 15, 66, 93}) {  // blocks of 4 and 2, full and partial
    expect_sweep_matches_loop<3>(rng, m);
    expect_sweep_matches_loop<7>(rng, m);
    expect_sweep_matches_loop<9>(rng, m);
    expect_sweep_matches_loop<9, 10, 10>(rng, m);  // the 3 x 3 variational kernel's
    expect_sweep_matches_loop<49, 56, 8>(rng, m);   // any other count's
    expect_sweep_matches_loop<5, 8, 8>(rng, m);
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

TEST(NodePicard, IntegralTermByVariationIsTheLoopsBits) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const std::size_t D : {3, 4, 7}) {  // 3 and 7 unrolled, 4 not
    for (const std::size_t nodes : {15, 66}) {
      const eulervop::detail::chebyshev_basis<double>& b = eulervop::detail::lobatto_basis(nodes);
      const std::size_t m = b.nodes.size();
      std::vector<double> Jn(m * D * D), rn(m * D), Pn(m * D * D), Y;
      for (double& x : Jn) x = 2 * u(rng);
      for (double& x : rn) x = u(rng);
      for (std::size_t q = 0; q < Pn.size(); ++q) Pn[q] = (q % (D * D) % (D + 1) == 0 ? 1.0 : 0.0) + 0.3 * u(rng);
      eulervop::detail::node_picard picard;
      ASSERT_TRUE(picard.integral_term_by_variation(b, Jn.data(), rn.data(), Pn.data(), D, 0.7, Y));
      const std::vector<double> reference = u_by_variation_over_memory(b, Jn, rn, Pn, D, 0.7);
      ASSERT_EQ(Y.size(), reference.size());
      for (std::size_t q = 0; q < Y.size(); ++q) ASSERT_EQ(Y[q], reference[q]) << "D " << D << " nodes " << nodes << " at " << q;
    }
  }
}

// Values of order one, and far below and above it (where 2^-e is not a double, ldexp's path).
TEST(NodePicard, GridCoefficientsAreTheLoopsIntegers) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const int scale : {0, -1000, -300, 900})
    for (const std::size_t count : {3, 9, 49})
      for (const std::size_t nodes : {15, 66}) {
        const eulervop::detail::chebyshev_basis<double>& b = eulervop::detail::lobatto_basis(nodes);
        std::vector<double> values(b.nodes.size() * count);
        for (double& x : values) x = std::ldexp(u(rng), scale);
        eulervop::detail::node_picard picard;
        std::vector<eulervop::detail::integer_poly> got, expected;
        for (const slong bits : {40, 56}) {
          const slong e = picard.grid_coefficients(b, values.data(), count, count, got, bits);
          ASSERT_EQ(e, grid_coefficients_over_memory(b, values, count, expected, bits));
          for (std::size_t q = 0; q < count; ++q)
            ASSERT_TRUE(fmpz_poly_equal(got[q].p, expected[q].p)) << "scale " << scale << " count " << count << " q " << q;
        }
      }
}

// The doubles of an integer polynomial on a grid against ldexp (exponents where 2^e is a double and
// where not, values that round and subnormal ones), and a series at the nodes against the loop
// over memory (T_k(s_l) v_l += c_k, from k = 0 up).
TEST(NodePicard, ScaledDoublesAndSeriesAreTheLoopsBits) {
  std::mt19937_64 rng(19);
  eulervop::detail::integer_poly p;
  for (slong k = 0; k < 20; ++k) fmpz_poly_set_coeff_si(p.p, k, static_cast<slong>(rng() >> 4) - (1LL << 59));
  std::vector<double> out;
  for (const slong e : {-1130, -1100, -1080, -1022, -400, 0, 17, 900, 1023, 1040}) {
    eulervop::detail::scaled_doubles(p.p, e, out);
    for (slong k = 0; k < p.p->length; ++k)
      ASSERT_EQ(out[k], std::ldexp(fmpz_get_d(p.p->coeffs + k), static_cast<int>(e))) << "e " << e << " k " << k;
  }
  std::uniform_real_distribution<double> u(-1, 1);
  for (const std::size_t nodes : {15, 17, 66}) {
    const eulervop::detail::chebyshev_basis<double>& b = eulervop::detail::lobatto_basis(nodes);
    const std::size_t m = b.nodes.size(), n = 23;
    std::vector<double> c(n), got(2 * m), T(n * m);
    for (double& x : c) x = u(rng);
    for (std::size_t l = 0; l < m; ++l) T[l] = 1, T[m + l] = b.nodes[l];
    for (std::size_t k = 2; k < n; ++k)
      for (std::size_t l = 0; l < m; ++l) T[k * m + l] = 2 * b.nodes[l] * T[(k - 1) * m + l] - T[(k - 2) * m + l];
    eulervop::detail::node_picard picard;
    picard.chebyshev_at_nodes(b, n);
    picard.series_at_nodes(c.data(), n, m, got.data(), 2);
    for (std::size_t l = 0; l < m; ++l) {
      double v = 0;
      for (std::size_t k = 0; k < n; ++k) v += c[k] * T[k * m + l];
      ASSERT_EQ(got[2 * l], v) << "nodes " << nodes << " at " << l;
    }
  }
}

// J's pattern (nonzero where `pattern` says) and Phi's live entries and their products' terms as
// ball_linear_flow.hpp's find_live_entries() makes them.
TEST(NodePicard, VariationalSweepsAreTheLoopsBits) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  // 3 x 3 with 9 live entries (J's pattern: Euler's zero diagonal, full, another) and fewer; more.
  const std::vector<std::size_t> dimensions = {3, 3, 3, 3, 4, 7, 7};
  for (std::size_t c = 0; c < dimensions.size(); ++c) {
    const std::size_t D = dimensions[c];
    std::vector<char> nonzero(D * D);
    for (std::size_t q = 0; q < D * D; ++q) nonzero[q] = D == 3 ? c == 1 || q % 4 != 0 : rng() % 5 != 0;
    if (c == 2) nonzero[1] = 0;                            // still all live, the products padded
    if (c == 3) std::fill(nonzero.begin(), nonzero.end(), 0), nonzero[1] = 1;  // fewer live entries
    std::vector<char> live(D * D, 0);
    for (std::size_t i = 0; i < D; ++i) live[i * D + i] = 1;
    for (bool grew = true; grew;) {
      grew = false;
      for (std::size_t q = 0; q < D * D; ++q)
        for (std::size_t k = 0; k < D && !live[q]; ++k)
          if (nonzero[q / D * D + k] && live[k * D + q % D]) live[q] = grew = true;
    }
    std::vector<std::size_t> entries;
    std::vector<std::vector<std::size_t>> through(D * D);
    for (std::size_t q = 0; q < D * D; ++q) {
      if (!live[q]) continue;
      entries.push_back(q);
      for (std::size_t k = 0; k < D; ++k)
        if (nonzero[q / D * D + k] && live[k * D + q % D]) through[q].push_back(k);
    }
    if (c < 3) ASSERT_EQ(entries.size(), 9u);
    if (c == 3) ASSERT_LT(entries.size(), 9u);
    for (const std::size_t nodes : {15, 33}) {
      const eulervop::detail::chebyshev_basis<double>& b = eulervop::detail::lobatto_basis(nodes);
      std::vector<double> Jn(b.nodes.size() * D * D, 0.0), Y;
      for (std::size_t q = 0; q < Jn.size(); ++q)
        if (nonzero[q % (D * D)]) Jn[q] = 1.5 * u(rng);
      eulervop::detail::node_picard picard;
      ASSERT_TRUE(picard.variational_sweeps(b, Jn.data(), D, 0.6, entries, through, Y));
      const std::vector<double> reference = phi_sweeps_over_memory(b, Jn, D, 0.6, entries, through);
      ASSERT_EQ(Y.size(), reference.size());
      for (std::size_t q = 0; q < Y.size(); ++q)
        ASSERT_EQ(Y[q], reference[q]) << "D " << D << " live " << entries.size() << " nodes " << nodes << " at " << q;
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
    eulervop::detail::ball_linear_flow reused(D), fresh(D);
    for (const flow_input& in : before) run(reused, in);
    run(reused, last);
    run(fresh, last);
    EXPECT_TRUE(mag_equal(reused.phi_residual(), fresh.phi_residual())) << "D " << D;
    EXPECT_TRUE(mag_equal(reused.u_residual(), fresh.u_residual())) << "D " << D;
    expect_same_balls(reused.Phi1(), fresh.Phi1(), "Phi(1)");
    expect_same_balls(reused.u1(), fresh.u1(), "u(1)");
    ASSERT_EQ(reused.phi_length(), fresh.phi_length());
    for (const double s : {-1.0, -0.3, 0.45}) {
      ball sb;
      arb_set_d(sb.get(), s);
      const eulervop::detail::chebyshev_values T(reused.phi_length(), sb, 200);
      std::vector<ball> a, b;
      reused.Phi_at(T, a, 200);
      fresh.Phi_at(T, b, 200);
      expect_same_balls(a, b, "Phi(s)");
    }
    // u_num's models, coefficient by coefficient.
    for (std::size_t i = 0; i < D; ++i) {
      const eulervop::detail::chebyshev_model &a = reused.u()[i], &b = fresh.u()[i];
      ASSERT_EQ(a.length(), b.length()) << "u_" << i;
      for (slong k = 0; k < a.length(); ++k) EXPECT_TRUE(arb_equal(a.coeff(k), b.coeff(k))) << "u_" << i << " T_" << k;
      EXPECT_TRUE(mag_equal(a.remainder(), b.remainder())) << "u_" << i;
    }
  }
}

}  // namespace
