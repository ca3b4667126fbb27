// The reference CSV: what the writer prints, the reader gives back, with the numbers as numbers.
#include "io/reference_csv.hpp"
#include "compute/scene_library.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

namespace {

using eulervop::quad;
using eulervop::vec3;
using namespace eulervop::app;

reference_metadata sample_metadata() {
  reference_metadata m;
  m.scene_name = "paper-fig1";
  m.scene_source = "data/scenes/paper-fig1.toml";
  m.command = "eulervop reference --verify";
  m.precision = eulervop::precision::mpfr(256);
  m.method = "chebyshev-picard degree=40 tolerance=1e-70 segments=3 rejected=0";
  m.estimated_max_error = decimal{"1.23e-70", 1.23e-70};
  m.verify_precision = eulervop::precision::mpfr(320);
  m.verify_method = "chebyshev-picard degree=52 tolerance=1e-90 segments=4 rejected=0";
  m.scene_text = "name = \"paper-fig1\"\n[initial]\n";
  return m;
}

TEST(ReferenceCsv, MetadataRoundTrips) {
  reference_csv_writer w(sample_metadata(), reference_layout::normalized);
  std::istringstream in(w.text());
  const reference_csv_reader r(in, "test");
  const reference_metadata& m = r.metadata();
  EXPECT_EQ(m.scene_name, "paper-fig1");
  EXPECT_EQ(m.scene_source, "data/scenes/paper-fig1.toml");
  EXPECT_EQ(m.command, "eulervop reference --verify");
  EXPECT_EQ(m.precision.name(), "mpfr:256");
  EXPECT_EQ(m.reading_precision().name(), "mpfr:256");
  ASSERT_TRUE(m.estimated_max_error);
  EXPECT_EQ(m.estimated_max_error->text, "1.23e-70");
  EXPECT_EQ(m.estimated_max_error->value, 1.23e-70);
  ASSERT_TRUE(m.verify_precision);
  EXPECT_EQ(m.verify_precision->name(), "mpfr:320");
  EXPECT_EQ(m.scene_text, "name = \"paper-fig1\"\n[initial]\n");
  EXPECT_FALSE(m.wall_seconds);  // not written: a file without timings reads back without them
}

// A body's estimate in rad/s reads back as written, and a negative one is refused like the others.
TEST(ReferenceCsv, EstimateInRadPerSecondRoundTrips) {
  reference_metadata m = sample_metadata();
  m.estimated_max_error_omega = decimal{"4.56e-71", 4.56e-71};
  reference_csv_writer w(m, reference_layout::physical);
  std::istringstream in(w.text());
  const reference_csv_reader r(in, "test");
  ASSERT_TRUE(r.metadata().estimated_max_error_omega);
  EXPECT_EQ(r.metadata().estimated_max_error_omega->text, "4.56e-71");
  EXPECT_EQ(r.metadata().estimated_max_error_omega->value, 4.56e-71);
  EXPECT_EQ(r.metadata().estimated_max_error->text, "1.23e-70");  // the key is not read as its prefix
  std::istringstream bad("# estimated_max_error_omega: -1e-30\ntau,Omega1,Omega2,Omega3\n");
  EXPECT_THROW(reference_csv_reader(bad, "reference x.csv"), input_error);
}

// The line of "# error_units:" in a header, or "" if there is none.
std::string error_units_line(const std::string& header) {
  const std::size_t at = header.find("# error_units: ");
  return at == std::string::npos ? "" : header.substr(at, header.find('\n', at) - at);
}

// Every form's figures name their unit, or say they have none; the radius columns are mentioned
// only where there are some.
TEST(ReferenceCsv, EveryFormNamesItsErrorUnits) {
  reference_metadata m = sample_metadata();
  EXPECT_EQ(error_units_line(reference_csv_header(m, reference_layout::normalized)),
            "# error_units: estimated_max_error = Eq. 20 (no unit)");
  EXPECT_EQ(error_units_line(reference_csv_header(m, reference_layout::coefficient)),
            "# error_units: estimated_max_error = |y - y*|_2 (no unit)");
  m.certified_max_error = decimal{"2.00e-70", 2e-70};
  EXPECT_EQ(error_units_line(reference_csv_header(m, reference_layout::coefficient)),
            "# error_units: estimated_max_error = |y - y*|_2 (no unit); certified_max_error = |y - y*|_2 (no unit); "
            "each row's radius columns likewise");
  m.estimated_max_error_omega = m.certified_max_error_omega = decimal{"3.00e-70", 3e-70};
  EXPECT_EQ(error_units_line(reference_csv_header(m, reference_layout::physical)),
            "# error_units: estimated_max_error = normalized Omega (Eq. 20, no unit); estimated_max_error_omega = "
            "rad/s; certified_max_error = normalized Omega (Eq. 20, no unit); certified_max_error_omega = rad/s; "
            "each row's radius columns likewise");
  m.estimated_max_error.reset();
  m.estimated_max_error_omega.reset();
  m.certified_max_error.reset();
  EXPECT_EQ(error_units_line(reference_csv_header(m, reference_layout::normalized)), "");  // no figure, no line
}

TEST(ReferenceCsv, DoubleFilesAreReadInQuad) {
  reference_metadata m = sample_metadata();
  m.precision = eulervop::precision::binary64();
  m.estimated_max_error.reset();
  reference_csv_writer w(m, reference_layout::normalized);
  std::istringstream in(w.text());
  const reference_csv_reader r(in, "test");
  EXPECT_EQ(r.metadata().precision.name(), "double");
  EXPECT_EQ(r.metadata().reading_precision().name(), "quad");
}

// A quad row printed by the writer reads back to the same quad values: to_text prints enough
// digits to round-trip (36 significant digits for 113 bits).
TEST(ReferenceCsv, QuadRowsRoundTripExactly) {
  reference_metadata m = sample_metadata();
  m.precision = eulervop::precision::binary128();
  reference_csv_writer w(m, reference_layout::normalized);
  // (cells must lie in the range of a double: the reader checks every number as a double too)
  const quad third = quad(1) / 3, tiny = quad(1e-300) / 7;
  const vec3<quad> Om = {third, -quad(2) / 7, tiny};
  w.row(quad(136) / 1024, Om);
  std::istringstream in(w.text());
  reference_csv_reader r(in, "test");
  ASSERT_TRUE(r.rows().next());
  EXPECT_EQ(r.rows().number(r.column("tau")).to_scalar<quad>(), quad(136) / 1024);
  const vec3<quad> back = r.Omega<quad>();
  for (int i = 0; i < 3; ++i) EXPECT_EQ(back[i], Om[i]) << i;
  EXPECT_FALSE(r.rows().next());
}

TEST(ReferenceCsv, BadMetadataNamesTheLine) {
  std::istringstream in("# precision: float80\ntau,Omega1,Omega2,Omega3\n");
  try {
    reference_csv_reader r(in, "reference x.csv");
    FAIL() << "accepted an unknown precision";
  } catch (const input_error& e) {
    EXPECT_EQ(std::string(e.what()), "reference x.csv: line 1: unknown precision `float80`");
  }
  std::istringstream in2("# estimated_max_error: -1\ntau,Omega1,Omega2,Omega3\n");
  EXPECT_THROW(reference_csv_reader(in2, "reference x.csv"), input_error);
  std::istringstream in3("tau,Omega1,Omega3\n");
  try {
    reference_csv_reader r(in3, "reference x.csv");
    FAIL() << "accepted a header without Omega2";
  } catch (const input_error& e) {
    EXPECT_EQ(std::string(e.what()), "reference x.csv: line 1: the header has no column `Omega2`");
  }
}

}  // namespace
