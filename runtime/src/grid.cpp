#include "grid.hpp"

#include <algorithm>
#include <cmath>

namespace mbgrt::detail {

OutputGrid::OutputGrid(double t_start, double t_end, double interval)
    : t_start_(t_start), t_end_(t_end), interval_(interval) {
  // The tolerance absorbs the rounding in e.g. 1.0 / 0.1 so that a span of a
  // whole number of intervals does not grow a spurious extra point.
  const double intervals = (t_end - t_start) / interval;
  count_ = static_cast<std::size_t>(std::ceil(intervals - 1e-9 * std::max(1.0, intervals))) + 1;
  const double inv = 1.0 / interval;
  if (std::abs(inv - std::round(inv)) <= 1e-9 * inv) per_second_ = std::round(inv);
}

double OutputGrid::operator[](std::size_t k) const {
  if (k + 1 >= count_) return t_end_;
  const double kd = static_cast<double>(k);
  // k / 10 is correctly rounded where k * 0.1 is not (3 * 0.1 = 0.30000000000000004),
  // so decimal intervals give the times a reader expects in the CSV.
  const double offset = per_second_ > 0.0 ? kd / per_second_ : kd * interval_;
  return std::min(t_start_ + offset, t_end_);
}

}  // namespace mbgrt::detail
