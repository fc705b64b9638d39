// make_fe_mesh: writes small FE models (nodes, stiffness and mass matrices in
// Matrix Market) for mbgc-reduce's tests and examples — the "FE program" the
// reduction reads. It shares no code with mbgc-reduce.
//
//   make_fe_mesh beam DIR L rho E nu width_y height_z elements
//       A straight bar along x from 0 to L of 3-D Euler–Bernoulli frame
//       elements (6 DOFs per node; node IDs 1 .. elements + 1).
//   make_fe_mesh ladder DIR rho E nu width_y height_z length half_track x_front x_rear element
//       A vehicle's ladder frame of frame elements (6 DOFs per node): two
//       rails along x from -length/2 to length/2 at y = +-half_track, and
//       cross members at both ends, at x_front, at x_rear and at x = 0;
//       elements of about `element` m. The suspension mounts are the rails'
//       nodes at x_front and x_rear: their IDs in DIR/fl.txt, fr.txt, rl.txt,
//       rr.txt (l: y > 0).
//   make_fe_mesh solid DIR L rho E nu width_y height_z nx ny nz
//       The box [0, L] x [-width_y/2, width_y/2] x [-height_z/2, height_z/2]
//       of nx x ny x nz 20-node brick elements (serendipity, 3 x 3 x 3 Gauss
//       points; 3 DOFs per node), and its end faces as node sets
//       DIR/root.txt (x = 0) and DIR/tip.txt (x = L).
//
// Each writes DIR/nodes.txt, DIR/K.mtx, DIR/M.mtx.
//
// Frame element: axial and torsion linear, bending Hermite cubic; consistent
// mass of the translations (no rotary inertia of bending, as an
// Euler–Bernoulli beam) and of torsion (rho Ip).
#if defined(__GNUC__) && !defined(__clang__)  // a false warning of GCC's inside Eigen
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <Eigen/Dense>
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace {

[[noreturn]] void usage(const std::string& message) {
  std::cerr << "make_fe_mesh: " << message << "\n"
            << "usage: make_fe_mesh beam DIR L rho E nu width_y height_z elements\n"
            << "       make_fe_mesh solid DIR L rho E nu width_y height_z nx ny nz\n"
            << "       make_fe_mesh ladder DIR rho E nu width_y height_z length half_track x_front x_rear element\n";
  std::exit(2);
}

double number(const char* text, const char* what, double lowest) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text, &end);
  if (end == text || *end != '\0' || errno == ERANGE || !std::isfinite(v) || v < lowest)
    usage(std::string(what) + " must be a number >= " + std::to_string(lowest) + ", got `" + text + "`");
  return v;
}

int count(const char* text, const char* what) {
  const double v = number(text, what, 1);
  if (v != std::floor(v) || v > 1e6) usage(std::string(what) + " must be a whole number 1..1e6");
  return static_cast<int>(v);
}

struct Section {
  double area, iy, iz, torsion, polar;  // m^2, m^4 (Iy about y: bending in x-z), J, Ip
};

Section rectangle(double width_y, double height_z) {
  Section s;
  s.area = width_y * height_z;
  s.iy = width_y * std::pow(height_z, 3) / 12;
  s.iz = height_z * std::pow(width_y, 3) / 12;
  s.polar = s.iy + s.iz;
  // Saint-Venant torsion constant of a rectangle a >= b (Roark): a b^3 (1/3 - 0.21 b/a (1 - b^4 / (12 a^4)))
  const double a = std::max(width_y, height_z), b = std::min(width_y, height_z);
  s.torsion = a * b * b * b * (1.0 / 3 - 0.21 * b / a * (1 - std::pow(b / a, 4) / 12));
  return s;
}

struct Material {
  double rho, youngs, shear;
};

struct Entry {
  long row, col;
  double value;
};

// The assembled model.
class Model {
 public:
  explicit Model(int dofs_per_node) : d_(dofs_per_node) {}
  int add_node(const Eigen::Vector3d& x) {
    nodes_.push_back(x);
    return static_cast<int>(nodes_.size()) - 1;
  }
  void add(std::vector<Entry>& m, const std::vector<long>& dofs, const Eigen::MatrixXd& e) {
    for (std::size_t i = 0; i < dofs.size(); ++i)
      for (std::size_t j = 0; j < dofs.size(); ++j)
        if (e(static_cast<long>(i), static_cast<long>(j)) != 0 && dofs[i] >= dofs[j])
          m.push_back({dofs[i], dofs[j], e(static_cast<long>(i), static_cast<long>(j))});
  }
  // An element whose DOFs are `dofs`, with its stiffness and mass matrices.
  void element(const std::vector<long>& dofs, const Eigen::MatrixXd& k, const Eigen::MatrixXd& m) {
    add(k_, dofs, k);
    add(m_, dofs, m);
  }
  // A 3-D frame element between nodes a and b.
  void frame(int a, int b, const Section& s, const Material& mat) {
    const Eigen::Vector3d axis = nodes_[static_cast<std::size_t>(b)] - nodes_[static_cast<std::size_t>(a)];
    const double l = axis.norm();
    const Eigen::Vector3d e1 = axis / l;
    const Eigen::Vector3d ref = std::abs(e1.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d e2 = ref.cross(e1).normalized(), e3 = e1.cross(e2);
    Eigen::Matrix3d r;
    r.row(0) = e1.transpose();
    r.row(1) = e2.transpose();
    r.row(2) = e3.transpose();

    // local DOFs: node a [u1 u2 u3 t1 t2 t3], node b the same
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(12, 12), m = Eigen::MatrixXd::Zero(12, 12);
    auto bar = [&](int dof, double stiffness, double inertia) {
      const int i[2] = {dof, 6 + dof};
      for (int p = 0; p < 2; ++p)
        for (int q = 0; q < 2; ++q) {
          k(i[p], i[q]) += (p == q ? 1 : -1) * stiffness / l;
          m(i[p], i[q]) += (p == q ? 2 : 1) * inertia * l / 6;
        }
    };
    bar(0, mat.youngs * s.area, mat.rho * s.area);
    bar(3, mat.shear * s.torsion, mat.rho * s.polar);
    // Hermite bending on (w_a, w'_a, w_b, w'_b)
    Eigen::Matrix4d kb, mb;
    kb << 12, 6 * l, -12, 6 * l, 6 * l, 4 * l * l, -6 * l, 2 * l * l, -12, -6 * l, 12, -6 * l, 6 * l, 2 * l * l, -6 * l, 4 * l * l;
    mb << 156, 22 * l, 54, -13 * l, 22 * l, 4 * l * l, 13 * l, -3 * l * l, 54, 13 * l, 156, -22 * l, -13 * l, -3 * l * l, -22 * l,
        4 * l * l;
    auto bend = [&](int w, int slope, double sign, double ei) {
      const int i[4] = {w, slope, 6 + w, 6 + slope};
      const double f[4] = {1, sign, 1, sign};  // w' = sign * rotation DOF
      for (int p = 0; p < 4; ++p)
        for (int q = 0; q < 4; ++q) {
          k(i[p], i[q]) += f[p] * f[q] * ei / (l * l * l) * kb(p, q);
          m(i[p], i[q]) += f[p] * f[q] * mat.rho * s.area * l / 420 * mb(p, q);
        }
    };
    bend(1, 5, 1, mat.youngs * s.iz);   // u2 with t3 = +du2/dx
    bend(2, 4, -1, mat.youngs * s.iy);  // u3 with t2 = -du3/dx
    Eigen::MatrixXd t = Eigen::MatrixXd::Zero(12, 12);
    for (int blk = 0; blk < 4; ++blk) t.block<3, 3>(3 * blk, 3 * blk) = r;
    const Eigen::MatrixXd kg = t.transpose() * k * t, mg = t.transpose() * m * t;
    std::vector<long> dofs;
    for (int n : {a, b})
      for (int q = 0; q < 6; ++q) dofs.push_back(static_cast<long>(n) * d_ + q);
    add(k_, dofs, kg);
    add(m_, dofs, mg);
  }
  void write(const std::filesystem::path& dir) const {
    std::filesystem::create_directories(dir);
    std::FILE* f = std::fopen((dir / "nodes.txt").c_str(), "w");
    if (!f) usage("cannot write " + (dir / "nodes.txt").string());
    std::fprintf(f, "# node ID, x, y, z (m); %d DOFs per node in this order\n", d_);
    for (std::size_t n = 0; n < nodes_.size(); ++n)
      std::fprintf(f, "%zu %.17g %.17g %.17g\n", n + 1, nodes_[n].x(), nodes_[n].y(), nodes_[n].z());
    std::fclose(f);
    write_matrix(dir / "K.mtx", k_, "stiffness");
    write_matrix(dir / "M.mtx", m_, "mass");
  }

 private:
  // Sums the element contributions per entry (column by column, as an FE
  // assembly does) and writes the lower triangle.
  void write_matrix(const std::filesystem::path& path, std::vector<Entry> m, const char* what) const {
    std::stable_sort(m.begin(), m.end(), [](const Entry& a, const Entry& b) { return a.col != b.col ? a.col < b.col : a.row < b.row; });
    std::vector<Entry> summed;
    for (const Entry& e : m) {
      if (!summed.empty() && summed.back().row == e.row && summed.back().col == e.col) summed.back().value += e.value;
      else summed.push_back(e);
    }
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (!f) usage("cannot write " + path.string());
    const long n = static_cast<long>(nodes_.size()) * d_;
    std::fprintf(f, "%%%%MatrixMarket matrix coordinate real symmetric\n%% %s matrix, written by make_fe_mesh\n", what);
    std::fprintf(f, "%ld %ld %zu\n", n, n, summed.size());
    for (const Entry& e : summed) std::fprintf(f, "%ld %ld %.17g\n", e.row + 1, e.col + 1, e.value);
    std::fclose(f);
  }
  int d_;
  std::vector<Eigen::Vector3d> nodes_;
  std::vector<Entry> k_, m_;  // lower triangle (row >= column), one per element contribution
};

// The 20-node serendipity brick on [-1, 1]^3: its nodes' natural
// coordinates (8 corners, then the 12 edge midpoints) and shape functions.
struct Hex20 {
  std::array<Eigen::Vector3d, 20> node;
  Hex20() {
    int k = 0;
    for (int c = 0; c < 8; ++c) node[static_cast<std::size_t>(k++)] = {c & 1 ? 1.0 : -1.0, c & 2 ? 1.0 : -1.0, c & 4 ? 1.0 : -1.0};
    for (int axis = 0; axis < 3; ++axis)
      for (int c = 0; c < 4; ++c) {
        Eigen::Vector3d p;
        p(axis) = 0;
        p((axis + 1) % 3) = c & 1 ? 1.0 : -1.0;
        p((axis + 2) % 3) = c & 2 ? 1.0 : -1.0;
        node[static_cast<std::size_t>(k++)] = p;
      }
  }
  // N (20) and dN/d(xi, eta, zeta) (20 x 3) at x.
  void eval(const Eigen::Vector3d& x, Eigen::VectorXd& n, Eigen::MatrixXd& dn) const {
    n.resize(20);
    dn.resize(20, 3);
    for (int i = 0; i < 20; ++i) {
      const Eigen::Vector3d& p = node[static_cast<std::size_t>(i)];
      if (i < 8) {
        const Eigen::Vector3d f = (Eigen::Vector3d::Ones() + x.cwiseProduct(p));  // 1 + x_a p_a
        const double s = x.dot(p) - 2;
        n(i) = f.prod() * s / 8;
        for (int a = 0; a < 3; ++a) dn(i, a) = p(a) * f((a + 1) % 3) * f((a + 2) % 3) * (2 * x(a) * p(a) + x((a + 1) % 3) * p((a + 1) % 3) + x((a + 2) % 3) * p((a + 2) % 3) - 1) / 8;
      } else {
        int axis = 0;
        while (p(axis) != 0) ++axis;
        const int b = (axis + 1) % 3, c = (axis + 2) % 3;
        const double g = 1 - x(axis) * x(axis), fb = 1 + x(b) * p(b), fc = 1 + x(c) * p(c);
        n(i) = g * fb * fc / 4;
        dn(i, axis) = -2 * x(axis) * fb * fc / 4;
        dn(i, b) = g * p(b) * fc / 4;
        dn(i, c) = g * fb * p(c) / 4;
      }
    }
  }
};

void solid(const std::filesystem::path& dir, double length, double rho, double youngs, double nu, double width_y, double height_z,
           int nx, int ny, int nz) {
  const Hex20 hex;
  const Eigen::Vector3d size(length / nx, width_y / ny, height_z / nz);  // one element
  const Eigen::Vector3d half = size / 2;
  const double det = half.prod();

  // Element matrices (all elements are the same box): 3 x 3 x 3 Gauss.
  const double g = std::sqrt(0.6), gw[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9}, gx[3] = {-g, 0, g};
  const double lambda = youngs * nu / ((1 + nu) * (1 - 2 * nu)), mu = youngs / (2 * (1 + nu));
  Eigen::Matrix<double, 6, 6> d = Eigen::Matrix<double, 6, 6>::Zero();
  d.topLeftCorner<3, 3>().setConstant(lambda);
  d.topLeftCorner<3, 3>().diagonal().array() += 2 * mu;
  d.bottomRightCorner<3, 3>().diagonal().setConstant(mu);
  Eigen::MatrixXd ke = Eigen::MatrixXd::Zero(60, 60), mscalar = Eigen::MatrixXd::Zero(20, 20);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) {
        Eigen::VectorXd n;
        Eigen::MatrixXd dn;
        hex.eval({gx[i], gx[j], gx[k]}, n, dn);
        const double w = gw[i] * gw[j] * gw[k] * det;
        Eigen::MatrixXd bm = Eigen::MatrixXd::Zero(6, 60);  // strains: xx yy zz, then engineering yz zx xy
        for (int a = 0; a < 20; ++a) {
          const Eigen::Vector3d grad = dn.row(a).transpose().cwiseQuotient(half);
          for (int c = 0; c < 3; ++c) bm(c, 3 * a + c) = grad(c);
          bm(3, 3 * a + 1) = grad(2), bm(3, 3 * a + 2) = grad(1);
          bm(4, 3 * a + 2) = grad(0), bm(4, 3 * a + 0) = grad(2);
          bm(5, 3 * a + 0) = grad(1), bm(5, 3 * a + 1) = grad(0);
        }
        ke += bm.transpose() * d * bm * w;
        mscalar += rho * n * n.transpose() * w;
      }
  Eigen::MatrixXd me = Eigen::MatrixXd::Zero(60, 60);  // M_s (x) I_3
  for (int a = 0; a < 20; ++a)
    for (int b = 0; b < 20; ++b)
      for (int c = 0; c < 3; ++c) me(3 * a + c, 3 * b + c) = mscalar(a, b);

  // Nodes on the half-step grid: corners (all indices even) and edge
  // midpoints (exactly one odd).
  const int gxn = 2 * nx + 1, gyn = 2 * ny + 1, gzn = 2 * nz + 1;
  std::vector<int> id(static_cast<std::size_t>(gxn) * gyn * gzn, -1);
  Model model(3);
  std::vector<int> root, tip;
  for (int ix = 0; ix < gxn; ++ix)
    for (int iy = 0; iy < gyn; ++iy)
      for (int iz = 0; iz < gzn; ++iz) {
        if ((ix & 1) + (iy & 1) + (iz & 1) > 1) continue;
        const int n = model.add_node({length * ix / (2.0 * nx), width_y * (iy / (2.0 * ny) - 0.5), height_z * (iz / (2.0 * nz) - 0.5)});
        id[(static_cast<std::size_t>(ix) * gyn + iy) * gzn + iz] = n;
        if (ix == 0) root.push_back(n + 1);
        if (ix == gxn - 1) tip.push_back(n + 1);
      }
  for (int ex = 0; ex < nx; ++ex)
    for (int ey = 0; ey < ny; ++ey)
      for (int ez = 0; ez < nz; ++ez) {
        std::vector<long> dofs;
        for (const Eigen::Vector3d& p : hex.node) {
          const int ix = 2 * ex + 1 + static_cast<int>(p.x()), iy = 2 * ey + 1 + static_cast<int>(p.y()), iz = 2 * ez + 1 + static_cast<int>(p.z());
          const int n = id[(static_cast<std::size_t>(ix) * gyn + iy) * gzn + iz];
          for (int c = 0; c < 3; ++c) dofs.push_back(3L * n + c);
        }
        model.element(dofs, ke, me);
      }
  model.write(dir);
  for (const auto& [name, set] : {std::pair<const char*, const std::vector<int>&>{"root.txt", root}, {"tip.txt", tip}}) {
    std::FILE* f = std::fopen((dir / name).c_str(), "w");
    if (!f) usage(std::string("cannot write ") + (dir / name).string());
    for (std::size_t i = 0; i < set.size(); ++i) std::fprintf(f, "%d%s", set[i], i + 1 < set.size() ? "\n" : "\n");
    std::fclose(f);
  }
}

/// The ladder frame (see the header). Nodes are shared where members meet.
void ladder(const std::filesystem::path& dir, double rho, double youngs, double nu, double width_y, double height_z,
            double length, double half_track, double x_front, double x_rear, double element) {
  if (!(x_front < length / 2 && x_front > 0 && x_rear > -length / 2 && x_rear < 0))
    usage("ladder: x_front must lie in (0, length/2) and x_rear in (-length/2, 0)");
  Model model(6);
  const Section s = rectangle(width_y, height_z);
  const Material mat{rho, youngs, youngs / (2 * (1 + nu))};
  // stations along the rails: the ends, the cross members and the mounts, then filled to `element`
  std::vector<double> stations = {-length / 2, x_rear, 0, x_front, length / 2};
  std::vector<double> xs;
  for (std::size_t k = 0; k + 1 < stations.size(); ++k) {
    const int n = std::max(1, static_cast<int>(std::ceil((stations[k + 1] - stations[k]) / element)));
    for (int i = 0; i < n; ++i) xs.push_back(stations[k] + (stations[k + 1] - stations[k]) * i / n);
  }
  xs.push_back(length / 2);
  std::vector<int> rail[2];
  for (int side = 0; side < 2; ++side)
    for (double x : xs) rail[side].push_back(model.add_node({x, side == 0 ? half_track : -half_track, 0}));
  for (int side = 0; side < 2; ++side)
    for (std::size_t i = 0; i + 1 < xs.size(); ++i) model.frame(rail[side][i], rail[side][i + 1], s, mat);
  auto index_of = [&](double x) {
    std::size_t best = 0;
    for (std::size_t i = 0; i < xs.size(); ++i)
      if (std::abs(xs[i] - x) < std::abs(xs[best] - x)) best = i;
    return best;
  };
  // cross members between the rails' nodes at the stations, elements of about `element`
  for (double x : stations) {
    const std::size_t i = index_of(x);
    const int n = std::max(1, static_cast<int>(std::ceil(2 * half_track / element)));
    int previous = rail[0][i];
    for (int k = 1; k <= n; ++k) {
      const int node = k == n ? rail[1][i] : model.add_node({xs[i], half_track - 2 * half_track * k / n, 0});
      model.frame(previous, node, s, mat);
      previous = node;
    }
  }
  model.write(dir);
  const struct {
    const char* file;
    int side;
    double x;
  } mounts[] = {{"fl.txt", 0, x_front}, {"fr.txt", 1, x_front}, {"rl.txt", 0, x_rear}, {"rr.txt", 1, x_rear}};
  for (const auto& m : mounts) {
    std::FILE* f = std::fopen((dir / m.file).c_str(), "w");
    if (!f) usage(std::string("cannot write ") + (dir / m.file).string());
    std::fprintf(f, "%d\n", rail[m.side][index_of(m.x)] + 1);
    std::fclose(f);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) usage("which model? beam");
  const std::string kind = argv[1];
  if (kind == "beam") {
    if (argc != 10) usage("beam takes 8 arguments");
    const std::filesystem::path dir = argv[2];
    const double length = number(argv[3], "L", 1e-12), rho = number(argv[4], "rho", 1e-12), e = number(argv[5], "E", 1e-12);
    const double nu = number(argv[6], "nu", 0);
    const Section s = rectangle(number(argv[7], "width_y", 1e-12), number(argv[8], "height_z", 1e-12));
    const int elements = count(argv[9], "elements");
    Model model(6);
    for (int i = 0; i <= elements; ++i) model.add_node({length * i / elements, 0, 0});
    for (int i = 0; i < elements; ++i) model.frame(i, i + 1, s, {rho, e, e / (2 * (1 + nu))});
    model.write(dir);
    return 0;
  }
  if (kind == "ladder") {
    if (argc != 13) usage("ladder takes 11 arguments");
    ladder(argv[2], number(argv[3], "rho", 1e-12), number(argv[4], "E", 1e-12), number(argv[5], "nu", 0),
           number(argv[6], "width_y", 1e-12), number(argv[7], "height_z", 1e-12), number(argv[8], "length", 1e-12),
           number(argv[9], "half_track", 1e-12), number(argv[10], "x_front", 1e-12), std::strtod(argv[11], nullptr),
           number(argv[12], "element", 1e-12));
    return 0;
  }
  if (kind == "solid") {
    if (argc != 12) usage("solid takes 10 arguments");
    solid(argv[2], number(argv[3], "L", 1e-12), number(argv[4], "rho", 1e-12), number(argv[5], "E", 1e-12),
          number(argv[6], "nu", 0), number(argv[7], "width_y", 1e-12), number(argv[8], "height_z", 1e-12),
          count(argv[9], "nx"), count(argv[10], "ny"), count(argv[11], "nz"));
    return 0;
  }
  usage("unknown model `" + kind + "`");
}
