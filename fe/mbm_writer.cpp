// fe/mbm_writer.cpp
#include "mbm_writer.hpp"

#include <cstdio>
#include <fmt/format.h>

namespace mbgc::fe {
namespace {

std::string num(double v) {
  if (v == 0) v = 0;  // no "-0"
  return fmt::format("{:.17g}", v);
}

void matrix(std::string& out, const std::string& record, const Eigen::MatrixXd& m) {
  out += record + "\n";
  for (long i = 0; i < m.rows(); ++i) {  // row by row, as the format asks
    out += " ";
    for (long j = 0; j < m.cols(); ++j) {
      out += ' ';  // (not " " + num(...): GCC 12 at -O3 reports a false -Wstringop-overflow there)
      out += num(m(i, j));
    }
    out += "\n";
  }
}

}  // namespace

bool write_mbm(const std::string& path, const std::vector<std::string>& comments, const Invariants& inv,
               const std::vector<NamedPoint>& points) {
  const int n = static_cast<int>(inv.mean.cols());
  std::string out;
  for (const std::string& c : comments) out += "# " + c + "\n";
  out += fmt::format("mbgc_modal_body 1\nmodes {}\nmass {}\n", n, num(inv.mass));
  matrix(out, "first_moment", inv.first_moment.transpose());
  matrix(out, "inertia", inv.inertia);
  matrix(out, "mean", inv.mean);
  for (int k = 0; k < n; ++k) matrix(out, fmt::format("moment {}", k + 1), inv.moment[static_cast<std::size_t>(k)]);
  for (int k = 0; k < n; ++k)
    for (int l = k; l < n; ++l)
      matrix(out, fmt::format("product {} {}", k + 1, l + 1), inv.product[static_cast<std::size_t>(k * n + l)]);
  matrix(out, "stiffness", inv.stiffness);
  for (const NamedPoint& p : points) {
    out += fmt::format("point {} {} {} {}\n", p.name, num(p.position.x()), num(p.position.y()), num(p.position.z()));
    matrix(out, "shape " + p.name, p.motion.shape);
    matrix(out, "slope " + p.name, p.motion.slope);
  }
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return false;
  const bool ok = std::fwrite(out.data(), 1, out.size(), f) == out.size();
  return std::fclose(f) == 0 && ok;
}

}  // namespace mbgc::fe
