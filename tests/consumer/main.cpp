// The consumer of the installed package: a torque-free quad reference (G = 0, Omega(0) =
// (c1, 0, c2), c1 = 1/2, c2 = 1) against the exact solution Omega(tau) = (c1 cn u, c1 sn u,
// c2 dn u), u = c2 tau, k = c1/c2 (paper Eq. 12), computed here with Boost.Math jacobi_elliptic
// in quad. Exit 0 if they agree at tau = 1 to 1e-28, 1 otherwise.
#include <eulervop/oracle.hpp>

#include <boost/math/special_functions/jacobi_elliptic.hpp>

#include <cstdio>

int main() {
  using eulervop::quad;
  const quad c1 = quad(1) / 2, c2 = 1;
  const auto problem = eulervop::oracle::problem<quad>({quad(0), quad(0), quad(0)}, {c1, quad(0), c2});
  const eulervop::oracle::reference<quad> ref(problem, quad(2));

  const quad tau = 1;
  const eulervop::vec3<quad> Om = ref(tau);
  quad cn, dn;
  const quad sn = boost::math::jacobi_elliptic(c1 / c2, c2 * tau, &cn, &dn);
  const eulervop::vec3<quad> exact = {c1 * cn, c1 * sn, c2 * dn};
  const double err = static_cast<double>(eulervop::eq20_error(exact, Om));

  // The Eq. 20 error of a double state (the exact one rounded): about double rounding.
  const eulervop::vec3<double> rounded = {static_cast<double>(exact[0]), static_cast<double>(exact[1]),
                                          static_cast<double>(exact[2])};
  const double err_double = ref.error(tau, rounded);

  std::printf("Omega(1) = (%s, %s, %s)\nEq. 20 error vs jacobi_elliptic: %.3e\ndouble state error: %.3e\n",
              eulervop::to_text(Om[0]).c_str(), eulervop::to_text(Om[1]).c_str(), eulervop::to_text(Om[2]).c_str(), err,
              err_double);
  const bool ok = err < 1e-28 && err_double < 1e-15 && err_double > 0;
  std::printf("%s\n", ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}
