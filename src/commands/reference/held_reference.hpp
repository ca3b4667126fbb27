// A reference run's rows held in memory, in the run's own precision: the Python module's
// Reference. Its columns are those of the CSV `eulervop reference` would write for the same job
// (reference_csv_header), its cells the same numbers; the decimal text of a cell is made only
// when asked for, so a million rows cost their values (16 bytes a number in quad), not their text.
#pragma once

#include "commands/reference/reference_job.hpp"
#include "compute/certified_row.hpp"
#include "io/reference_csv.hpp"

#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/model/physical_scaling.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace eulervop::app {

// The rows' numbers in T: the state (Omega, omega in the direct form, or y) and q.
template <scalar T>
struct held_rows {
  std::vector<vec3<T>> y;
  std::vector<quaternion<T>> q;  // with an attitude
  std::optional<physical_scaling<T>> scale;  // a physical scene's
};

class held_reference final : public reference_row_sink {
 public:
  // What a column holds.
  enum class cell_kind { time, tau, state, omega, q, radius, radius_omega, radius_q };
  struct column_kind {
    cell_kind kind;
    std::size_t index;  // the component, for state, omega and q
  };

  // An empty reference for the job's run (run_reference_job fills it). The job must sample at
  // binary64 times (use_binary_times).
  explicit held_reference(const reference_job& job);

  void values(const double& tau, const double* t, const vec3<double>& y, const quaternion<double>* q) override;
  void values(const quad& tau, const quad* t, const vec3<quad>& y, const quaternion<quad>* q) override;
  void values(const mpfr_real& tau, const mpfr_real* t, const vec3<mpfr_real>& y,
              const quaternion<mpfr_real>* q) override;
  void certified(const std::vector<std::string>& cells, const certified_radii& radii) override;
  // The run's metadata, once it is over: the header follows from it.
  void finish(reference_metadata metadata);

  std::size_t size() const { return times_.size(); }
  // The sample times, each exactly the binary64 number it was given as, in the scene's own time.
  const std::vector<double>& times() const { return times_; }
  const std::vector<std::string>& columns() const { return columns_; }
  const std::vector<column_kind>& kinds() const { return kinds_; }
  const reference_metadata& metadata() const { return metadata_; }
  const scene& source_scene() const { return scene_; }
  const eulervop::precision& precision() const { return precision_; }
  reference_layout layout() const { return layout_; }

  // Column c of every row as binary64: each value rounded to nearest, each radius rounded up (so
  // that it still bounds the distance of the printed cells from the exact solution).
  void column_values(std::size_t c, double* out, std::size_t stride) const;
  // Row i's cells as `eulervop reference` prints them.
  std::vector<std::string> row_text(std::size_t i) const;
  // The whole file `eulervop reference` would write: header, then rows.
  std::string csv_text() const;

  // Cell (i, c) in T, the run's type (with_scalar(precision()) gives it); not for the radii.
  template <scalar T>
  T value(std::size_t i, std::size_t c) const;
  // The cell's text (the radii's as the certificate wrote them).
  std::string text(std::size_t i, std::size_t c) const;

 private:
  template <scalar T>
  void keep(const T* t, const vec3<T>& y, const quaternion<T>* q);
  template <scalar T>
  const held_rows<T>& rows_in() const { return std::get<held_rows<T>>(rows_); }

  scene scene_;
  eulervop::precision precision_;
  reference_layout layout_;
  bool certify_;
  std::vector<double> times_;
  std::variant<std::monostate, held_rows<double>, held_rows<quad>, held_rows<mpfr_real>> rows_;
  std::vector<certified_radii> radii_;
  reference_metadata metadata_;
  std::vector<std::string> columns_;
  std::vector<column_kind> kinds_;
};

}  // namespace eulervop::app
