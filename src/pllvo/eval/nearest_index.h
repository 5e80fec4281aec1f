#pragma once
// numpy-style argmin of |value(j) - target| (first index on ties) over j in [first, last)
// when value(j) is non-decreasing. Floating-point rounding keeps |value - target| monotone
// on each side of the first value >= target, so only the boundary needs looking at.
#include <cmath>
#include <cstddef>

namespace pllvo::eval::detail {

template <typename ValueAt>
size_t nearest_index_sorted(size_t first, size_t last, double target, ValueAt value) {
  size_t lo = first, hi = last;  // first index with value >= target, by bisection
  while (lo < hi) {
    const size_t mid = lo + (hi - lo) / 2;
    if (value(mid) < target) lo = mid + 1;
    else hi = mid;
  }
  if (lo == first) return first;
  size_t left = lo - 1;
  const double d_left = std::abs(value(left) - target);
  while (left > first && std::abs(value(left - 1) - target) == d_left) --left;
  if (lo == last) return left;
  return d_left <= std::abs(value(lo) - target) ? left : lo;
}

}  // namespace pllvo::eval::detail
