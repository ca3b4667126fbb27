// The exception that carries a failed outcome (outcome.hpp) to the program, which maps it to
// exit code 3: the reference integrator gave up, or a reference cannot be used.
#pragma once

#include <eulervop/core/outcome.hpp>
#include <eulervop/core/outcome_text.hpp>

#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

namespace eulervop {

// what() is "numerical failure at tau=X: " and the outcome's text, then ": " and `detail` when
// one is given (what a formula torque evaluated to, and where: model/expression_torque.hpp).
class numerical_failure : public std::runtime_error {
 public:
  explicit numerical_failure(const outcome& status, const std::string& detail = {})
      : std::runtime_error("numerical failure at tau=" + format_tau(status.tau) + ": " + describe(status) +
                           (detail.empty() ? "" : ": " + detail)),
        status_(status) {}
  // The same failure placed in the user's terms: "numerical failure at " + `place` (e.g.
  // "t=50 s (tau=14.4337567)", the scene's own time first) and the same cause.
  numerical_failure placed_at(const std::string& place) const {
    numerical_failure out = *this;
    const std::string what = std::runtime_error::what();
    const std::size_t cause = what.find(": ");
    out.std::runtime_error::operator=(
        std::runtime_error("numerical failure at " + place + (cause == std::string::npos ? "" : what.substr(cause))));
    return out;
  }
  double tau() const { return status_.tau.value_or(std::numeric_limits<double>::quiet_NaN()); }
  const outcome& status() const { return status_; }

 private:
  static std::string format_tau(const std::optional<double>& tau) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", tau.value_or(std::numeric_limits<double>::quiet_NaN()));
    return buf;
  }
  outcome status_;
};

}  // namespace eulervop
