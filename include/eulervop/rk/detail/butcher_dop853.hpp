// The 12-stage 8th-order Runge-Kutta method of DOP853 (Hairer & Wanner), as a Butcher tableau
// built in the scalar type T. Included by <eulervop/rk/tableaux.hpp>; not a public header.
//
// Source: E. Hairer, S. P. Norsett, G. Wanner, "Solving Ordinary Differential Equations I",
// 2nd ed., Springer 1993, Section II.10, and the coefficients of the Fortran code dop853.f
// (version of 2004, http://www.unige.ch/~hairer/software.html), which prints each coefficient
// as a decimal with about 30 significant digits.
//
// What is exact and what is not:
//   - The nodes c2..c11 and the rows 2-7 of A are exact: they lie in Q(sqrt 6) with small
//     denominators. We identified them with PSLQ (mpmath, 32 digits) from the dop853.f decimals
//     and every form below reproduces all ~30 printed digits (checked again in
//     tests/test_runge_kutta.cpp). Examples: c4 = (6 - sqrt6)/30, c5 = (6 + sqrt6)/30,
//     a51 = (462 + 107 sqrt6)/3000, a87 = 3072/13^5. They are built in T from integers and
//     sqrt(T(6)), so they are exact to the rounding of T.
//   - Rows 8-12 of A (except a87) and the weights b are not identifiable that way (they come
//     from a free parameter chosen numerically). They are parsed in T from the dop853.f decimal
//     strings, never from double literals. So they carry ~30 digits (~1e-30 relative): in quad
//     (eps 1.9e-34) the row sums of rows 8-12 and sum(b) hold to ~1e-30, and in MPFR the method
//     has a consistency defect of that size. An rk8 run therefore has an error floor of about
//     1e-30 * (span) * |f|, whatever the precision. The tests measure it.
#pragma once

#include <eulervop/core/scalar_traits.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <string>
#include <type_traits>

namespace eulervop::rk::detail {

// A decimal string parsed correctly rounded in T (strtod for double; the multiprecision
// string constructors otherwise).
template <scalar T>
T decimal(const char* text) {
  if constexpr (std::is_same_v<T, double>) {
    return std::strtod(text, nullptr);
  } else {
    return T(text);
  }
}

// The nodes c and the rows 2-7 of A: exact in Q(sqrt 6), built from integers and sqrt(T(6)).
template <class Tableau, scalar T>
void fill_dop853_exact(Tableau& tab) {
  using std::sqrt;
  const T s6 = sqrt(T(6));
  auto q = [](int num, int den) { return T(num) / T(den); };
  auto& a = tab.a;
  auto& c = tab.c;

  c[0] = T(0);
  c[1] = (T(12) - T(2) * s6) / T(135);
  c[2] = (T(6) - s6) / T(45);
  c[3] = (T(6) - s6) / T(30);
  c[4] = (T(6) + s6) / T(30);
  c[5] = q(1, 3);
  c[6] = q(1, 4);
  c[7] = q(4, 13);
  c[8] = q(127, 195);
  c[9] = q(3, 5);
  c[10] = q(6, 7);
  c[11] = T(1);

  a[1][0] = c[1];
  a[2][0] = (T(6) - s6) / T(180);
  a[2][1] = (T(6) - s6) / T(60);
  a[3][0] = (T(6) - s6) / T(120);
  a[3][2] = (T(6) - s6) / T(40);
  a[4][0] = (T(462) + T(107) * s6) / T(3000);
  a[4][2] = -(T(402) + T(197) * s6) / T(1000);
  a[4][3] = (T(168) + T(73) * s6) / T(375);
  a[5][0] = q(1, 27);
  a[5][3] = (T(16) + s6) / T(108);
  a[5][4] = (T(16) - s6) / T(108);
  a[6][0] = q(19, 512);
  a[6][3] = (T(118) + T(23) * s6) / T(1024);
  a[6][4] = (T(118) - T(23) * s6) / T(1024);
  a[6][5] = q(-9, 512);
}

// The rows 8-12 of A (a87 is exact) and the weights b: the decimals of dop853.f, parsed in T.
template <class Tableau, scalar T>
void fill_dop853_decimal(Tableau& tab) {
  auto q = [](int num, int den) { return T(num) / T(den); };
  auto& a = tab.a;
  auto& b = tab.b;
  const auto d = [](const char* text) { return decimal<T>(text); };

  a[7][0] = d("3.70920001185047927108779319836e-02");
  a[7][3] = d("1.70383925712239993810214054705e-01");
  a[7][4] = d("1.07262030446373284651809199168e-01");
  a[7][5] = d("-1.53194377486244017527936158236e-02");
  a[7][6] = q(3072, 371293);  // 3072 / 13^5

  a[8][0] = d("6.24110958716075717114429577812e-01");
  a[8][3] = d("-3.36089262944694129406857109825");
  a[8][4] = d("-8.68219346841726006818189891453e-01");
  a[8][5] = d("2.75920996994467083049415600797e+01");
  a[8][6] = d("2.01540675504778934086186788979e+01");
  a[8][7] = d("-4.34898841810699588477366255144e+01");

  a[9][0] = d("4.77662536438264365890433908527e-01");
  a[9][3] = d("-2.48811461997166764192642586468");
  a[9][4] = d("-5.90290826836842996371446475743e-01");
  a[9][5] = d("2.12300514481811942347288949897e+01");
  a[9][6] = d("1.52792336328824235832596922938e+01");
  a[9][7] = d("-3.32882109689848629194453265587e+01");
  a[9][8] = d("-2.03312017085086261358222928593e-02");

  a[10][0] = d("-9.3714243008598732571704021658e-01");
  a[10][3] = d("5.18637242884406370830023853209");
  a[10][4] = d("1.09143734899672957818500254654");
  a[10][5] = d("-8.14978701074692612513997267357");
  a[10][6] = d("-1.85200656599969598641566180701e+01");
  a[10][7] = d("2.27394870993505042818970056734e+01");
  a[10][8] = d("2.49360555267965238987089396762");
  a[10][9] = d("-3.0467644718982195003823669022");

  a[11][0] = d("2.27331014751653820792359768449");
  a[11][3] = d("-1.05344954667372501984066689879e+01");
  a[11][4] = d("-2.00087205822486249909675718444");
  a[11][5] = d("-1.79589318631187989172765950534e+01");
  a[11][6] = d("2.79488845294199600508499808837e+01");
  a[11][7] = d("-2.85899827713502369474065508674");
  a[11][8] = d("-8.87285693353062954433549289258");
  a[11][9] = d("1.23605671757943030647266201528e+01");
  a[11][10] = d("6.43392746015763530355970484046e-01");

  b[0] = d("5.42937341165687622380535766363e-02");
  b[5] = d("4.45031289275240888144113950566");
  b[6] = d("1.89151789931450038304281599044");
  b[7] = d("-5.8012039600105847814672114227");
  b[8] = d("3.1116436695781989440891606237e-01");
  b[9] = d("-1.52160949662516078556178806805e-01");
  b[10] = d("2.01365400804030348374776537501e-01");
  b[11] = d("4.47106157277725905176885569043e-02");
}

template <class Tableau, scalar T>
void fill_dop853(Tableau& tab) {
  fill_dop853_exact<Tableau, T>(tab);
  fill_dop853_decimal<Tableau, T>(tab);
}

}  // namespace eulervop::rk::detail
