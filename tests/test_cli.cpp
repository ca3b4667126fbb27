// The `eulervop` program end to end: bad input (exit 2, one line naming the field or flag, no
// output file), and short successful runs (CSV layout, determinism). The contract is in
// docs/design.md section 5.3.
#include "cli_test_support.hpp"

#include <eulervop/core/scalar.hpp>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

using namespace eulervop::cli_test;

// Files in `dir` other than the scene we wrote: there must be none after a failure (no output,
// no temporary left behind).
std::vector<std::string> leftovers(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name != "scene.toml" && name != "existing.csv") names.push_back(name);
  }
  return names;
}

// ---- bad input -------------------------------------------------------------------------------

const std::string good_scene =
    "name = \"good\"\n[torque]\nG = [1.0, 1.0, 1.0]\n[initial]\nOmega = [0.5, 0.0, 1.0]\n"
    "[span]\ntau_end = 1.0\nsamples = 3\n";
const std::string physical_scene =
    "name = \"phys\"\n[body]\ninertia = [100, 150, 200]\n[torque]\nM = [0.01, -0.02, 0.005]\n"
    "[initial]\nomega = [0.02, 0.1, 0.05]\n[span]\nt_end = 10\nsamples = 3\n";
// The SciML rigid body's equations (docs/test-problems.md): the coefficient form with a formula.
const std::string coefficient_scene =
    "name = \"coef\"\n[equations]\na = [-2.0, 1.25, -0.5]\n[torque]\nf = [0.0, 0.0, \"0.25*sin(t)^2\"]\n"
    "[initial]\ny = [1.0, 0.0, 0.9]\n[span]\nt_end = 1.0\nsamples = 3\n";
// A torque on a window: [[torque.piece]] with formula bounds.
const std::string piece_scene = good_scene + "[[torque.piece]]\nfrom = \"0.25\"\nto = \"pi/8\"\nG = [0, 0, 2]\n";

struct bad_input {
  const char* label;
  std::string scene;               // written to scene.toml and passed when not empty
  std::vector<std::string> args;   // after "reference"; "--out out.csv" is added unless has_out
  std::string expected;            // the field or flag the message must name
  bool has_out = false;
  bool pass_scene = true;
};

void PrintTo(const bad_input& c, std::ostream* os) { *os << c.label; }

std::string with(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  if (at == std::string::npos) throw std::logic_error("test setup: '" + from + "' not in scene");
  return text.replace(at, from.size(), to);
}

std::vector<bad_input> bad_inputs() {
  const std::string& g = good_scene;
  const std::string& p = physical_scene;
  return {
      // scene files
      {"malformed toml", "name = \"x\"\n[span\n", {}, "parse error"},
      {"invalid utf8", "name = \"\xff\xfe\"\n", {}, "parse error"},
      {"empty file", "", {}, "name"},
      {"missing name", with(g, "name = \"good\"\n", ""), {}, "`name`"},
      {"name wrong type", with(g, "\"good\"", "true"), {}, "name = true"},
      {"unknown top-level key", g + "colour = 1\n", {}, "`colour`"},
      {"unknown key in table", with(g, "samples = 3", "samples = 3\nsample = 3"), {}, "`sample`"},
      {"unknown table", g + "[extras]\n", {}, "`extras`"},
      {"missing initial", with(g, "[initial]\nOmega = [0.5, 0.0, 1.0]\n", ""), {}, "[initial]"},
      {"Omega and c1", with(g, "Omega = [0.5, 0.0, 1.0]", "Omega = [0.5, 0.0, 1.0]\nc1 = 0.5"), {}, "[initial]"},
      {"Omega wrong type", with(g, "[0.5, 0.0, 1.0]", "\"0.5, 0, 1\""), {}, "[initial] Omega"},
      {"Omega nan", with(g, "[0.5, 0.0, 1.0]", "[nan, 0.0, 1.0]"), {}, "[initial] Omega = nan"},
      {"G inf", with(g, "[1.0, 1.0, 1.0]", "[1.0, inf, 1.0]"), {}, "[torque] G2 = inf"},
      {"G negative inf", with(g, "[1.0, 1.0, 1.0]", "[1.0, 1.0, -inf]"), {}, "[torque] G3 = -inf"},
      {"k not below 1", with(g, "Omega = [0.5, 0.0, 1.0]", "c1 = 2\nc2 = 1\nu = 0"), {}, "[initial] c1 = 2"},
      {"tau_end zero", with(g, "tau_end = 1.0", "tau_end = 0"), {}, "[span] tau_end = 0"},
      {"tau_end negative", with(g, "tau_end = 1.0", "tau_end = -1"), {}, "[span] tau_end = -1"},
      {"tau_end nan", with(g, "tau_end = 1.0", "tau_end = nan"), {}, "[span] tau_end = nan"},
      {"samples 1", with(g, "samples = 3", "samples = 1"), {}, "[span] samples = 1"},
      {"samples wrong type", with(g, "samples = 3", "samples = \"3\""), {}, "[span] samples"},
      {"times unordered", with(g, "samples = 3", "times = [0.5, 0.25]"), {}, "[span] times = 0.25"},
      {"negative inertia", with(p, "[100, 150, 200]", "[100, -150, 200]"), {}, "[body] inertia"},
      {"omega without body", with(p, "[body]\ninertia = [100, 150, 200]\n[torque]\nM = [0.01, -0.02, 0.005]\n", ""),
       {}, "[initial] omega"},
      {"G with body", with(p, "M = [0.01, -0.02, 0.005]", "G = [1, 1, 1]"), {}, "[torque] G"},
      {"t_end negative", with(p, "t_end = 10", "t_end = -10"), {}, "[span] t_end = -10"},
      {"precision float", g + "[reference]\nprecision = \"float\"\n", {}, "[reference] precision = \"float\""},
      {"precision mpfr:1 in scene", g + "[reference]\nprecision = \"mpfr:1\"\n", {}, "[reference] precision"},
      {"method unknown", g + "[run]\nmethods = [\"euler-forward\"]\n", {}, "[run] methods"},
      {"step zero", g + "[run]\nstep = 0\n", {}, "[run] step = 0"},
      // torque formulas (G3 of the normalized scene, M3 of the physical one, f3 of the coefficient form)
      {"formula unknown identifier", with(g, "G = [1.0, 1.0, 1.0]", "G = [1.0, 1.0, \"foo*tau\"]"), {}, "`foo`"},
      {"formula unknown function", with(g, "G = [1.0, 1.0, 1.0]", "G = [1.0, 1.0, \"tan(tau)\"]"), {}, "`tan`"},
      {"formula omega1 in a normalized scene", with(g, "G = [1.0, 1.0, 1.0]", "G = [1.0, 1.0, \"omega1\"]"), {},
       "`omega1` is a variable of a physical scene"},
      {"formula tau in a physical scene", with(p, "M = [0.01, -0.02, 0.005]", "M = [0.01, -0.02, \"tau\"]"), {},
       "`tau` is a variable of a normalized scene"},
      {"formula omega1 in the coefficient form", with(coefficient_scene, "\"0.25*sin(t)^2\"", "\"omega1\""), {},
       "[torque] f3 = \"omega1\""},
      {"formula unbalanced open", with(g, "G = [1.0, 1.0, 1.0]", "G = [1.0, 1.0, \"sin(tau\"]"), {}, "[torque] G3"},
      {"formula unbalanced close", with(g, "G = [1.0, 1.0, 1.0]", "G = [1.0, 1.0, \"tau)\"]"), {}, "`)`"},
      {"formula dangling operator", with(g, "G = [1.0, 1.0, 1.0]", "G = [1.0, 1.0, \"tau*\"]"), {}, "[torque] G3"},
      {"formula non-integer power", with(g, "G = [1.0, 1.0, 1.0]", "G = [1.0, 1.0, \"tau^0.5\"]"), {}, "power"},
      {"formula wrong arity", with(g, "G = [1.0, 1.0, 1.0]", "G = [1.0, 1.0, \"sin(tau, 1)\"]"), {}, "sin"},
      {"formula empty", with(g, "G = [1.0, 1.0, 1.0]", "G = [1.0, 1.0, \"  \"]"), {}, "[torque] G3"},
      {"formula not a string", with(g, "G = [1.0, 1.0, 1.0]", "G = [1.0, 1.0, true]"), {}, "[torque] G3 = true"},
      // the attitude
      {"q of length 3", with(p, "omega = [0.02, 0.1, 0.05]", "omega = [0.02, 0.1, 0.05]\nq = [1, 0, 0]"), {},
       "[initial] q"},
      {"q nan", with(p, "omega = [0.02, 0.1, 0.05]", "omega = [0.02, 0.1, 0.05]\nq = [nan, 0, 0, 1]"), {},
       "[initial] q = nan"},
      {"q inf", with(p, "omega = [0.02, 0.1, 0.05]", "omega = [0.02, 0.1, 0.05]\nq = [1, inf, 0, 0]"), {},
       "[initial] q = inf"},
      {"q norm not 1", with(p, "omega = [0.02, 0.1, 0.05]", "omega = [0.02, 0.1, 0.05]\nq = [1, 0.01, 0, 0]"), {},
       "[initial] q = [1, 0.01, 0, 0]: its norm is 1.00004999875"},
      {"q without a body", with(g, "Omega = [0.5, 0.0, 1.0]", "Omega = [0.5, 0.0, 1.0]\nq = [1, 0, 0, 0]"), {},
       "[initial] q: an attitude needs a body"},
      {"q in the coefficient form", with(coefficient_scene, "y = [1.0, 0.0, 0.9]", "y = [1.0, 0.0, 0.9]\nq = [1, 0, 0, 0]"),
       {}, "[initial] q: an attitude needs a body"},
      // the coefficient form
      {"equations with body", with(p, "[torque]", "[equations]\na = [1, 2, 3]\n[torque]"), {}, "[equations]"},
      {"equations a of length 2", with(coefficient_scene, "a = [-2.0, 1.25, -0.5]", "a = [-2.0, 1.25]"), {},
       "[equations] a"},
      {"equations a nan", with(coefficient_scene, "a = [-2.0, 1.25, -0.5]", "a = [-2.0, nan, -0.5]"), {},
       "[equations] a = nan"},
      {"coefficient form with Omega", with(coefficient_scene, "y = [", "Omega = ["), {}, "[initial]"},
      {"coefficient form with G", with(coefficient_scene, "f = [", "G = ["), {}, "[torque]"},
      {"coefficient form with tau_end", with(coefficient_scene, "t_end", "tau_end"), {}, "[span] tau_end"},
      // pieces
      {"piece without from", with(piece_scene, "from = \"0.25\"\n", ""), {}, "`from`"},
      {"piece without to", with(piece_scene, "to = \"pi/8\"\n", ""), {}, "`to`"},
      {"piece from after to", with(piece_scene, "from = \"0.25\"", "from = \"0.5\""), {}, "must be below to = pi/8"},
      {"piece bound not constant", with(piece_scene, "from = \"0.25\"", "from = \"tau\""), {}, "from = \"tau\""},
      {"piece without G", with(piece_scene, "G = [0, 0, 2]", ""), {}, "`G`"},
      {"pieces overlap", piece_scene + "[[torque.piece]]\nfrom = 0.3\nto = 0.5\nG = [0, 0, 1]\n", {}, "overlaps"},
      {"piece of M in a normalized scene", with(piece_scene, "G = [0, 0, 2]", "M = [0, 0, 2]"), {}, "`M`"},
      // paths
      {"unreadable scene path", "", {"does-not-exist.toml"}, "does-not-exist.toml", false, false},
      {"scene is a directory", "", {"."}, "scene .", false, false},
      {"unwritable out", g, {"--out", "/nonexistent/dir/x.csv"}, "--out /nonexistent/dir/x.csv", true},
      {"out is a directory", g, {"--out", "."}, "--out .", true},
      // flags
      {"flag precision mpfr:1", g, {"--precision", "mpfr:1"}, "--precision mpfr:1"},
      {"flag precision mpfr:10000000", g, {"--precision", "mpfr:10000000"}, "--precision mpfr:10000000"},
      {"flag precision float", g, {"--precision", "float"}, "--precision float"},
      {"flag t-end on normalized", g, {"--t-end", "5"}, "--t-end 5"},
      {"flag tau-end on physical", p, {"--tau-end", "5"}, "--tau-end 5"},
      {"flag tau-end nan", g, {"--tau-end", "nan"}, "--tau-end nan"},
      {"flag tau-end inf", g, {"--tau-end", "inf"}, "--tau-end inf"},
      {"flag tau-end zero", g, {"--tau-end", "0"}, "--tau-end 0"},
      {"flag tau-end negative", g, {"--tau-end=-2"}, "--tau-end -2"},
      {"flag tau-end text", g, {"--tau-end", "long"}, "--tau-end long"},
      {"flag tau-end missing value", g, {"--tau-end"}, "--tau-end", true},
      {"flag samples 0", g, {"--samples", "0"}, "--samples 0"},
      {"flag samples negative", g, {"--samples", "-3"}, "--samples -3"},
      {"flag samples not integer", g, {"--samples", "2.5"}, "--samples 2.5"},
      {"flag samples and times", g, {"--samples", "3", "--times", "0.5"}, "--samples"},
      {"flag times unordered", g, {"--times", "0.5,0.25"}, "--times 0.5,0.25"},
      {"flag times beyond span", g, {"--times", "0.5,2"}, "--times 0.5,2"},
      {"flag times nan", g, {"--times", "0.5,nan"}, "--times 0.5,nan"},
      {"flag times empty item", g, {"--times", "0.5,,0.7"}, "--times 0.5,,0.7"},
      {"flag degree zero", g, {"--degree", "0"}, "--degree 0"},
      {"flag tolerance negative", g, {"--tolerance=-1e-20"}, "--tolerance -1e-20"},
      {"flag unknown flag", g, {"--bogus"}, "--bogus"},
      {"flag two scenes", g, {"other.toml"}, "other.toml"},
  };
}

class BadInput : public ::testing::TestWithParam<bad_input> {};

TEST_P(BadInput, ExitsTwoWithOneLineAndNoFile) {
  const bad_input& c = GetParam();
  // Twice: once to a new output path (which must not appear), once over an existing file
  // (which must survive untouched).
  for (const char* target : {"out.csv", "existing.csv"}) {
    SCOPED_TRACE(target);
    temp_dir dir;
    std::vector<std::string> args = {"reference"};
    if (c.pass_scene) {
      write_file(dir.path() / "scene.toml", c.scene);
      args.push_back("scene.toml");
    }
    args.insert(args.end(), c.args.begin(), c.args.end());
    if (!c.has_out) args.insert(args.end(), {"--out", target});
    write_file(dir.path() / "existing.csv", "keep me\n");

    const run_result r = run(dir.path(), args);
    expect_one_line_error(r, c.expected);
    EXPECT_EQ(read_file(dir.path() / "existing.csv"), "keep me\n");
    const auto extra = leftovers(dir.path());
    EXPECT_TRUE(extra.empty()) << extra.front();
    if (c.has_out) break;
  }
}

INSTANTIATE_TEST_SUITE_P(Table, BadInput, ::testing::ValuesIn(bad_inputs()),
                         [](const ::testing::TestParamInfo<bad_input>& info) { return test_name_of(info.param.label); });

TEST(BadCommandLine, UnknownCommandAndNoCommand) {
  temp_dir dir;
  for (const std::vector<std::string>& args : {std::vector<std::string>{"frobnicate"}, std::vector<std::string>{}}) {
    const run_result r = run(dir.path(), args);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(lines_of(r.err).size(), 1u) << r.err;
    EXPECT_TRUE(r.err.starts_with("eulervop: error: ")) << r.err;
  }
}

TEST(CommandLine, VersionAndHelp) {
  temp_dir dir;
  const run_result v = run(dir.path(), {"--version"});
  EXPECT_EQ(v.exit_code, 0);
  EXPECT_TRUE(v.out.starts_with("eulervop ")) << v.out;
  const run_result h = run(dir.path(), {"reference", "--help"});
  EXPECT_EQ(h.exit_code, 0);
  EXPECT_NE(h.out.find("--verify"), std::string::npos);
}

// ---- successful runs -------------------------------------------------------------------------

// The CSV without the wall-time lines, which are the only ones allowed to differ between runs.
std::string without_wall_time(const std::string& csv) {
  std::string kept;
  for (const auto& l : lines_of(csv))
    if (!l.starts_with("# wall_seconds")) kept += l + "\n";
  return kept;
}

std::vector<std::string> data_rows(const std::string& csv) {
  std::vector<std::string> rows;
  for (const auto& l : lines_of(csv))
    if (!l.starts_with("#")) rows.push_back(l);
  return rows;
}

TEST(Reference, ShortRunWritesCsvDeterministically) {
  temp_dir dir;
  const std::vector<std::string> args = {"reference", "--tau-end", "1", "--samples", "5", "--out", "x.csv"};
  const run_result first = run(dir.path(), args);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_TRUE(first.out.empty());
  const std::string a = read_file(dir.path() / "x.csv");
  const run_result second = run(dir.path(), args);
  ASSERT_EQ(second.exit_code, 0) << second.err;
  const std::string b = read_file(dir.path() / "x.csv");

  const auto rows = data_rows(a);
  ASSERT_EQ(rows.size(), 6u) << a;
  EXPECT_EQ(rows[0], "tau,Omega1,Omega2,Omega3");
  EXPECT_TRUE(rows[1].starts_with("0.000000000000000000000000000000000000e+00,")) << rows[1];
  EXPECT_TRUE(rows[5].starts_with("1.000000000000000000000000000000000000e+00,")) << rows[5];
  for (const char* meta : {"# eulervop ", "# scene: paper-fig1", "# scene_source: ", "# precision: quad",
                           "# method: chebyshev-picard degree=", "# wall_seconds: ", "# scene_text: name = \"paper-fig1\""})
    EXPECT_NE(a.find(meta), std::string::npos) << meta;
  EXPECT_TRUE(a.starts_with("# eulervop ")) << a;
  EXPECT_EQ(without_wall_time(a), without_wall_time(b));
  EXPECT_EQ(leftovers(dir.path()), std::vector<std::string>{"x.csv"});
}

TEST(Reference, StdoutMatchesFile) {
  temp_dir dir;
  const run_result to_file = run(dir.path(), {"reference", "--tau-end", "0.5", "--samples", "3", "--out", "y.csv"});
  const run_result to_stdout = run(dir.path(), {"reference", "--tau-end", "0.5", "--samples", "3"});
  ASSERT_EQ(to_file.exit_code, 0) << to_file.err;
  ASSERT_EQ(to_stdout.exit_code, 0) << to_stdout.err;
  EXPECT_EQ(without_wall_time(read_file(dir.path() / "y.csv")), without_wall_time(to_stdout.out));
  EXPECT_TRUE(to_stdout.err.empty()) << to_stdout.err;  // no progress when stderr is not a terminal
}

// Explicit --times reach the run as the decimals given: 0.1 is quad("0.1"), not the double 0.1.
TEST(Reference, ExplicitTimesAreExact) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"reference", "--tau-end", "0.3", "--times", "0.1,0.25,0.3"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = data_rows(r.out);
  ASSERT_EQ(rows.size(), 4u);
  const char* expected[] = {"0.1", "0.25", "0.3"};
  for (int i = 0; i < 3; ++i) {
    const std::string tau = rows[i + 1].substr(0, rows[i + 1].find(','));
    EXPECT_EQ(*eulervop::from_text<eulervop::quad>(tau), eulervop::quad(expected[i])) << tau;
  }
}

TEST(Reference, PhysicalSceneHasPhysicalColumns) {
  temp_dir dir;
  write_file(dir.path() / "scene.toml", physical_scene);
  const run_result r = run(dir.path(), {"reference", "scene.toml", "--precision", "double", "--t-end", "20"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = data_rows(r.out);
  ASSERT_EQ(rows.size(), 4u) << r.out;
  EXPECT_EQ(rows[0], "t,omega1,omega2,omega3,tau,Omega1,Omega2,Omega3");
  // Column 1 is t: 0, 10, 20 s.
  auto column = [](const std::string& row, int i) {
    std::istringstream in(row);
    std::string cell;
    for (int k = 0; k <= i; ++k) std::getline(in, cell, ',');
    return std::stod(cell);
  };
  EXPECT_EQ(column(rows[3], 0), 20.0);
  EXPECT_NEAR(column(rows[1], 1), 0.02, 1e-15);  // omega1(0)
  EXPECT_NE(r.out.find("# precision: double"), std::string::npos);
}

TEST(Reference, VerifyReportsAnHonestSmallError) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"reference", "--precision", "double", "--tau-end", "1", "--samples", "3", "--verify"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto at = r.out.find("# estimated_max_error: ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const double err = std::stod(r.out.substr(at + 23));
  // Double's reference on a short span: at the level of a few eps, and not zero (the quad
  // recomputation sees double's rounding of the state).
  EXPECT_GT(err, 0.0);
  EXPECT_LT(err, 1e-13);
  EXPECT_NE(r.out.find("# verify_precision: quad"), std::string::npos);
}

TEST(Reference, MpfrRunReportsEffectiveBits) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"reference", "--precision", "mpfr:128", "--tau-end", "0.25", "--samples", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("# precision: mpfr:128 (effective_bits="), std::string::npos) << r.out;
  const auto rows = data_rows(r.out);
  ASSERT_EQ(rows.size(), 3u);
  // Enough digits to round-trip 128+ bits: at least 40 significant digits per value.
  EXPECT_GE(rows[2].find(','), 40u) << rows[2];
}

// ---- torques of time and state, the coefficient form, moments of no rigid body ----------------

TEST(Reference, CoefficientFormWritesTAndY) {
  temp_dir dir;
  write_file(dir.path() / "scene.toml", coefficient_scene);
  const run_result r = run(dir.path(), {"reference", "scene.toml", "--out", "ref.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = read_file(dir.path() / "ref.csv");
  const auto rows = data_rows(csv);
  ASSERT_EQ(rows.size(), 4u) << csv;
  EXPECT_EQ(rows[0], "t,y1,y2,y3");
  EXPECT_TRUE(rows[1].starts_with("0.000000000000000000000000000000000000e+00,1.0000")) << rows[1];
}

// Moments that break the triangle inequality are integrated, with one note on stderr and one in
// the file's metadata.
TEST(Reference, MomentsOfNoRigidBodyAreIntegratedWithANote) {
  temp_dir dir;
  write_file(dir.path() / "scene.toml", with(physical_scene, "[100, 150, 200]", "[100, 150, 300]"));
  const run_result r = run(dir.path(), {"reference", "scene.toml", "--out", "ref.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto err = lines_of(r.err);
  ASSERT_EQ(err.size(), 1u) << r.err;
  EXPECT_TRUE(err[0].starts_with("note: scene phys: [body] inertia = [100, 150, 300]: no rigid body")) << err[0];
  const std::string csv = read_file(dir.path() / "ref.csv");
  EXPECT_NE(csv.find("\n# note: [body] inertia = [100, 150, 300]: no rigid body has these moments"), std::string::npos)
      << csv;
  EXPECT_EQ(data_rows(csv).size(), 4u);
}

// A formula that is not finite where the integrator evaluates it: exit 3, one line naming the
// formula and the time, and no output file.
TEST(Reference, NonFiniteTorqueIsANumericalFailureNamingTheFormula) {
  temp_dir dir;
  write_file(dir.path() / "scene.toml", with(good_scene, "G = [1.0, 1.0, 1.0]", "G = [1.0, 1.0, \"log(tau - 0.5)\"]"));
  const run_result r = run(dir.path(), {"reference", "scene.toml", "--out", "ref.csv"});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  const auto err = lines_of(r.err);
  ASSERT_EQ(err.size(), 1u) << r.err;
  EXPECT_NE(err[0].find("G3 = log(tau - 0.5) is nan at tau = "), std::string::npos) << err[0];
  EXPECT_EQ(err[0].find("nan,"), std::string::npos) << err[0];
  EXPECT_EQ(leftovers(dir.path()), std::vector<std::string>{});
}

// --certify takes a piece whose formulas are polynomials, here at the irrational breakpoint
// pi/8, and refuses a formula that is not one (sin of the time) in one line.
TEST(Reference, CertifyTakesPiecesAndFormulasOfTheTime) {
  temp_dir dir;
  write_file(dir.path() / "scene.toml", coefficient_scene);  // f3 = 0.25 sin(t)^2
  const run_result c = run(dir.path(), {"reference", "scene.toml", "--certify", "--out", "ref.csv"});
  ASSERT_EQ(c.exit_code, 0) << c.err;
  EXPECT_NE(read_file(dir.path() / "ref.csv").find("\nt,y1,y2,y3,radius\n"), std::string::npos);
  // y has no unit, and the radius's line says so as the other forms' do.
  EXPECT_NE(read_file(dir.path() / "ref.csv")
                .find("\n# error_units: certified_max_error = |y - y*|_2 (no unit); each row's radius columns "
                      "likewise\n"),
            std::string::npos);
  write_file(dir.path() / "scene.toml", piece_scene);
  const run_result r = run(dir.path(), {"reference", "scene.toml", "--certify", "--out", "ref.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = read_file(dir.path() / "ref.csv");
  EXPECT_NE(csv.find("\ntau,Omega1,Omega2,Omega3,radius\n"), std::string::npos) << csv;
  EXPECT_NE(csv.find("# certify_method: arb bits=177 ball Chebyshev models, 3-state Lohner parallelepiped\n"), std::string::npos);
}

// `check` takes a coefficient-form trajectory by the scene's names, t and y1..3, and names the
// columns it needs when given others.
TEST(Check, CoefficientFormTrajectoryByTAndY) {
  temp_dir dir;
  write_file(dir.path() / "scene.toml", coefficient_scene);
  ASSERT_EQ(run(dir.path(), {"reference", "scene.toml", "--precision", "double", "--out", "ref.csv"}).exit_code, 0);
  std::string traj;
  for (const auto& row : data_rows(read_file(dir.path() / "ref.csv"))) traj += row + "\n";
  write_file(dir.path() / "traj.csv", traj);
  const run_result ok = run(dir.path(), {"check", "scene.toml", "traj.csv", "--tol", "1e-12"});
  EXPECT_EQ(ok.exit_code, 0) << ok.err << ok.out;
  // Eq. 7's invariants belong to Eq. 5: the table says why it has none, naming this form.
  EXPECT_NE(ok.out.find("invariant drift: none"), std::string::npos) << ok.out;
  EXPECT_NE(ok.out.find("coefficient form"), std::string::npos) << ok.out;
  write_file(dir.path() / "omega.csv", with(traj, "t,y1,y2,y3", "t,omega1,omega2,omega3"));
  expect_one_line_error(run(dir.path(), {"check", "scene.toml", "omega.csv"}), "y1..3");
  // Against a verified file: its estimate in y, in the words of its `# error_units:` line, and no
  // figure in rad/s (y is no body's rates).
  ASSERT_EQ(run(dir.path(), {"reference", "scene.toml", "--verify", "--out", "verified.csv"}).exit_code, 0);
  EXPECT_NE(read_file(dir.path() / "verified.csv").find("\n# error_units: estimated_max_error = |y - y*|_2 (no unit)\n"),
            std::string::npos);
  const run_result j = run(dir.path(), {"check", "verified.csv", "traj.csv", "--format", "json"});
  ASSERT_EQ(j.exit_code, 0) << j.err;
  EXPECT_NE(j.out.find("\"estimated_max_error_unit\": \"|y - y*|_2 (no unit)\""), std::string::npos) << j.out;
  EXPECT_NE(j.out.find("\"estimated_max_error_omega\": null"), std::string::npos) << j.out;
}

// An attitude scene: the q columns after the rates, the convention in the metadata, |q| = 1 on
// every row to quad rounding (the exact motion keeps the norm), and --certify's radius of q.
TEST(Reference, AttitudeColumnsAndConvention) {
  temp_dir dir;
  write_file(dir.path() / "scene.toml",
             with(physical_scene, "omega = [0.02, 0.1, 0.05]", "omega = [0.02, 0.1, 0.05]\nq = [0.5, 0.5, 0.5, 0.5]"));
  const run_result r = run(dir.path(), {"reference", "scene.toml", "--out", "ref.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = read_file(dir.path() / "ref.csv");
  EXPECT_NE(csv.find("\n# attitude: q0..q3 a Hamilton quaternion, scalar first, body to inertial"), std::string::npos);
  const auto rows = data_rows(csv);
  ASSERT_EQ(rows.size(), 4u) << csv;
  EXPECT_EQ(rows[0], "t,omega1,omega2,omega3,q0,q1,q2,q3,tau,Omega1,Omega2,Omega3");
  for (std::size_t k = 1; k < rows.size(); ++k) {
    std::vector<eulervop::quad> cells;
    std::istringstream in(rows[k]);
    for (std::string c; std::getline(in, c, ',');) cells.push_back(*eulervop::from_text<eulervop::quad>(c));
    ASSERT_EQ(cells.size(), 12u);
    const eulervop::quad n2 = cells[4] * cells[4] + cells[5] * cells[5] + cells[6] * cells[6] + cells[7] * cells[7];
    EXPECT_LE(abs(n2 - 1), 64 * std::numeric_limits<eulervop::quad>::epsilon()) << rows[k];
  }
  ASSERT_EQ(run(dir.path(), {"reference", "scene.toml", "--certify", "--out", "c.csv"}).exit_code, 0);
  const std::string certified = read_file(dir.path() / "c.csv");
  EXPECT_NE(certified.find("\n# certified_max_error_q: "), std::string::npos);
  EXPECT_EQ(data_rows(certified)[0],
            "t,omega1,omega2,omega3,q0,q1,q2,q3,tau,Omega1,Omega2,Omega3,radius,radius_omega,radius_q");
}

// A tolerance below the precision's reach: the run stops at its rounding, one note says so, and
// the method line records the tolerance actually used (epsilon: 2^-112 in quad, 2^-256 at
// mpfr:256, whose 257 effective bits give 2^(1 - 257)).
TEST(Reference, ToleranceBelowReachIsNotedAndRecorded) {
  temp_dir dir;
  const std::vector<std::pair<std::string, std::string>> cases = {{"quad", "tolerance=1.93e-34"},
                                                                    {"mpfr:256", "tolerance=8.64e-78"}};
  for (const auto& [precision, used] : cases) {
    const run_result r = run(dir.path(), {"reference", "--tau-end", "1", "--samples", "3", "--precision", precision,
                                          "--tolerance", "1e-100", "--out", "ref.csv"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto err = lines_of(r.err);
    ASSERT_EQ(err.size(), 1u) << r.err;
    EXPECT_TRUE(err[0].starts_with("note: --tolerance 1e-100 is below what " + precision + " can reach")) << err[0];
    const std::string csv = read_file(dir.path() / "ref.csv");
    const std::size_t at = csv.find("# method: chebyshev-picard degree=");
    ASSERT_NE(at, std::string::npos);
    const std::string method = csv.substr(at, csv.find('\n', at) - at);
    EXPECT_NE(method.find(used), std::string::npos) << method;  // the request stays on the # overrides line
    EXPECT_NE(csv.find("--precision=" + precision + " --tolerance=1e-100\n"), std::string::npos);
  }
  // At the reach or above: no note.
  const run_result ok = run(dir.path(), {"reference", "--tau-end", "1", "--samples", "3", "--tolerance", "1e-30"});
  EXPECT_EQ(ok.exit_code, 0);
  EXPECT_TRUE(ok.err.empty()) << ok.err;
}

}  // namespace
