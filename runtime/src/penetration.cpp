#include "penetration.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "report.hpp"

namespace mbgrt::detail {

StartPenetrations::StartPenetrations(Events& events, double tolerance) : events_(events), tolerance_(tolerance) {
  const Contacts& contacts = events.contacts();
  for (std::size_t c = 0; c < contacts.count(); ++c)
    if (!contacts.compliant(c) && contacts.start_gap(c) < -tolerance_)
      found_.push_back({c, -contacts.start_gap(c)});
}

std::vector<std::string> StartPenetrations::describe() const {
  std::vector<std::string> lines;
  for (const Found& f : found_)
    lines.push_back(fmt::format("{} starts {:.3g} m inside its surface (its gap is {:.3g} m, beyond the run's atol {:g} m): "
                                "its row pushes the bodies apart, adding energy the model did not have; start it at a gap "
                                ">= 0 (docs/multibody.md, Starting in contact)",
                                events_.model_name(events_.contacts().event(f.contact)), f.depth, -f.depth, tolerance_));
  return lines;
}

void StartPenetrations::observe(double t, const double* y, double absorbed) {
  Contacts& contacts = events_.contacts();
  for (Found& f : found_) {
    if (!std::isnan(f.settled_t)) continue;
    // (the row's approach to the surface is exponential: out once within a
    // thousandth of the depth, what remains adds less than a thousandth)
    if (contacts.closed(f.contact) && contacts.gap(t, y, f.contact) < -std::max(tolerance_, 1e-3 * f.depth)) continue;
    f.settled_t = t;
    f.added = -absorbed;
  }
}

std::vector<std::string> StartPenetrations::summary() const {
  std::vector<std::string> lines;
  for (const Found& f : found_) {
    const std::string name = events_.model_name(events_.contacts().event(f.contact));
    if (std::isnan(f.settled_t))
      lines.push_back(fmt::format("{} started {:.3g} m inside its surface and was still inside at the end", name, f.depth));
    else if (std::isnan(f.added))
      lines.push_back(fmt::format("{} started {:.3g} m inside its surface, pushed out by t = {} s", name, f.depth,
                                  format_time(f.settled_t)));
    else
      lines.push_back(fmt::format("{} started {:.3g} m inside its surface: pushing it out added {:.3g} J by t = {} s", name,
                                  f.depth, f.added, format_time(f.settled_t)));
  }
  return lines;
}

}  // namespace mbgrt::detail
