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
  // The same failure stated in the scene's own time: "numerical failure at t=X s (tau=Y): ...",
  // where t = tau * per_tau (a physical scene's seconds, Eq. 4), so that the time comes first in
  // the user's terms.
  numerical_failure in_time(const std::string& name, double per_tau, const std::string& unit) const {
    numerical_failure out = *this;
    if (!status_.tau) return out;
    const std::string what = std::runtime_error::what();
    const std::size_t cause = what.find(": ");
    out.std::runtime_error::operator=(std::runtime_error(
        "numerical failure at " + name + "=" + format_tau(*status_.tau * per_tau) + (unit.empty() ? "" : " " + unit) +
        " (tau=" + format_tau(*status_.tau) + ")" + (cause == std::string::npos ? "" : what.substr(cause))));
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
