// make_fe_beam: writes the modal-data file (.mbm, docs/modal_format.md) of a
// straight Euler–Bernoulli beam clamped at x = 0, computed from its own finite
// elements.
//
// Why: the `ModalFile.*` tests need a body that comes from "an FE program" and
// not from the compiler. This program is that FE program. It reduces the beam
// to its fixed-interface normal modes (a Craig–Bampton reduction with the
// clamped end as the interface has exactly these modes). The tests then check
// that a body read from its file moves like the compiler's built-in
// `flexible = beam`. It uses nothing from the compiler, so the two models
// share no code.
//
//   make_fe_beam OUT.mbm L rho E width_y height_z n_xy n_xz elements
//
// The beam runs along body x from 0 to L. Its section is width_y (along y) x
// height_z (along z). n_xy modes bend it in the x-y plane (deflection along y,
// stiffness E Iz), then n_xz modes bend it in the x-z plane (deflection along
// z, stiffness E Iy), each plane lowest frequency first.
//
// FE model per plane: `elements` equal 2-node Hermite cubic elements with DOFs
// (w, w') per node. The mass matrix is consistent and translational only, and
// node 0 is clamped.
//
// Build: g++ -std=c++20 -O2 -I/usr/include/eigen3 make_fe_beam.cpp

// Eigen's eigensolvers trip GCC's -Wmaybe-uninitialized (a false positive).
// CMake's Eigen3::Eigen target hides it with -isystem, but a plain
// `g++ -I/usr/include/eigen3 -Werror` build needs this.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <Eigen/Dense>
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

namespace {

constexpr int kMaxModes = 64;  // the format's limit on `modes n`

struct Args {
  std::string out_path;
  double length = 0, density = 0, youngs = 0, width_y = 0, height_z = 0;
  int n_xy = 0, n_xz = 0, elements = 0;
};

[[noreturn]] void usage_error(const std::string& message) {
  std::cerr << "make_fe_beam: " << message << "\n"
            << "usage: make_fe_beam OUT.mbm L rho E width_y height_z n_xy n_xz elements\n"
            << "  e.g. make_fe_beam beam.mbm 8 2766.67 6.8952e10 3.675e-2 1.986e-3 3 2 40\n";
  std::exit(2);
}

double positive_number(const char* text, const char* what) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text, &end);
  if (end == text || *end != '\0' || errno == ERANGE || !std::isfinite(v) || v <= 0)
    usage_error(std::string(what) + " must be a positive number, got `" + text + "`");
  return v;
}

int count_at_least(const char* text, const char* what, long lowest) {
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || errno == ERANGE || v < lowest || v > 1000000)
    usage_error(std::string(what) + " must be an integer >= " + std::to_string(lowest) + ", got `" + text + "`");
  return static_cast<int>(v);
}

Args parse_args(int argc, char** argv) {
  if (argc != 10) usage_error("expected 9 arguments, got " + std::to_string(argc - 1));
  Args a;
  a.out_path = argv[1];
  a.length = positive_number(argv[2], "L");
  a.density = positive_number(argv[3], "rho");
  a.youngs = positive_number(argv[4], "E");
  a.width_y = positive_number(argv[5], "width_y");
  a.height_z = positive_number(argv[6], "height_z");
  a.n_xy = count_at_least(argv[7], "n_xy", 0);
  a.n_xz = count_at_least(argv[8], "n_xz", 0);
  a.elements = count_at_least(argv[9], "elements", 1);
  if (a.n_xy + a.n_xz < 1) usage_error("n_xy + n_xz must be at least 1");
  if (a.n_xy + a.n_xz > kMaxModes) usage_error("n_xy + n_xz must be at most " + std::to_string(kMaxModes));
  // Asking for more modes than elements gives modes the mesh cannot resolve.
  if (a.n_xy > a.elements || a.n_xz > a.elements) usage_error("n_xy and n_xz must each be at most `elements`");
  return a;
}

// Hermite cubic shape functions of one element of length h at local
// coordinate s in [0, 1], acting on the DOFs (w_left, w'_left, w_right, w'_right).
struct Hermite {
  Eigen::Vector4d value, slope, curvature;  // N, dN/dx, d2N/dx2

  Hermite(double s, double h) {
    const double s2 = s * s, s3 = s2 * s;
    value << 1 - 3 * s2 + 2 * s3, h * (s - 2 * s2 + s3), 3 * s2 - 2 * s3, h * (s3 - s2);
    slope << (6 * s2 - 6 * s) / h, 1 - 4 * s + 3 * s2, (6 * s - 6 * s2) / h, 3 * s2 - 2 * s;
    curvature << (12 * s - 6) / (h * h), (6 * s - 4) / h, (6 - 12 * s) / (h * h), (6 * s - 2) / h;
  }
};

// 5-point Gauss–Legendre rule mapped to [0, 1]. It is exact to degree 9. The
// highest degree used here is 6 (N N^T in the mass matrix and Phi_k Phi_l in
// the products).
struct GaussPoint {
  double s, weight;
};

std::vector<GaussPoint> gauss5() {
  const double a = std::sqrt(5 - 2 * std::sqrt(10.0 / 7)) / 3, b = std::sqrt(5 + 2 * std::sqrt(10.0 / 7)) / 3;
  const double wa = (322 + 13 * std::sqrt(70.0)) / 900, wb = (322 - 13 * std::sqrt(70.0)) / 900;
  const double t[5] = {-b, -a, 0, a, b}, w[5] = {wb, wa, 128.0 / 225, wa, wb};
  std::vector<GaussPoint> rule;
  for (int i = 0; i < 5; ++i) rule.push_back({(t[i] + 1) / 2, w[i] / 2});
  return rule;
}

// One bending plane: its FE matrices (all nodes, clamp included) and its
// lowest modes as full DOF vectors [w_0, w'_0, w_1, w'_1, ...].
struct Plane {
  Eigen::MatrixXd stiffness, mass;
  std::vector<Eigen::VectorXd> modes;
};

Plane solve_plane(double mass_per_length, double bending_stiffness, double length, int elements, int mode_count) {
  const int dofs = 2 * (elements + 1);
  const double h = length / elements;
  Plane p;
  p.stiffness = Eigen::MatrixXd::Zero(dofs, dofs);
  p.mass = Eigen::MatrixXd::Zero(dofs, dofs);
  for (int e = 0; e < elements; ++e) {
    Eigen::Matrix4d ke = Eigen::Matrix4d::Zero(), me = Eigen::Matrix4d::Zero();
    for (const GaussPoint& g : gauss5()) {
      const Hermite n(g.s, h);
      ke += bending_stiffness * n.curvature * n.curvature.transpose() * g.weight * h;
      me += mass_per_length * n.value * n.value.transpose() * g.weight * h;
    }
    p.stiffness.block<4, 4>(2 * e, 2 * e) += ke;
    p.mass.block<4, 4>(2 * e, 2 * e) += me;
  }
  if (mode_count == 0) return p;

  // The clamp removes node 0's two DOFs. What remains is positive definite.
  const int free = dofs - 2;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(p.stiffness.bottomRightCorner(free, free),
                                                                   p.mass.bottomRightCorner(free, free));
  if (solver.info() != Eigen::Success) {
    std::cerr << "make_fe_beam: the generalised eigenproblem did not converge\n";
    std::exit(1);
  }
  // Eigen returns eigenvalues in increasing order, so the first columns are the lowest modes.
  for (int k = 0; k < mode_count; ++k) {
    Eigen::VectorXd full = Eigen::VectorXd::Zero(dofs);
    full.tail(free) = solver.eigenvectors().col(k);
    // Normalisation: the largest |w| over the nodes is 1 and w(L) > 0. This
    // makes eta_k the tip deflection (for a cantilever the tip is the largest).
    double largest = 0;
    for (int i = 0; i <= elements; ++i) largest = std::max(largest, std::abs(full(2 * i)));
    full /= largest;
    if (full(2 * elements) < 0) full = -full;
    p.modes.push_back(full);
  }
  return p;
}

// A mode of the body: the axis its deflection runs along (1 = y for x-y
// bending, 2 = z for x-z bending) and its nodal DOFs within that plane.
struct Mode {
  int axis;
  const Eigen::VectorXd* dofs;
  const Plane* plane;
};

// Everything the file holds except the points.
struct Invariants {
  double mass = 0;
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  Eigen::MatrixXd mean;                    // 3 x n
  std::vector<Eigen::Matrix3d> moment;     // A_k
  std::vector<Eigen::Matrix3d> product;    // B_kl at k * n + l, k <= l
  Eigen::MatrixXd stiffness;               // n x n
};

Invariants integrate(const Args& a, const std::vector<Mode>& modes) {
  const int n = static_cast<int>(modes.size());
  const double area = a.width_y * a.height_z;
  const double mu = a.density * area;
  const double iy = a.width_y * std::pow(a.height_z, 3) / 12, iz = a.height_z * std::pow(a.width_y, 3) / 12;
  const double h = a.length / a.elements;

  Invariants inv;
  inv.mean = Eigen::MatrixXd::Zero(3, n);
  inv.moment.assign(n, Eigen::Matrix3d::Zero());
  inv.product.assign(static_cast<std::size_t>(n) * n, Eigen::Matrix3d::Zero());
  double line_second_moment = 0;  // ∫ x^2 dm

  for (int e = 0; e < a.elements; ++e) {
    for (const GaussPoint& g : gauss5()) {
      const Hermite shape(g.s, h);
      const double x = (e + g.s) * h, dm = mu * g.weight * h;
      const Eigen::Vector3d r0(x, 0, 0);
      Eigen::MatrixXd phi = Eigen::MatrixXd::Zero(3, n);  // Phi(r0)
      for (int k = 0; k < n; ++k) phi(modes[k].axis, k) = shape.value.dot(modes[k].dofs->segment<4>(2 * e));

      inv.mass += dm;
      inv.first_moment += r0 * dm;
      line_second_moment += x * x * dm;
      inv.mean += phi * dm;
      for (int k = 0; k < n; ++k) {
        inv.moment[k] += r0 * phi.col(k).transpose() * dm;
        for (int l = k; l < n; ++l) inv.product[k * n + l] += phi.col(k) * phi.col(l).transpose() * dm;
      }
    }
  }

  // J0 of the line of mass plus each section's own rotary inertia, rho L Iy
  // and rho L Iz. The compiler's built-in beam uses exactly this J0, and the
  // tests compare against it.
  inv.inertia.diagonal() << a.density * a.length * (iy + iz), line_second_moment + a.density * a.length * iy,
      line_second_moment + a.density * a.length * iz;

  // Modal stiffness from the FE matrix. Modes of different planes do not
  // couple. Within a plane the matrix is diagonal up to rounding; we still
  // write it in full, symmetrised.
  inv.stiffness = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < n; ++k)
    for (int l = 0; l < n; ++l)
      if (modes[k].plane == modes[l].plane)
        inv.stiffness(k, l) = modes[k].dofs->dot(modes[k].plane->stiffness * *modes[l].dofs);
  inv.stiffness = (0.5 * (inv.stiffness + inv.stiffness.transpose())).eval();
  return inv;
}

std::string num(double v) {
  if (v == 0) v = 0;  // write the clamp's and other signed zeros as "0", not "-0"
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

void write_matrix(std::FILE* f, const std::string& record, const Eigen::MatrixXd& m) {
  std::fprintf(f, "%s\n", record.c_str());
  for (int i = 0; i < m.rows(); ++i) {  // row by row, as the format asks
    std::fprintf(f, " ");
    for (int j = 0; j < m.cols(); ++j) std::fprintf(f, " %s", num(m(i, j)).c_str());
    std::fprintf(f, "\n");
  }
}

}  // namespace

int main(int argc, char** argv) {
  const Args a = parse_args(argc, argv);
  const double mu = a.density * a.width_y * a.height_z;
  const double iy = a.width_y * std::pow(a.height_z, 3) / 12, iz = a.height_z * std::pow(a.width_y, 3) / 12;

  // Deflection along y bends about z (E Iz), deflection along z about y (E Iy).
  const Plane xy = solve_plane(mu, a.youngs * iz, a.length, a.elements, a.n_xy);
  const Plane xz = solve_plane(mu, a.youngs * iy, a.length, a.elements, a.n_xz);
  std::vector<Mode> modes;
  for (const Eigen::VectorXd& m : xy.modes) modes.push_back({1, &m, &xy});
  for (const Eigen::VectorXd& m : xz.modes) modes.push_back({2, &m, &xz});
  const int n = static_cast<int>(modes.size());

  const Invariants inv = integrate(a, modes);
  std::vector<double> omega(n);
  for (int k = 0; k < n; ++k) omega[k] = std::sqrt(inv.stiffness(k, k) / inv.product[k * n + k].trace());

  std::FILE* f = std::fopen(a.out_path.c_str(), "w");
  if (!f) {
    std::cerr << "make_fe_beam: cannot write " << a.out_path << "\n";
    return 1;
  }
  std::fprintf(f, "# Generated by tests/numeric/make_fe_beam: Euler-Bernoulli beam clamped at x = 0,\n");
  std::fprintf(f, "# fixed-interface normal modes from %d Hermite elements per plane.\n", a.elements);
  std::fprintf(f, "# arguments: L %s rho %s E %s width_y %s height_z %s n_xy %d n_xz %d elements %d\n",
               num(a.length).c_str(), num(a.density).c_str(), num(a.youngs).c_str(), num(a.width_y).c_str(),
               num(a.height_z).c_str(), a.n_xy, a.n_xz, a.elements);
  std::fprintf(f, "# modes normalised to largest nodal |deflection| 1, tip deflection positive\n");
  for (int k = 0; k < n; ++k)
    std::fprintf(f, "# mode %d: %s bending %d, omega = %s rad/s\n", k + 1, modes[k].axis == 1 ? "x-y" : "x-z",
                 modes[k].axis == 1 ? k + 1 : k + 1 - a.n_xy, num(omega[k]).c_str());

  std::fprintf(f, "mbgc_modal_body 1\nmodes %d\n", n);
  std::fprintf(f, "mass %s\n", num(inv.mass).c_str());
  write_matrix(f, "first_moment", inv.first_moment.transpose());
  write_matrix(f, "inertia", inv.inertia);
  write_matrix(f, "mean", inv.mean);
  for (int k = 0; k < n; ++k) write_matrix(f, "moment " + std::to_string(k + 1), inv.moment[k]);
  for (int k = 0; k < n; ++k)
    for (int l = k; l < n; ++l)
      write_matrix(f, "product " + std::to_string(k + 1) + " " + std::to_string(l + 1), inv.product[k * n + l]);
  write_matrix(f, "stiffness", inv.stiffness);

  // Points sit on nodes, so shape and slope are nodal DOFs. For odd
  // `elements` there is no node at L/2; `mid` is then node elements/2
  // rounded down.
  const struct {
    const char* name;
    int node;
  } points[] = {{"root", 0}, {"mid", a.elements / 2}, {"tip", a.elements}};
  for (const auto& p : points) {
    Eigen::MatrixXd shape = Eigen::MatrixXd::Zero(3, n), slope = Eigen::MatrixXd::Zero(3, n);
    for (int k = 0; k < n; ++k) {
      const double w = (*modes[k].dofs)(2 * p.node), dw = (*modes[k].dofs)(2 * p.node + 1);
      shape(modes[k].axis, k) = w;
      // The section's small rotation is [0, -w_z', w_y']: x-y bending turns it
      // about +z, x-z bending turns it about -y.
      if (modes[k].axis == 1) slope(2, k) = dw;
      else slope(1, k) = -dw;
    }
    const double x = a.length * p.node / a.elements;
    std::fprintf(f, "point %s %s 0 0\n", p.name, num(x).c_str());
    write_matrix(f, std::string("shape ") + p.name, shape);
    write_matrix(f, std::string("slope ") + p.name, slope);
  }

  const bool ok = std::ferror(f) == 0;
  if (std::fclose(f) != 0 || !ok) {
    std::cerr << "make_fe_beam: error writing " << a.out_path << "\n";
    return 1;
  }
  for (int k = 0; k < n; ++k)
    std::cout << "mode " << k + 1 << " (" << (modes[k].axis == 1 ? "x-y" : "x-z") << "): omega = " << num(omega[k])
              << " rad/s\n";
  return 0;
}
