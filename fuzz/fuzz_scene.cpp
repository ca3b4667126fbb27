// libFuzzer target for the scene parser (docs/fuzzing.md). Build and run: tools/fuzz_scene.sh.
//
// Contract under test: parse_scene() either returns a scene or throws input_error; nothing
// else may escape, and no sanitizer (ASan, UBSan) may fire. Scenes that parse are then turned
// into numbers by to_problem / tau_end_of / sample_times_of for double and quad, which convert
// every decimal again in the target type (scene_problem.hpp); those must not throw either.
// Any other exception reaches std::terminate, which libFuzzer reports as a crash with the input.
#include <eulervop/core/scalar.hpp>
#include <eulervop/scene/scene.hpp>
#include <eulervop/scene/scene_problem.hpp>

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace {

// sample_times_of allocates one value per sample (the parser allows up to 10^7); above this the
// fuzzer would spend its time in allocation and softfloat loops rather than in the parser, and
// the code path is the same for any count.
constexpr std::int64_t max_samples_exercised = 4096;

template <class T>
void exercise(const eulervop::scene::scene& s) {
  using namespace eulervop::scene;
  const auto p = to_problem<T>(s);
  const T end = tau_end_of<T>(s);
  if (!s.samples || *s.samples <= max_samples_exercised) {
    const auto times = sample_times_of<T>(s);
    (void)times;
  }
  if (s.step && s.step->value) (void)s.step->value->template to_scalar<T>();
  if (s.tolerance) (void)s.tolerance->template to_scalar<T>();
  (void)p;
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
