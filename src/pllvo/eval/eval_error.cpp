#include "pllvo/eval/eval_error.h"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace pllvo::eval {

std::string_view EvalError::evo_name() const {
  switch (kind_) {
    case EvalErrorKind::sync: return "SyncException";
    case EvalErrorKind::filter: return "FilterException";
    case EvalErrorKind::geometry: return "GeometryException";
    case EvalErrorKind::metrics: return "MetricsException";
  }
  return "EvoException";
}

std::string python_repr(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  // Python: shortest round-trip digits, fixed notation for 1e-4 <= |x| < 1e16.
  const double mag = std::abs(value);
  const bool fixed = mag == 0.0 || (mag >= 1e-4 && mag < 1e16);
  char buf[64];
  const auto fmt = fixed ? std::chars_format::fixed : std::chars_format::scientific;
  char* end = std::to_chars(buf, buf + sizeof(buf) - 2, value, fmt).ptr;
  if (fixed && std::find(buf, end, '.') == end) {  // Python writes floats as "10.0"
    *end++ = '.';
    *end++ = '0';
  }
  return std::string(buf, end);
}

}  // namespace pllvo::eval
