// Scenes: the shipped and embedded paper scene, exact decimals in quad and MPFR, the physical
// conversion (Eqs. 2-4, 8-9 against Eq. 7), sample times, and bad scenes (format:
// docs/scenes.md).
#include "type_test_names.hpp"

#include <eulervop/reference/integrate.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/integrals.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/scene/decimal.hpp>
#include <eulervop/scene/input_error.hpp>
#include <eulervop/scene/scene.hpp>
#include <eulervop/scene/scene_problem.hpp>

#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

namespace {

using eulervop::mpfr_real;
using eulervop::quad;
using eulervop::vec3;
using namespace eulervop::scene;

const std::string source_dir = EULERVOP_SOURCE_DIR;

scene parse(const std::string& text) { return parse_scene(text, "test.toml"); }

// ---- the paper scene -------------------------------------------------------------------------

TEST(PaperScene, ShippedFileMatchesThePaper) {
  const scene s = load_scene_file(source_dir + "/data/scenes/paper-fig1.toml");
  EXPECT_EQ(s.name, "paper-fig1");
  EXPECT_FALSE(s.is_physical());
  // Section 3: G = (1,1,1), c1 = 0.5, c2 = 1, u = 0, so Omega(0) = (0.5, 0, 1) exactly.
  const auto p = to_problem<quad>(s);
  EXPECT_EQ(p.torque.G, (vec3<quad>{1, 1, 1}));
  EXPECT_EQ(p.Omega0, (vec3<quad>{quad("0.5"), 0, 1}));
  EXPECT_EQ(p.tau0, 0);
  EXPECT_EQ(tau_end_of<quad>(s), 136);
  ASSERT_TRUE(s.samples.has_value());
  EXPECT_EQ(*s.samples, 2000);
  ASSERT_TRUE(s.step && s.step->K_divisor);
  EXPECT_EQ(*s.step->K_divisor, 200);
  EXPECT_EQ(s.methods, (std::vector<std::string>{"rk4", "rkf45"}));
  EXPECT_EQ(s.reference_precision.name(), "quad");
}

TEST(PaperScene, EmbeddedDefaultEqualsShippedFile) {
  const scene file = load_scene_file(source_dir + "/data/scenes/paper-fig1.toml");
  const scene embedded = load_default_scene();
  EXPECT_EQ(embedded.source_text, file.source_text);  // byte for byte
  EXPECT_EQ(embedded.name, file.name);
  EXPECT_EQ(embedded.description, file.description);
  EXPECT_EQ(to_problem<quad>(embedded).torque.G, to_problem<quad>(file).torque.G);
  EXPECT_EQ(to_problem<quad>(embedded).Omega0, to_problem<quad>(file).Omega0);
  EXPECT_EQ(embedded.span_end.text, file.span_end.text);
  EXPECT_EQ(embedded.samples, file.samples);
  EXPECT_EQ(embedded.methods, file.methods);
  EXPECT_EQ(embedded.reference_precision.name(), file.reference_precision.name());
  EXPECT_NE(embedded.origin.find("embedded"), std::string::npos);
}

TEST(ShippedScenes, AllParse) {
  for (const char* name : {"paper-fig1", "torque-free-k0.5", "spacecraft-physical"}) {
    SCOPED_TRACE(name);
    const scene s = load_scene_file(source_dir + "/data/scenes/" + name + ".toml");
    EXPECT_EQ(s.name, name);
    EXPECT_FALSE(s.description.empty());
  }
  const scene sc = load_scene_file(source_dir + "/data/scenes/spacecraft-physical.toml");
  EXPECT_TRUE(sc.is_physical());
  EXPECT_EQ(*sc.samples, 361);
}

// ---- exact decimals --------------------------------------------------------------------------

const char* const decimal_scene = R"(name = "decimals"
[torque]
G = [1_000.5, +2, -3e-1]
[initial]
Omega = [0.1, 0.10000000000000000000000000000001, 1]
[span]
tau_end = 0.3
times = [0.1, 0.2]
)";

// 0.1 must be 0.1 to the precision of the run, not the double nearest to it.
TEST(ExactDecimal, QuadGetsTheDecimalNotTheDouble) {
  const auto p = to_problem<quad>(parse(decimal_scene));
  EXPECT_EQ(p.Omega0[0], quad("0.1"));
  EXPECT_NE(p.Omega0[0], quad(0.1));
  // More digits than a double holds: distinct from 0.1 in quad.
  EXPECT_EQ(p.Omega0[1], quad("0.10000000000000000000000000000001"));
  EXPECT_NE(p.Omega0[1], p.Omega0[0]);
  EXPECT_EQ(p.Omega0[2], quad(1));
  // TOML spellings: digit separators, a leading '+', an exponent.
  EXPECT_EQ(p.torque.G[0], quad("1000.5"));
  EXPECT_EQ(p.torque.G[1], quad(2));
  EXPECT_EQ(p.torque.G[2], quad("-0.3"));
  const auto times = sample_times_of<quad>(parse(decimal_scene));
  ASSERT_EQ(times.tau.size(), 2u);
  EXPECT_EQ(times.tau[0], quad("0.1"));
  EXPECT_EQ(times.tau[1], quad("0.2"));
  EXPECT_EQ(tau_end_of<quad>(parse(decimal_scene)), quad("0.3"));
}

TEST(ExactDecimal, MpfrGetsTheDecimalAtItsPrecision) {
  const eulervop::mpfr_precision_scope scope(256);
  const auto p = to_problem<mpfr_real>(parse(decimal_scene));
  EXPECT_EQ(p.Omega0[0], mpfr_real("0.1"));
  EXPECT_NE(p.Omega0[0], mpfr_real(0.1));
  EXPECT_GE(p.Omega0[0].precision(), 77u);  // decimal digits for 256 bits
}

TEST(ExactDecimal, DoubleIsCorrectlyRounded) {
  const auto p = to_problem<double>(parse(decimal_scene));
  EXPECT_EQ(p.Omega0[0], 0.1);
  EXPECT_EQ(p.torque.G[0], 1000.5);
}

TEST(ExactDecimal, ParseDecimal) {
  EXPECT_EQ(parse_decimal("+1.50e3").number->text, "1.50e3");
  EXPECT_EQ(parse_decimal("1_000", true).number->text, "1000");
  EXPECT_FALSE(parse_decimal("1_000").number);
  EXPECT_EQ(parse_decimal("nan").problem, decimal_problem::not_finite);
  EXPECT_EQ(parse_decimal("-inf").problem, decimal_problem::not_finite);
  EXPECT_EQ(parse_decimal("0x10").problem, decimal_problem::not_a_number);
  EXPECT_EQ(parse_decimal("1e999").problem, decimal_problem::out_of_range);
  EXPECT_EQ(parse_decimal("1e-999").problem, decimal_problem::out_of_range);
  EXPECT_EQ(parse_decimal("0e-999").number->value, 0.0);
  EXPECT_EQ(parse_decimal("").problem, decimal_problem::not_a_number);
  EXPECT_EQ(parse_decimal("1.").number->value, 1.0);
  EXPECT_EQ(parse_decimal(".5").number->value, 0.5);
  EXPECT_EQ(parse_decimal("e5").problem, decimal_problem::not_a_number);
}

// Non-ASCII text, a multi-line string and CRLF line endings before the numbers must not shift
// the decimal text taken from the source.
TEST(ExactDecimal, SurvivesNonAsciiMultilineAndCrlf) {
  const std::string text =
      "name = \"\u03a9\u2080 sc\u00e8ne\"\r\ndescription = \"\"\"\r\n\u03a9 line one\r\nline two \u2713\"\"\"\r\n"
      "[initial]\r\n\tOmega = [ 0.1 ,\t0.7, 1e-1 ]\r\n[span]\r\ntau_end = 1\r\nsamples = 2\r\n";
  const auto p = to_problem<quad>(parse(text));
  EXPECT_EQ(p.Omega0[0], quad("0.1"));
  EXPECT_EQ(p.Omega0[1], quad("0.7"));
  EXPECT_EQ(p.Omega0[2], quad("0.1"));
}

// ---- sample times ----------------------------------------------------------------------------

TEST(SampleTimes, EquallySpacedWithExactEndpoints) {
  const scene s = parse("name = \"x\"\n[initial]\nOmega = [1, 0, 1]\n[span]\ntau_end = 0.7\nsamples = 8\n");
  const auto times = sample_times_of<quad>(s);
  ASSERT_EQ(times.tau.size(), 8u);
  EXPECT_EQ(times.tau.front(), 0);
  EXPECT_EQ(times.tau.back(), quad("0.7"));
  EXPECT_EQ(times.tau[1], quad("0.7") / 7);
  EXPECT_TRUE(times.t.empty());
  for (std::size_t i = 1; i < times.tau.size(); ++i) EXPECT_LT(times.tau[i - 1], times.tau[i]);
}

// ---- physical scenes -------------------------------------------------------------------------

const char* const physical_scene = R"(name = "phys"
[body]
inertia = [100.0, 150.0, 200.0]
[torque]
M = [0.01, -0.02, 0.005]
[initial]
omega = [0.02, 0.1, 0.05]
[span]
t_end = 3600
samples = 5
)";

template <class T>
class PhysicalConversion : public ::testing::Test {};
using ConversionTypes = ::testing::Types<double, quad>;
TYPED_TEST_SUITE(PhysicalConversion, ConversionTypes, scalar_test_names);

// Physical -> normalized (Eqs. 2-4, G as in docs/design.md section 1.1) -> physical returns the
// scene's numbers.
TYPED_TEST(PhysicalConversion, RoundTrips) {
  using T = TypeParam;
  using std::abs;
  const scene s = parse(physical_scene);
  const auto p = to_problem<T>(s);
  const auto scale = scaling_of<T>(s);
  const T eps = eulervop::epsilon<T>();
  const vec3<T> omega = scale.omega_of_Omega(p.Omega0);
  const vec3<T> M = scale.M_of_G(p.torque.G);
  const vec3<T> omega_in = to_vec3<T>(std::get<initial_rates>(s.initial).rates);
  const vec3<T> M_in = to_vec3<T>(*s.torque);
  for (int i = 0; i < 3; ++i) {
    // A division and a multiplication by the same rounded factors: a few eps relative.
    EXPECT_LE(abs(omega[i] - omega_in[i]), 4 * eps * abs(omega_in[i])) << i;
    EXPECT_LE(abs(M[i] - M_in[i]), 8 * eps * abs(M_in[i])) << i;
  }
  const T t_end = scale.t_of_tau(tau_end_of<T>(s));
  EXPECT_LE(abs(t_end - T(3600)), 4 * eps * T(3600));
  // Samples: t column exact, tau = t dtau/dt.
  const auto times = sample_times_of<T>(s);
  ASSERT_EQ(times.t.size(), 5u);
  EXPECT_EQ(times.t[4], T(3600));
  EXPECT_EQ(times.tau[4], tau_end_of<T>(s));
  EXPECT_EQ(times.tau[2], scale.tau_of_t(T(1800)));
}

// Eqs. 8-9 (with the corrected Eq. 9 denominator) give the same c1, c2 as Eq. 7 applied to the
// normalized rates.
TYPED_TEST(PhysicalConversion, EnergyIntegralsMatchEq7) {
  using T = TypeParam;
  using std::abs;
  const T eps = eulervop::epsilon<T>();
  for (const char* omega : {"[0.02, 0.1, 0.05]", "[-0.3, 0.001, 0.2]", "[0.5, -0.4, -0.7]"}) {
    SCOPED_TRACE(omega);
    std::string text = physical_scene;
    text.replace(text.find("[0.02, 0.1, 0.05]"), 17, omega);
    const scene s = parse(text);
    const auto p = to_problem<T>(s);
    const auto scale = scaling_of<T>(s);
    const vec3<T> w = to_vec3<T>(std::get<initial_rates>(s.initial).rates);
    const T c1sq = eulervop::c1_squared(p.Omega0), c2sq = eulervop::c2_squared(p.Omega0);
    // Eq. 8 subtracts 2 T I3 - H^2, which cancels to ~ c1^2 (I3-I1)(I3-I2) out of ~ I3^2 w^2:
    // allow the condition number of that difference times a few eps.
    const T scale_sq = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) * 200 * 200 / (50 * 100);
    EXPECT_LE(abs(scale.c1_squared_from_energy(w) - c1sq), 16 * eps * scale_sq);
    EXPECT_LE(abs(scale.c2_squared_from_energy(w) - c2sq), 16 * eps * scale_sq * 4);
  }
}

// c1, c2, u with u != 0 (Eq. 12) keeps the integrals of Eq. 7: c1^2 = O1^2 + O2^2, c2^2 = O2^2 + O3^2.
TEST(InitialElements, NonZeroUKeepsTheIntegrals) {
  const scene s = parse("name = \"x\"\n[initial]\nc1 = 0.5\nc2 = 1.25\nu = 2.7\n[span]\ntau_end = 1\nsamples = 2\n");
  const auto p = to_problem<quad>(s);
  using std::abs;
  const quad eps = eulervop::epsilon<quad>();
  EXPECT_LE(abs(eulervop::c1_squared(p.Omega0) - quad("0.25")), 8 * eps);
  EXPECT_LE(abs(eulervop::c2_squared(p.Omega0) - quad("1.5625")), 8 * eps);
  EXPECT_GT(p.Omega0[1], 0);  // sn(2.7 | 0.4) > 0 (2.7 < 2 K(0.4) = 3.3)
  EXPECT_LT(p.Omega0[0], 0);  // cn < 0 past K(0.4) = 1.64
}

TEST(InitialElements, ZeroUIsExact) {
  const scene s = parse("name = \"x\"\n[initial]\nc1 = 0.3\nc2 = 0.9\nu = 0\n[span]\ntau_end = 1\nsamples = 2\n");
  const auto p = to_problem<quad>(s);
  EXPECT_EQ(p.Omega0, (vec3<quad>{quad("0.3"), 0, quad("0.9")}));
}

// ---- bad scenes ------------------------------------------------------------------------------

struct bad_scene {
  const char* label;
  std::string text;
  std::vector<std::string> expected;  // substrings the message must contain
};

const std::string head = "name = \"x\"\n";
const std::string init = "[initial]\nOmega = [0.5, 0.0, 1.0]\n";
const std::string span = "[span]\ntau_end = 1.0\nsamples = 3\n";
const std::string body = "[body]\ninertia = [100, 150, 200]\n";
const std::string pinit = "[initial]\nomega = [0.02, 0.1, 0.05]\n";
const std::string pspan = "[span]\nt_end = 10\nsamples = 3\n";

std::vector<bad_scene> bad_scenes() {
  return {
      {"empty", "", {"name", "empty"}},
      {"comments only", "# nothing\n\n", {"name"}},
      {"malformed", head + "[span\n", {"test.toml:2:", "parse error"}},
      {"bad string", "name = \"x\n", {"parse error"}},
      {"duplicate key", head + "name = \"y\"\n" + init + span, {"parse error"}},
      {"missing name", init + span, {"`name`"}},
      {"name not string", "name = 3\n" + init + span, {"name = 3", "string"}},
      {"name empty", "name = \"\"\n" + init + span, {"name", "empty"}},
      {"unknown top-level", head + "colour = 1\n" + init + span, {"colour", "top level"}},
      {"unknown in span", head + init + span + "foo = 2\n", {"foo", "[span]"}},
      {"unknown in initial", head + "[initial]\nOmega = [0.5, 0.0, 1.0]\nOmeg = 1\n" + span, {"Omeg", "[initial]"}},
      {"unknown table", head + init + span + "[extra]\nx = 1\n", {"extra"}},
      {"span not table", head + "span = 3\n" + init, {"[span]", "table"}},
      {"missing initial", head + span, {"[initial]"}},
      {"missing span", head + init, {"[span]"}},
      {"Omega and c1", head + "[initial]\nOmega = [0.5, 0.0, 1.0]\nc1 = 0.5\n" + span, {"[initial]", "not both"}},
      {"c1 without c2", head + "[initial]\nc1 = 0.5\nu = 0\n" + span, {"c2"}},
      {"k = 1", head + "[initial]\nc1 = 1\nc2 = 1\nu = 0\n" + span, {"[initial] c1 = 1", "k"}},
      {"c2 zero", head + "[initial]\nc1 = 0\nc2 = 0\nu = 0\n" + span, {"[initial] c2 = 0"}},
      {"Omega two", head + "[initial]\nOmega = [0.5, 1.0]\n" + span, {"[initial] Omega", "3 numbers"}},
      {"Omega string", head + "[initial]\nOmega = [\"a\", 0, 1]\n" + span, {"[initial] Omega", "number"}},
      {"Omega nan", head + "[initial]\nOmega = [nan, 0.0, 1.0]\n" + span, {"[initial] Omega = nan", "finite"}},
      {"G inf", head + "[torque]\nG = [inf, 0, 0]\n" + init + span, {"[torque] G1 = inf", "finite"}},
      {"G -inf", head + "[torque]\nG = [0, -inf, 0]\n" + init + span, {"[torque] G2 = -inf"}},
      {"tau_end zero", head + init + "[span]\ntau_end = 0\nsamples = 3\n", {"[span] tau_end = 0", "positive"}},
      {"tau_end negative", head + init + "[span]\ntau_end = -1\nsamples = 3\n", {"[span] tau_end = -1", "positive"}},
      {"tau_end string", head + init + "[span]\ntau_end = \"136 s\"\nsamples = 3\n",
       {"[span] tau_end = \"136 s\"", "a constant formula here"}},
      {"tau_end missing", head + init + "[span]\nsamples = 3\n", {"tau_end"}},
      {"samples 1", head + init + "[span]\ntau_end = 1\nsamples = 1\n", {"[span] samples = 1"}},
      {"samples float", head + init + "[span]\ntau_end = 1\nsamples = 2.5\n", {"[span] samples = 2.5", "integer"}},
      {"samples huge", head + init + "[span]\ntau_end = 1\nsamples = 100000000000\n", {"[span] samples"}},
      {"samples and times", head + init + "[span]\ntau_end = 1\nsamples = 3\ntimes = [0.5]\n", {"[span]", "not both"}},
      {"times unordered", head + init + "[span]\ntau_end = 1\ntimes = [0.5, 0.2]\n", {"[span] times = 0.2", "increasing"}},
      {"times repeated", head + init + "[span]\ntau_end = 1\ntimes = [0.5, 0.5]\n", {"[span] times = 0.5"}},
      {"times beyond", head + init + "[span]\ntau_end = 1\ntimes = [0.5, 2]\n", {"[span] times = 2", "tau_end"}},
      {"times negative", head + init + "[span]\ntau_end = 1\ntimes = [-0.5]\n", {"[span] times = -0.5"}},
      {"inertia negative third", head + "[body]\ninertia = [100, 150, -200]\n" + pinit + pspan, {"[body] inertia", "I3 must be positive"}},
      {"inertia zero", head + "[body]\ninertia = [0, 100, 200]\n" + pinit + pspan, {"[body] inertia", "positive"}},
      {"omega without body", head + pinit + span, {"[initial] omega", "[body]"}},
      {"G in physical", head + body + "[torque]\nG = [1, 1, 1]\n" + pinit + pspan, {"[torque] G", "physical"}},
      {"M without body", head + "[torque]\nM = [1, 1, 1]\n" + init + span, {"[torque] M", "[body]"}},
      {"Omega in physical", head + body + init + pspan, {"[initial] Omega", "physical"}},
      {"tau_end in physical", head + body + pinit + span, {"[span] tau_end", "t_end"}},
      {"t_end in normalized", head + init + "[span]\nt_end = 1\nsamples = 3\n", {"[span] t_end", "[body]"}},
      {"t_end negative", head + body + pinit + "[span]\nt_end = -5\nsamples = 3\n", {"[span] t_end = -5"}},
      {"empty torque", head + "[torque]\n" + init + span, {"[torque]"}},
      {"precision float", head + init + span + "[reference]\nprecision = \"float\"\n", {"[reference] precision = \"float\""}},
      {"precision mpfr:1", head + init + span + "[reference]\nprecision = \"mpfr:1\"\n", {"[reference] precision = \"mpfr:1\""}},
      {"precision number", head + init + span + "[reference]\nprecision = 128\n", {"[reference] precision = 128"}},
      {"degree zero", head + init + span + "[reference]\ndegree = 0\n", {"[reference] degree = 0"}},
      {"tolerance negative", head + init + span + "[reference]\ntolerance = -1e-30\n", {"[reference] tolerance = -1e-30"}},
      {"unknown in reference", head + init + span + "[reference]\nbits = 3\n", {"bits", "[reference]"}},
      {"step K/0", head + init + span + "[run]\nstep = \"K/0\"\n", {"[run] step = \"K/0\""}},
      {"step negative", head + init + span + "[run]\nstep = -0.01\n", {"[run] step = -0.01"}},
      {"method unknown", head + init + span + "[run]\nmethods = [\"rk5\"]\n", {"[run] methods = \"rk5\""}},
      {"method twice", head + init + span + "[run]\nmethods = [\"rk4\", \"rk4\"]\n", {"[run] methods", "twice"}},
      {"formulation unknown", head + init + span + "[run]\nformulations = [\"kepler\"]\n", {"[run] formulations"}},
  };
}

void PrintTo(const bad_scene& c, std::ostream* os) { *os << c.label; }

class BadScene : public ::testing::TestWithParam<bad_scene> {};

TEST_P(BadScene, OneLineMessageNamesTheField) {
  const bad_scene& c = GetParam();
  try {
    parse(c.text);
    FAIL() << "accepted: " << c.text;
  } catch (const input_error& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    EXPECT_TRUE(msg.starts_with("scene test.toml")) << msg;
    for (const auto& part : c.expected) EXPECT_NE(msg.find(part), std::string::npos) << "'" << part << "' not in: " << msg;
  }
}

INSTANTIATE_TEST_SUITE_P(Table, BadScene, ::testing::ValuesIn(bad_scenes()),
                         [](const ::testing::TestParamInfo<bad_scene>& info) {
                           std::string name;
                           for (char ch : std::string(info.param.label))
                             name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
                           return name;
                         });

// A scene without samples or times loads (the command line may complete it: --samples, --times),
// and asking for its sample times names what is missing.
TEST(SceneSpan, WithoutSamplesLoadsAndItsTimesAreRefused) {
  const eulervop::scene::scene s = parse("name = \"open\"\n[initial]\nOmega = [0.5, 0.0, 1.0]\n[span]\ntau_end = 1\n");
  EXPECT_FALSE(s.samples.has_value());
  EXPECT_TRUE(s.times.empty());
  try {
    (void)eulervop::scene::sample_times_of<double>(s);
    FAIL() << "sample times of a scene without samples or times";
  } catch (const input_error& e) {
    EXPECT_EQ(std::string(e.what()), "[span] of scene open: give samples (a count) or times (a list)");
  }
}

TEST(BadSceneFile, UnreadablePathNamesIt) {
  try {
    load_scene_file("/nonexistent/scene.toml");
    FAIL();
  } catch (const input_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/scene.toml"), std::string::npos) << e.what();
  }
}

}  // namespace
