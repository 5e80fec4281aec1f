#pragma once
// Errors of the evaluation. They mirror the exceptions evo raises (so the test vectors
// can name them) and are bad input for the user: the CLI reports them and exits 2.
#include <string>
#include <string_view>

#include "pllvo/common/error.h"

namespace pllvo::eval {

enum class EvalErrorKind {
  sync,      ///< evo's SyncException: no timestamps associate
  filter,    ///< evo's FilterException: the RPE delta selects no pose pairs
  geometry,  ///< evo's GeometryException: degenerate Umeyama covariance
  metrics,   ///< evo's MetricsException: a metric that cannot be computed on this input
};

class EvalError : public InputError {
 public:
  EvalError(EvalErrorKind kind, const std::string& message) : InputError(message), kind_(kind) {}
  EvalErrorKind kind() const { return kind_; }
  /// evo's exception class name ("SyncException", ...).
  std::string_view evo_name() const;

 private:
  EvalErrorKind kind_;
};

/// A double as Python's repr() writes it ("0.01", "10.0", "1e-05"), so that messages
/// read exactly like evo's.
std::string python_repr(double value);

}  // namespace pllvo::eval
