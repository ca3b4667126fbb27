// Helpers for the end-to-end tests of the `eulervop` program (test_cli.cpp, test_report.cpp):
// run the binary (EULERVOP_BINARY) in a fresh directory and capture its exit code and output.
#pragma once

#include <gtest/gtest.h>

#include <cctype>
#include <string_view>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

namespace eulervop::cli_test {

namespace fs = std::filesystem;

inline const std::string binary = EULERVOP_BINARY;
inline const std::string source_dir = EULERVOP_SOURCE_DIR;

inline std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A torque that overflows double: Omega3 = G3 tau passes DBL_MAX = 1.798e308 at tau = 1.798e8
// (exact: G3 = 1e300 from Omega3 = 0). A double reference must stop there as a numerical failure.
// The scene is shared with the Python module's tests (tests/scenes/overflow.toml).
inline std::string overflow_scene() { return read_file(source_dir + "/tests/scenes/overflow.toml"); }

inline void write_file(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

inline std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

inline std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// A fresh directory per test, removed afterwards.
class temp_dir {
 public:
  temp_dir() {
    std::string pattern = (fs::temp_directory_path() / "eulervop-cli-XXXXXX").string();
    path_ = ::mkdtemp(pattern.data());
  }
  ~temp_dir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  temp_dir(const temp_dir&) = delete;
  temp_dir& operator=(const temp_dir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

struct run_result {
  int exit_code = -1;
  std::string out, err;
};

// Runs the binary (or `program`) in `dir` with `args`, capturing stdout and stderr.
inline run_result run(const fs::path& dir, const std::vector<std::string>& args, const std::string& program = binary) {
  std::string cmd = "cd " + shell_quote(dir.string()) + " && " + shell_quote(program);
  for (const auto& a : args) cmd += " " + shell_quote(a);
  cmd += " > .stdout 2> .stderr < /dev/null";
  const int status = std::system(cmd.c_str());
  run_result r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_file(dir / ".stdout");
  r.err = read_file(dir / ".stderr");
  fs::remove(dir / ".stdout");
  fs::remove(dir / ".stderr");
  return r;
}

// Cells of a CSV line (empty cells kept).
inline std::vector<std::string> cells_of(const std::string& line) {
  std::vector<std::string> cells;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = line.find(',', begin);
    cells.push_back(line.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin));
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  return cells;
}

// The data rows of a CSV text (a reference, errors.csv), as cells: `#` lines skipped, the first
// other line the header (into `header`, if given).
inline std::vector<std::vector<std::string>> table_rows(const std::string& csv,
                                                        std::vector<std::string>* header = nullptr) {
  std::vector<std::vector<std::string>> rows;
  bool header_seen = false;
  for (const std::string& l : lines_of(csv)) {
    if (l.starts_with("#")) continue;
    if (!header_seen) {
      header_seen = true;
      if (header) *header = cells_of(l);
      continue;
    }
    rows.push_back(cells_of(l));
  }
  return rows;
}

inline std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// No NaN or infinity in any output, in any spelling (docs/design.md section 5.3).
inline void expect_no_nan(const std::string& text, const std::string& what) {
  const std::string l = lower(text);
  EXPECT_EQ(l.find("nan"), std::string::npos) << what << ":\n" << text;
  EXPECT_EQ(l.find("inf"), std::string::npos) << what << ":\n" << text;
}

// A GoogleTest parameter name from a case label: letters and digits kept, the rest '_'.
inline std::string test_name_of(std::string_view label) {
  std::string name;
  for (char ch : label) name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
  return name;
}

// The bad-input contract (docs/design.md section 5.3): exit code 2, exactly one line on stderr
// that starts "eulervop: error: " and contains `expected`, nothing on stdout.
inline void expect_one_line_error(const run_result& r, const std::string& expected) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  const auto lines = lines_of(r.err);
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_TRUE(lines[0].starts_with("eulervop: error: ")) << lines[0];
  EXPECT_NE(lines[0].find(expected), std::string::npos) << "'" << expected << "' not in: " << lines[0];
  EXPECT_TRUE(r.out.empty()) << r.out;
}

// Names of the entries of `dir` other than `keep`.
inline std::vector<std::string> entries_except(const fs::path& dir, const std::string& keep) {
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename() != keep) files.push_back(e.path().filename().string());
  return files;
}

}  // namespace eulervop::cli_test
