// The radii of a row on the general path of --certify (docs/certified.md, "What is proven"),
// from what the certificate proves at the row's tau (ball_certifier.hpp: ball_row): for a group
// of components (the state, omega in rad/s, q), an upper bound of |y_group - printed|_2.
//
// The row's time may stand for an exact time a rounding away from the binary tau the certificate
// worked at (a physical row's t, whose exact tau is t dtau/dt): each component then moves by at
// most that distance times the bound of |y'| on the tube, and y stays in the tube while the move
// is below the tube's reach. A group may be a linear image of the state, component by component
// (omega = P^T (sqrt(A) Omega), Eq. 2).
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/ball_certifier.hpp>
#include <eulervop/model/principal_axes.hpp>

#include <arb.h>

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace eulervop {

// The map of a group: printed component axes.axis(i) is sign(i) scale_i y_(first + i); none: the
// identity.
struct group_map {
  axis_permutation axes;
  std::array<ball, 3> scale;
};

// [0, an upper bound of |image of y - printed|_2] over the `count` components from `first`, the
// printed decimals `printed`, with y moved by `shift` (a ball holding the distance between the
// row's exact time and its binary tau; zero when they are the same number).
inline ball group_radius(const ball_row& row, std::size_t first, std::size_t count, const std::vector<std::string>& printed,
                         const ball& shift, const std::optional<group_map>& map, slong prec) {
  // y moves by at most |shift| |y_i'| per component while it stays in the tube, which it does while
  // the whole move (its 2-norm) is below the tube's reach.
  mag_value dt, m, sum, whole;
  arb_get_mag(dt.m, shift.get());
  std::vector<mag_value> move(row.y.size());
  for (std::size_t i = 0; i < row.y.size(); ++i) {
    mag_mul(move[i].m, dt.m, row.rate[i].m);
    mag_addmul(whole.m, move[i].m, move[i].m);
  }
  mag_sqrt(whole.m, whole.m);
  if (!mag_is_zero(dt.m) && !(mag_cmp(whole.m, row.reach.m) < 0))
    throw std::domain_error("a row's time lies too far from its binary tau");
  ball y, p;
  for (std::size_t i = 0; i < count; ++i) {
    y = row.y[first + i];
    arb_add_error_mag(y.get(), move[first + i].m);
    std::size_t slot = i;
    if (map) {
      arb_mul(y.get(), y.get(), map->scale[i].get(), prec);
      if (map->axes.sign(static_cast<int>(i)) < 0) arb_neg(y.get(), y.get());
      slot = static_cast<std::size_t>(map->axes.axis(static_cast<int>(i)));
    }
    p = decimal_ball(printed[slot], prec);
    arb_sub(y.get(), y.get(), p.get(), prec);
    arb_get_mag(m.m, y.get());
    mag_addmul(sum.m, m.m, m.m);
  }
  mag_sqrt(sum.m, sum.m);
  ball out;
  arf_set_mag(arb_midref(out.get()), sum.m);
  to_zero_hull(out);
  return out;
}

}  // namespace eulervop
