#include "commands/reference/held_reference.hpp"

#include "compute/scene_library.hpp"
#include "compute/with_scalar.hpp"

#include <fmt/format.h>

#include <cfenv>
#include <cstdlib>
#include <stdexcept>

namespace eulervop::app {

held_reference::held_reference(const reference_job& job)
    : scene_(job.scn), precision_(job.precision), layout_(job.layout), certify_(job.certify),
      times_(job.binary_times.value_or(std::vector<double>{})) {
  if (!job.binary_times) throw std::logic_error("held_reference: the job's times are not binary64 (use_binary_times)");
}

template <scalar T>
void held_reference::keep(const T*, const vec3<T>& y, const quaternion<T>* q) {
  if (std::holds_alternative<std::monostate>(rows_)) {
    held_rows<T> rows;
    rows.y.reserve(times_.size());
    if (q) rows.q.reserve(times_.size());
    if (layout_ == reference_layout::physical) rows.scale.emplace(scaling_of<T>(scene_));
    rows_ = std::move(rows);
  }
  auto& rows = std::get<held_rows<T>>(rows_);
  rows.y.push_back(y);
  if (q) rows.q.push_back(*q);
}

void held_reference::values(const double&, const double* t, const vec3<double>& y, const quaternion<double>* q) {
  keep(t, y, q);
}
void held_reference::values(const quad&, const quad* t, const vec3<quad>& y, const quaternion<quad>* q) {
  keep(t, y, q);
}
void held_reference::values(const mpfr_real&, const mpfr_real* t, const vec3<mpfr_real>& y,
                            const quaternion<mpfr_real>* q) {
  keep(t, y, q);
}

void held_reference::certified(const std::vector<std::string>&, const certified_radii& radii) {
  radii_.push_back(radii);
}

void held_reference::finish(reference_metadata metadata) {
  metadata_ = std::move(metadata);
  columns_ = reference_columns(metadata_, layout_);
  kinds_.clear();
  for (const std::string& name : columns_) {
    const auto k = static_cast<std::size_t>(name.back() - '0');
    if (name == "t" || (name == "tau" && layout_ == reference_layout::normalized)) kinds_.push_back({cell_kind::time, 0});
    else if (name == "tau") kinds_.push_back({cell_kind::tau, 0});
    else if (name == "radius") kinds_.push_back({cell_kind::radius, 0});
    else if (name == "radius_omega") kinds_.push_back({cell_kind::radius_omega, 0});
    else if (name == "radius_q") kinds_.push_back({cell_kind::radius_q, 0});
    else if (name[0] == 'q') kinds_.push_back({cell_kind::q, k});
    // omega1..3 of a physical file are omega in rad/s; of the direct form, its state
    else if (name[0] == 'o' && layout_ == reference_layout::physical) kinds_.push_back({cell_kind::omega, k - 1});
    else kinds_.push_back({cell_kind::state, k - 1});  // Omega, y, or the direct form's omega
  }
  if (size() != (std::visit([](const auto& r) -> std::size_t {
        if constexpr (std::is_same_v<std::decay_t<decltype(r)>, std::monostate>) return 0;
        else return r.y.size();
      }, rows_)) || (certify_ && radii_.size() != size()))
    throw std::logic_error("held_reference: the run did not give every row");
}

template <scalar T>
T held_reference::value(std::size_t i, std::size_t c) const {
  const held_rows<T>& rows = rows_in<T>();
  const column_kind k = kinds_[c];
  switch (k.kind) {
    case cell_kind::time: return T(times_[i]);
    case cell_kind::tau: return rows.scale->tau_of_t(T(times_[i]));
    case cell_kind::state: return rows.y[i][k.index];
    case cell_kind::omega: return rows.scale->omega_of_Omega(rows.y[i])[k.index];
    case cell_kind::q: {
      const quaternion<T>& q = rows.q[i];
      return k.index == 0 ? q.w : k.index == 1 ? q.x : k.index == 2 ? q.y : q.z;
    }
    default: break;
  }
  throw std::logic_error("held_reference::value: a radius is a text");
}

std::string held_reference::text(std::size_t i, std::size_t c) const {
  switch (kinds_[c].kind) {
    case cell_kind::radius: return radii_[i].state;
    case cell_kind::radius_omega: return layout_ == reference_layout::direct ? radii_[i].state : *radii_[i].omega;
    case cell_kind::radius_q: return *radii_[i].q;
    default: break;
  }
  return with_scalar(precision_, [&](auto zero) { return to_text(value<decltype(zero)>(i, c)); });
}

namespace {
// A radius's decimal text as the binary64 number at or above it: a bound stays a bound.
double rounded_up(const std::string& text) {
  const int mode = std::fegetround();
  std::fesetround(FE_UPWARD);
  const double x = std::strtod(text.c_str(), nullptr);  // glibc's strtod rounds in the current mode
  std::fesetround(mode);
  return x;
}
}  // namespace

void held_reference::column_values(std::size_t c, double* out, std::size_t stride) const {
  const cell_kind kind = kinds_[c].kind;
  if (kind == cell_kind::radius || kind == cell_kind::radius_omega || kind == cell_kind::radius_q) {
    for (std::size_t i = 0; i < size(); ++i) out[i * stride] = rounded_up(text(i, c));
    return;
  }
  if (kind == cell_kind::time) {
    for (std::size_t i = 0; i < size(); ++i) out[i * stride] = times_[i];
    return;
  }
  with_scalar(precision_, [&](auto zero) {
    using T = decltype(zero);
    for (std::size_t i = 0; i < size(); ++i) out[i * stride] = static_cast<double>(value<T>(i, c));
    return 0;
  });
}

std::vector<std::string> held_reference::row_text(std::size_t i) const {
  std::vector<std::string> out;
  out.reserve(columns_.size());
  for (std::size_t c = 0; c < columns_.size(); ++c) out.push_back(text(i, c));
  return out;
}

std::string held_reference::csv_text() const {
  std::string text = reference_csv_header(metadata_, layout_);
  for (std::size_t i = 0; i < size(); ++i) {
    const std::vector<std::string> cells = row_text(i);
    for (std::size_t c = 0; c < cells.size(); ++c) {
      if (c) text += ',';
      text += cells[c];
    }
    text += '\n';
  }
  return text;
}

template double held_reference::value<double>(std::size_t, std::size_t) const;
template quad held_reference::value<quad>(std::size_t, std::size_t) const;
template mpfr_real held_reference::value<mpfr_real>(std::size_t, std::size_t) const;

}  // namespace eulervop::app
