// libFuzzer target for the scene parser (docs/fuzzing.md). Build and run: tools/fuzz_scene.sh.
//
// Contract under test: parse_scene() either returns a scene or throws input_error; nothing
// else may escape, and no sanitizer (ASan, UBSan) may fire. Scenes that parse are then turned
// into numbers by with_problem / tau_end_of / sample_times_of for double and quad, which convert
// every decimal again in the target type (scene_problem.hpp); those must not throw either. A
// torque of formulas is evaluated, with its Jacobian, at the start, on both sides of every
// breakpoint and at the end of the span: a value that is not finite there is the
// numerical_failure the program reports with exit code 3, and nothing else may escape.
// Any other exception reaches std::terminate, which libFuzzer reports as a crash with the input.
#include <eulervop/core/scalar.hpp>
#include <eulervop/scene/scene.hpp>
#include <eulervop/scene/scene_problem.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace {

// sample_times_of allocates one value per sample (the parser allows up to 10^7); above this the
// fuzzer would spend its time in allocation and softfloat loops rather than in the parser, and
// the code path is the same for any count.
constexpr std::int64_t max_samples_exercised = 4096;

// The torque at the times an integrator would use: the span's ends and each breakpoint, pinned to
// either side.
template <class P>
void evaluate_torque(const P& p, const typename P::value_type& end) {
  using T = typename P::value_type;
  using Torque = typename P::torque_type;
  if constexpr (!eulervop::is_constant_torque_v<Torque>) {
    std::vector<T> times = {p.tau0, end};
    for (const T& b : p.torque.breakpoints()) times.push_back(b);
    std::array<eulervop::vec3<T>, 3> J{};
    try {
      for (const T& t : times)
        for (std::size_t side = 0; side < 2; ++side) {
          const std::size_t i = p.torque.interval_at(t);
          p.torque.pin(side == 0 && i > 0 ? i - 1 : i);
          (void)p.torque.value(t, p.Omega0);
          if constexpr (eulervop::torque_traits<Torque>::depends_on_state) p.torque.add_jacobian(t, p.Omega0, J);
        }
    } catch (const eulervop::numerical_failure&) {
      // a formula not finite there: exit code 3 in the program
    }
    p.torque.unpin();
  }
}

template <class T>
void exercise(const eulervop::scene::scene& s) {
  using namespace eulervop::scene;
  const T end = tau_end_of<T>(s);
  with_problem<T>(s, [&](const auto& p) { evaluate_torque(p, end); });
  if (!s.samples || *s.samples <= max_samples_exercised) {
    const auto times = sample_times_of<T>(s);
    (void)times;
  }
  if (s.step && s.step->value) (void)s.step->value->template to_scalar<T>();
  if (s.tolerance) (void)s.tolerance->template to_scalar<T>();
  (void)end;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  eulervop::scene::scene s;
  try {
    s = eulervop::scene::parse_scene(text, "fuzz.toml");
  } catch (const eulervop::scene::input_error&) {
    return 0;  // rejected with the one exception type for bad input: fine
  }
  exercise<double>(s);
  exercise<eulervop::quad>(s);
  return 0;
}
