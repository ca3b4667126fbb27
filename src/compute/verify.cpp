#include "compute/verify.hpp"

#include "compute/reference_compute.hpp"
#include "compute/with_scalar.hpp"

#include <eulervop/model/error_measure.hpp>
#include <eulervop/model/physical_scaling.hpp>

#include <fmt/format.h>

#include <optional>
#include <stdexcept>
#include <type_traits>

#include <mpfr.h>

namespace eulervop::app {

namespace {

// A value of the narrower type, exactly, in the wider one (created at the current precision).
template <scalar Hi, scalar Lo>
Hi widen(const Lo& x) {
  if constexpr (std::is_same_v<Hi, mpfr_real> && std::is_same_v<Lo, mpfr_real>) {
    Hi r;  // thread default precision, which is the wider one inside the verify scope
    mpfr_set(r.backend().data(), x.backend().data(), MPFR_RNDN);
    return r;
  } else {
    return Hi(x);  // double -> quad, quad -> mpfr: exact
  }
}

// "1.23e-30": three significant digits, in the wide type (an MPFR error can underflow double).
template <scalar T>
std::string three_digits(const T& x) {
  if constexpr (std::is_same_v<T, double>)
    return fmt::format("{:.2e}", x);
  else
    return x.str(2, std::ios_base::scientific);
}

template <scalar Hi, scalar Lo>
vec3<Hi> widen3(const vec3<Lo>& v) {
  return {widen<Hi>(v[0]), widen<Hi>(v[1]), widen<Hi>(v[2])};
}

// `omega`, if given, holds the omega the narrow rows print (a physical scene in the normalized
// form): the wide Omega is mapped by Eq. 2 in the wide type, from the scene's decimals, and the
// largest difference in rad/s is kept too.
template <scalar Hi, scalar Lo>
verify_result verify_in(const scene& s, const Lo& tau_end, const std::vector<Lo>& taus,
                        const std::vector<vec3<Lo>>& Omega, const eulervop::precision& wide,
                        const std::vector<quaternion<Lo>>* attitude, const std::vector<vec3<Lo>>* omega) {
  std::vector<Hi> wide_taus;
  wide_taus.reserve(taus.size());
  for (const Lo& t : taus) wide_taus.push_back(widen<Hi>(t));
  std::optional<physical_scaling<Hi>> scale;
  if (omega) scale.emplace(scaling_of<Hi>(s));
  // Compared as they come: the wide samples are not kept.
  Hi worst = 0, worst_angle = 0, worst_omega = 0;
  const auto compare = [&](std::size_t i, const vec3<Hi>& ref) {
    const Hi err = eq20_error(ref, widen3<Hi>(Omega[i]));
    if (err > worst) worst = err;
    if (!scale) return;
    const Hi err_omega = eq20_error(scale->omega_of_Omega(ref), widen3<Hi>((*omega)[i]));
    if (err_omega > worst_omega) worst_omega = err_omega;
  };
  const reference_run run =
      attitude ? integrate_scene_attitude<Hi>(s, widen<Hi>(tau_end), wide_taus, picard_settings{}, "verify",
                                              [&](std::size_t i, const vec3<Hi>& ref, const quaternion<Hi>& q) {
                                                compare(i, ref);
                                                const quaternion<Lo>& n = (*attitude)[i];
                                                const quaternion<Hi> narrow{widen<Hi>(n.w), widen<Hi>(n.x),
                                                                            widen<Hi>(n.y), widen<Hi>(n.z)};
                                                const Hi angle = rotation_angle(q, narrow);
                                                if (angle > worst_angle) worst_angle = angle;
                                              })
               : with_problem<Hi>(s, [&](const auto& problem) {
                   return integrate_streaming<Hi>(problem, widen<Hi>(tau_end), wide_taus, picard_settings{}, "verify",
                                                  compare);
                 });
  verify_result out{decimal{three_digits(worst), static_cast<double>(worst)}, std::nullopt, std::nullopt, wide,
                    method_text(picard_settings{}, run.stats), run.wall_seconds};
  if (scale) out.max_error_omega = decimal{three_digits(worst_omega), static_cast<double>(worst_omega)};
  if (attitude) out.max_attitude_error = decimal{three_digits(worst_angle), static_cast<double>(worst_angle)};
  return out;
}

}  // namespace

// One precision up: double -> quad -> mpfr:(113+64) ; mpfr:B -> mpfr:(B+64). `narrow` is the
// precision of Lo (its bits matter for MPFR).
template <scalar Lo>
verify_result verify(const scene& s, const Lo& tau_end, const std::vector<Lo>& taus,
                     const std::vector<vec3<Lo>>& Omega, const eulervop::precision& narrow,
                     const std::vector<quaternion<Lo>>* attitude) {
  constexpr unsigned extra_bits = 64;
  const eulervop::precision wide =
      std::is_same_v<Lo, double>
          ? eulervop::precision::binary128()
          : eulervop::precision::mpfr((std::is_same_v<Lo, quad> ? 113u : narrow.bits) + extra_bits);
  // The omega a physical scene's rows print, mapped here in the narrow precision as the rows
  // were (the wide scope below would map an MPFR Omega at the wide precision).
  std::vector<vec3<Lo>> omega;
  const bool direct = uses_direct_form(s);
  if (s.is_physical() && !direct) {
    const physical_scaling<Lo> scale = scaling_of<Lo>(s);
    omega.reserve(Omega.size());
    for (const vec3<Lo>& y : Omega) omega.push_back(scale.omega_of_Omega(y));
  }
  verify_result out = with_scalar(wide, [&](auto zero) -> verify_result {
    using Hi = decltype(zero);
    if constexpr (std::is_same_v<Hi, double> || (std::is_same_v<Hi, quad> && !std::is_same_v<Lo, double>))
      throw std::logic_error("verify: the precision is not wider");
    else
      return verify_in<Hi>(s, tau_end, taus, Omega, wide, attitude, s.is_physical() && !direct ? &omega : nullptr);
  });
  if (s.is_physical() && direct) out.max_error_omega = out.max_error;  // the state is omega
  return out;
}

template verify_result verify<double>(const scene&, const double&, const std::vector<double>&,
                                     const std::vector<vec3<double>>&, const eulervop::precision&,
                                     const std::vector<quaternion<double>>*);
template verify_result verify<quad>(const scene&, const quad&, const std::vector<quad>&, const std::vector<vec3<quad>>&,
                                   const eulervop::precision&, const std::vector<quaternion<quad>>*);
template verify_result verify<mpfr_real>(const scene&, const mpfr_real&, const std::vector<mpfr_real>&,
                                        const std::vector<vec3<mpfr_real>>&, const eulervop::precision&,
                                        const std::vector<quaternion<mpfr_real>>*);

}  // namespace eulervop::app
