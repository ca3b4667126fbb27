// The reference CSV of `eulervop reference`: its '#' metadata block, its header and its rows.
//
// One writer and one streaming reader, so the format has one owner (the layout is described in
// the README, "Command line"). `reference` and `batch` write it, streaming the rows (the header,
// which states the finished run, is written last and placed first); `report --reference` and
// `check` read it. Numbers stay numbers: the estimated error is a decimal (its text as written,
// three significant digits, and the nearest double), the precision a parsed precision.
#pragma once

#include "compute/scene_library.hpp"
#include "io/csv_rows.hpp"
#include "io/text_buffer.hpp"

#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/model/euler_problem.hpp>

#include <fmt/format.h>

#include <array>
#include <cstddef>
#include <functional>
#include <istream>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace eulervop::app {

// The '#' lines of a reference file, in the order they are written.
struct reference_metadata {
  std::string scene_name;                        // # scene
  std::string scene_source;                      // # scene_source
  std::string command;                           // # command (none if empty)
  std::string overrides;                         // # overrides (none if empty)
  std::string times;                             // # times: binary_times_note when the times are binary64
  eulervop::precision precision = eulervop::precision::binary128();  // # precision
  std::string method;                            // # method
  std::optional<double> wall_seconds;            // # wall_seconds
  std::optional<decimal> estimated_max_error;    // # estimated_max_error (--verify)
  std::optional<decimal> estimated_max_error_omega;  // # estimated_max_error_omega (a body's, rad/s)
  std::optional<eulervop::precision> verify_precision;  // # verify_precision (with --verify)
  std::string verify_method;                     // # verify_method (with --verify)
  std::optional<double> wall_seconds_verify;     // # wall_seconds_verify
  std::optional<decimal> certified_max_error;    // # certified_max_error (--certify; rows then carry `radius`)
  std::optional<decimal> certified_max_error_omega;  // # certified_max_error_omega (physical scenes, rad/s)
  std::optional<decimal> certified_max_error_q;  // # certified_max_error_q (with an attitude: |q - q*|_2)
  std::string certify_method;                    // # certify_method (with --certify)
  std::vector<std::string> notes;                // # note lines (the scene's notes)
  std::string attitude;                          // # attitude (its convention): rows carry q0..q3
  std::string coupled;                           // # coupled: the torque reads q (one problem of 7 states)
  std::optional<decimal> q_norm_drift;           // # q_norm_drift: the largest | |q| - 1 | (coupled runs)
  std::optional<decimal> estimated_max_attitude_error;  // # estimated_max_attitude_error (rad, --verify)
  std::string scene_text;                        // # scene_text lines, each ending in '\n'

  // The precision to read the rows in: double values are exact in quad, MPFR at its bits.
  eulervop::precision reading_precision() const;
};

// The "# times:" line of a run sampled at binary64 times (the Python module's): `check` then
// matches a trajectory's time to a sample exactly, not to a decimal within 1e-12.
inline constexpr const char* binary_times_note =
    "binary64 (each sample time is a binary64 number, printed to the digits that give it back)";

// The "# attitude:" line: the convention of the q columns, and the precision [initial] q was
// normalized in.
std::string attitude_convention(const eulervop::precision& p);

// "mpfr:256 (effective_bits=257)": the precision as the metadata states it.
std::string precision_text(const eulervop::precision& p);

// The columns of a reference file: tau and Omega for a normalized scene; for a physical scene, its
// own terms first (t and omega, q0..q3 with an attitude), then tau and Omega; t and omega alone
// for a body integrated in the direct form of Eq. 1, which has no tau or Omega; t and y for a
// scene in the coefficient form.
enum class reference_layout { normalized, physical, direct, coefficient };

// The layout of the scene's reference file: the one place that decides it.
reference_layout reference_layout_of(const scene& s);

// The columns of a reference file of this metadata (certified: radii; an attitude: q0..q3).
std::vector<std::string> reference_columns(const reference_metadata& m, reference_layout layout);

// The metadata block and the column header of a reference file, each line ending in '\n'.
std::string reference_csv_header(const reference_metadata& m, reference_layout layout);

// The unit of each error figure a reference of this layout carries (its estimates, radii and
// their header lines), by name: "rad/s", "rad", or what a figure without a unit measures (the
// normalized Eq. 20, the coefficient form's |y - y*|_2).
std::string error_unit(reference_layout layout, std::string_view figure);

// Formats the rows of a reference file and hands them to `sink` in chunks of about 64 KiB, so a
// run streams its rows however many there are.
class reference_csv_row_writer {
 public:
  using sink_function = std::function<void(std::string_view)>;
  explicit reference_csv_row_writer(sink_function sink) : sink_(std::move(sink)) {}

  template <scalar T>
  void row(const T& tau, const vec3<T>& Omega) {
    cells(tau, Omega);
    end_row();
  }
  // A physical scene's row: the time in seconds and omega in rad/s (the scene's own terms), then
  // the normalized state. (A row of the direct form is the one-state row, with t and omega.)
  template <scalar T>
  void row(const T& tau, const vec3<T>& Omega, const T& t, const vec3<T>& omega) {
    cells(t, omega);
    buffer_.push_back(',');
    cells(tau, Omega);
    end_row();
  }
  // A row with the attitude: the row above, then q0..q3.
  template <scalar T>
  void row(const T& tau, const vec3<T>& Omega, const quaternion<T>& q) {
    cells(tau, Omega);
    quaternion_cells(q);
    end_row();
  }
  // A physical scene's row with the attitude: t, omega, q0..q3, then the normalized state.
  template <scalar T>
  void row(const T& tau, const vec3<T>& Omega, const T& t, const vec3<T>& omega, const quaternion<T>& q) {
    cells(t, omega);
    quaternion_cells(q);
    buffer_.push_back(',');
    cells(tau, Omega);
    end_row();
  }
  // A certified row: its cells as texts, already formatted (the radii were computed for them), in
  // the layout's order (reference_csv_header).
  void certified_row(const std::vector<std::string>& cells) {
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (i) buffer_.push_back(',');
      buffer_.append(cells[i].data(), cells[i].data() + cells[i].size());
    }
    end_row();
  }
  // Hands over the rows still buffered.
  void flush();

 private:
  template <scalar T>
  void cells(const T& time, const vec3<T>& v) {
    format_into(buffer_, "{},{},{},{}", to_text(time), to_text(v[0]), to_text(v[1]), to_text(v[2]));
  }
  template <scalar T>
  void quaternion_cells(const quaternion<T>& q) {
    format_into(buffer_, ",{},{},{},{}", to_text(q.w), to_text(q.x), to_text(q.y), to_text(q.z));
  }
  void end_row();

  sink_function sink_;
  fmt::memory_buffer buffer_;
};

// A whole reference file in memory, header then rows: for small files and the tests.
class reference_csv_writer {
 public:
  reference_csv_writer(const reference_metadata& m, reference_layout layout)
      : text_(reference_csv_header(m, layout)), rows_([this](std::string_view s) { text_.append(s); }) {}
  reference_csv_writer(const reference_csv_writer&) = delete;  // rows_ appends to this->text_
  reference_csv_writer& operator=(const reference_csv_writer&) = delete;

  template <scalar T, class... Physical>
  void row(const T& tau, const vec3<T>& Omega, const Physical&... t_and_omega) {
    rows_.row(tau, Omega, t_and_omega...);
  }
  std::string text() {
    rows_.flush();
    return text_;
  }

 private:
  std::string text_;
  reference_csv_row_writer rows_;
};

// The metadata block of the reference file at `path`; `what` names it in messages ("--reference").
reference_metadata read_reference_metadata(std::string_view what, const std::string& path);

// Streams a reference file: the metadata and the header on construction, then one row per
// next(). Every problem is an input_error naming `where`, the line and the cell.
class reference_csv_reader {
 public:
  reference_csv_reader(std::istream& in, std::string where);

  const reference_metadata& metadata() const { return meta_; }
  // The column named `name`; input_error ("the header has no column `name`{why}") if absent.
  std::size_t column(const std::string& name, std::string_view why = "") const;
  csv_rows& rows() { return rows_; }
  const csv_rows& rows() const { return rows_; }

  // The current row's state as numbers in T: Omega, or omega in a file of the direct form
  // (reference_layout::direct), whose state it is.
  template <scalar T>
  vec3<T> Omega() const {
    return columns<T>(Omega_);
  }
  // The current row's cells in three columns, as numbers in T.
  template <scalar T>
  vec3<T> columns(const std::array<std::size_t, 3>& c) const {
    return {rows_.number(c[0]).template to_scalar<T>(), rows_.number(c[1]).template to_scalar<T>(),
            rows_.number(c[2]).template to_scalar<T>()};
  }

 private:
  csv_rows rows_;
  reference_metadata meta_;
  std::array<std::size_t, 3> Omega_{};
};

}  // namespace eulervop::app
