// Communication points: t_start, t_start + interval, ..., t_end.
#pragma once

#include <cstddef>

namespace mbgrt::detail {

class OutputGrid {
 public:
  /// Requires t_end >= t_start and interval > 0. When the span is not a whole
  /// number of intervals the last point is t_end itself (a shorter last interval).
  OutputGrid(double t_start, double t_end, double interval);

  /// Number of points, t_start included.
  std::size_t size() const { return count_; }
  double operator[](std::size_t k) const;

 private:
  double t_start_, t_end_, interval_;
  double per_second_ = 0.0;  ///< 1/interval when that is a whole number, else 0
  std::size_t count_;
};

}  // namespace mbgrt::detail
