// multibody/beam.cpp — the built-in beam: modal integrals, M(eta), points and limits.
#include "multibody/beam.hpp"
#include "multibody/drawing.hpp"
#include "multibody/model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <ranges>
#include <tuple>

#include <fmt/format.h>

namespace mbgc::multibody::detail {

using namespace mbgc::ir;

namespace {
/// Saint-Venant torsion constant: the polar moment for circle and tube (exact);
/// a rectangle a x b, a >= b: a b^3 (1/3 - 0.21 (b/a) (1 - b^4 / (12 a^4))) (Roark, within 0.5 %).
E torsion_constant(const Build& B, const AstExpr& section, const BeamSym& n) {
  if (section.name != "rectangle") return B.ref(n.Ip());
  E a = B.call("max", {term(section.args[0]), term(section.args[1])}), b = B.call("min", {term(section.args[0]), term(section.args[1])});
  auto pw = [&](E x, double k) { return B.op('^', x, B.num(k)); };
  E bracket = B.op('-', B.num(1.0 / 3.0),
                   B.op('*', B.op('*', B.num(0.21), B.op('/', b, a)), B.op('-', B.num(1), B.op('/', pw(b, 4), B.op('*', B.num(12), pw(a, 4))))));
  return B.op('*', B.op('*', a, pw(b, 3)), bracket);
}
}  // namespace

std::map<std::string, std::array<double, 3>> Beam::points() const {
  std::map<std::string, std::array<double, 3>> out;
  for (const auto& [name, x] : point_x) out[name] = {x - origin_m, 0, 0};
  return out;
}

Eta Beam::split(const std::function<E(int)>& eta) const {
  const Beam& beam = *this;
  Eta out;
  for (int i = 0; i < (beam.y ? beam.y->count() : 0); ++i) out.y.push_back(eta(i));
  for (int i = 0; i < (beam.z ? beam.z->count() : 0); ++i) out.z.push_back(eta(beam.offset_z() + i));
  for (int i = 0; i < (beam.axial ? beam.axial->count() : 0); ++i) out.axial.push_back(eta(beam.offset_axial() + i));
  for (int i = 0; i < (beam.torsion ? beam.torsion->count() : 0); ++i) out.torsion.push_back(eta(beam.offset_torsion() + i));
  return out;
}

/// s(eta) = int u dm: the first moment about the frame origin, body axes.
E Beam::first_moment(const Build& B, const FlexibleSym& body, const Eta& eta) const {
  const Beam& beam = *this;
  const BeamSym n(body);
  E sx = B.op('*', B.ref(n.mass()), B.op('/', B.ref(n.length()), B.num(2)));
  if (beam.origin_m != 0) sx = B.op('*', B.ref(n.mass()), B.op('-', B.op('/', B.ref(n.length()), B.num(2)), B.num(beam.origin_m)));
  if (beam.tisserand) sx = B.num(0);  // the origin is the mass centre
  if (beam.geometric_stiffness && !beam.tisserand) {  // Tisserand: the foreshortening moves no mass
    E shortening = B.op('+', quadratic(B, n.group('y').load(), eta.y, eta.y), quadratic(B, n.group('z').load(), eta.z, eta.z));
    sx = B.op('-', sx, B.op('*', B.num(0.5), shortening));
  }
  if (!eta.axial.empty() && !beam.mean_axes) sx = B.op('+', sx, vec_dot(B, n.group('a').mean(), eta.axial));
  std::vector<E> sy, sz;  // int phi dm eta: zero in mean axes
  for (std::size_t i = 0; i < eta.y.size() && !beam.mean_axes; ++i) sy.push_back(B.op('*', B.at(B.ref(n.group('y').mean()), static_cast<int>(i) + 1), eta.y[i]));
  for (std::size_t i = 0; i < eta.z.size() && !beam.mean_axes; ++i) sz.push_back(B.op('*', B.at(B.ref(n.group('z').mean()), static_cast<int>(i) + 1), eta.z[i]));
  return B.list({sx, sum_of(B, sy), sum_of(B, sz)});
}

/// d s / d eta (3 x n): the translational coupling M_V,eta, rows of scalars.
Rows Beam::translation_coupling(const Build& B, const FlexibleSym& body, const Eta& eta) const {
  const Beam& beam = *this;
  const BeamSym n(body);
  const int ny = static_cast<int>(eta.y.size()), nz = static_cast<int>(eta.z.size());
  std::vector<std::vector<E>> m(3, std::vector<E>(static_cast<std::size_t>(beam.count()), B.num(0)));
  for (int i = 0; i < static_cast<int>(eta.axial.size()) && !beam.mean_axes; ++i)
    m[0][static_cast<std::size_t>(beam.offset_axial() + i)] = B.at(B.ref(n.group('a').mean()), i + 1);
  for (int i = 0; i < ny; ++i) {
    if (beam.geometric_stiffness && !beam.tisserand) m[0][static_cast<std::size_t>(i)] = B.neg(row_dot(B, n.group('y').load(), i, eta.y));
    if (!beam.mean_axes) m[1][static_cast<std::size_t>(i)] = B.at(B.ref(n.group('y').mean()), i + 1);
  }
  for (int i = 0; i < nz; ++i) {
    if (beam.geometric_stiffness && !beam.tisserand) m[0][static_cast<std::size_t>(ny + i)] = B.neg(row_dot(B, n.group('z').load(), i, eta.z));
    if (!beam.mean_axes) m[2][static_cast<std::size_t>(ny + i)] = B.at(B.ref(n.group('z').mean()), i + 1);
  }
  return m;
}

/// The generalised mass matrix M(eta), (6 + n) x (6 + n), as rows of scalars.
Rows Beam::mass_matrix(const Build& B, const FlexibleSym& body, const Eta& eta) const {
  const Beam& beam = *this;
  const BeamSym n(body);
  const std::size_t ne = static_cast<std::size_t>(beam.count()), N = 6 + ne, ny = eta.y.size();
  std::vector<std::vector<E>> M(N, std::vector<E>(N, B.num(0)));
  E zero = B.num(0);
  E m = B.ref(n.mass());
  for (int k = 0; k < 3; ++k) M[k][k] = m;
  put_first_moment(B, M, first_moment(B, n, eta));
  // omega-omega: J(eta) = J0 + J1(eta) + J2(eta)
  E qy = quadratic(B, n.group('y').mass(), eta.y, eta.y), qz = quadratic(B, n.group('z').mass(), eta.z, eta.z);
  E qyz = quadratic(B, n.cross_mass('y', 'z'), eta.y, eta.z);
  E spin = beam.geometric_stiffness ? B.op('+', quadratic(B, n.group('y').spin(), eta.y, eta.y), quadratic(B, n.group('z').spin(), eta.z, eta.z))
                                    : zero;
  E dy = zero, dz = zero;
  for (std::size_t i = 0; i < eta.y.size() && !beam.mean_axes; ++i) dy = B.op('+', dy, B.op('*', B.at(B.ref(n.group('y').moment()), static_cast<int>(i) + 1), eta.y[i]));
  for (std::size_t i = 0; i < eta.z.size() && !beam.mean_axes; ++i) dz = B.op('+', dz, B.op('*', B.at(B.ref(n.group('z').moment()), static_cast<int>(i) + 1), eta.z[i]));
  E J0 = B.ref(n.J0());
  M[3][3] = B.op('+', idx2(B, J0, 1, 1), B.op('+', qy, qz));
  M[4][4] = B.op('+', idx2(B, J0, 2, 2), B.op('-', qz, spin));
  M[5][5] = B.op('+', idx2(B, J0, 3, 3), B.op('-', qy, spin));
  M[3][4] = M[4][3] = B.neg(dy);
  M[3][5] = M[5][3] = B.neg(dz);
  M[4][5] = M[5][4] = B.neg(qyz);
  // V-eta and omega-eta couplings, and the modal mass
  auto tc = translation_coupling(B, n, eta);
  for (std::size_t r = 0; r < 3; ++r)
    for (std::size_t c = 0; c < ne; ++c) M[r][6 + c] = M[6 + c][r] = tc[r][c];
  for (std::size_t j = 0; j < eta.y.size(); ++j) {
    E cx = B.neg(row_dot(B, n.cross_mass('y', 'z'), static_cast<int>(j), eta.z));
    M[3][6 + j] = M[6 + j][3] = cx;
    if (!beam.mean_axes) M[5][6 + j] = M[6 + j][5] = B.at(B.ref(n.group('y').moment()), static_cast<int>(j) + 1);
  }
  for (std::size_t j = 0; j < eta.z.size(); ++j) {
    E cx = row_dot(B, n.cross_mass('y', 'z'), static_cast<int>(j), eta.y, /*transposed=*/true);
    M[3][6 + ny + j] = M[6 + ny + j][3] = cx;
    if (!beam.mean_axes) M[4][6 + ny + j] = M[6 + ny + j][4] = B.neg(B.at(B.ref(n.group('z').moment()), static_cast<int>(j) + 1));
  }
  for (std::size_t i = 0; i < eta.y.size(); ++i)
    for (std::size_t j = 0; j < eta.y.size(); ++j) M[6 + i][6 + j] = idx2(B, B.ref(n.group('y').mass()), static_cast<int>(i) + 1, static_cast<int>(j) + 1);
  for (std::size_t i = 0; i < eta.z.size(); ++i)
    for (std::size_t j = 0; j < eta.z.size(); ++j)
      M[6 + ny + i][6 + ny + j] = idx2(B, B.ref(n.group('z').mass()), static_cast<int>(i) + 1, static_cast<int>(j) + 1);
  add_stretch_and_twist(B, n, eta, M);
  return M;
}

/// Axial and torsion modes in M(eta): the linear fields u = [chi zeta, 0, 0]
/// (stretch) and a section turned by psi theta about x (twist), with the
/// inertia invariants of docs/modal_format.md. Stretch changes J_yy, J_zz
/// by 2 int x u dm + int u^2 dm, couples with bending through int u w dm,
/// and with omega through int r x u' dm; twist couples with omega_x through
/// the sections' polar inertia and turns a non-circular section's
/// principal axes (J_yz). Its second-order inertia terms are left out: a
/// linearised rotation field gets them wrong.
void Beam::add_stretch_and_twist(const Build& B, const BeamSym& n, const Eta& eta, Rows& M) const {
  const Beam& beam = *this;
  const std::size_t ny = eta.y.size(), nz = eta.z.size();
  const auto oa = static_cast<std::size_t>(6 + beam.offset_axial()), ot = static_cast<std::size_t>(6 + beam.offset_torsion());
  auto plus = [&](E a, E b) { return B.op('+', a, b); };
  auto minus = [&](E a, E b) { return B.op('-', a, b); };
  if (!eta.axial.empty()) {
    E stretch = plus(B.op('*', B.num(2), vec_dot(B, n.group('a').moment(), eta.axial)), quadratic(B, n.group('a').mass(), eta.axial, eta.axial));
    M[4][4] = plus(M[4][4], stretch);
    M[5][5] = plus(M[5][5], stretch);
    if (ny) M[3][4] = M[4][3] = minus(M[3][4], quadratic(B, n.cross_mass('a', 'y'), eta.axial, eta.y));
    if (nz) M[3][5] = M[5][3] = minus(M[3][5], quadratic(B, n.cross_mass('a', 'z'), eta.axial, eta.z));
    for (std::size_t k = 0; k < eta.axial.size(); ++k) {
      // omega - stretch rate: int r x [chi, 0, 0] dm = [0, int w_z chi, -int w_y chi]
      if (nz) M[4][oa + k] = M[oa + k][4] = row_dot(B, n.cross_mass('a', 'z'), static_cast<int>(k), eta.z);
      if (ny) M[5][oa + k] = M[oa + k][5] = B.neg(row_dot(B, n.cross_mass('a', 'y'), static_cast<int>(k), eta.y));
      for (std::size_t l = 0; l < eta.axial.size(); ++l)
        M[oa + k][oa + l] = idx2(B, B.ref(n.group('a').mass()), static_cast<int>(k) + 1, static_cast<int>(l) + 1);
    }
    // omega - bending rate, through the stretched position: [u, 0, 0] x phi
    for (std::size_t l = 0; l < ny; ++l)
      M[5][6 + l] = M[6 + l][5] = plus(M[5][6 + l], row_dot(B, n.cross_mass('a', 'y'), static_cast<int>(l), eta.axial, /*transposed=*/true));
    for (std::size_t l = 0; l < nz; ++l)
      M[4][6 + ny + l] = M[6 + ny + l][4] = minus(M[4][6 + ny + l], row_dot(B, n.cross_mass('a', 'z'), static_cast<int>(l), eta.axial, /*transposed=*/true));
  }
  if (!eta.torsion.empty()) {
    M[4][5] = M[5][4] = minus(M[4][5], vec_dot(B, n.group('t').product(), eta.torsion));
    for (std::size_t k = 0; k < eta.torsion.size(); ++k) {
      M[3][ot + k] = M[ot + k][3] = B.at(B.ref(n.group('t').mean()), static_cast<int>(k) + 1);
      for (std::size_t l = 0; l < eta.torsion.size(); ++l)
        M[ot + k][ot + l] = idx2(B, B.ref(n.group('t').mass()), static_cast<int>(k) + 1, static_cast<int>(l) + 1);
    }
  }
}

/// Parameters of stretch and twist: the rod modes' integrals times mu (stretch) or the sections' rho Ip (twist).
void Beam::rod_params(const FieldParams& fp) const {
  const Build& B = fp.B;
  const AstBody& d = fp.decl;
  const BeamSym n(d.name);
  const Beam& beam = *this;
  E damping = body_term(d, beam_setting::damping), mu = B.ref(n.mass_per_length()), rho = B.ref(n.density());
  if (beam.axial) {
    const flex::RodIntegrals I = flex::rod_integrals(*beam.axial);
    const BeamModesSym a = n.group('a');
    fp.param(a.mean(), B.op('*', mu, vector_param(B, I.mean)));
    fp.param(a.moment(), B.op('*', mu, vector_param(B, I.moment)));
    fp.param(a.mass(), B.op('*', mu, matrix_param(B, I.mass)));
    fp.param(a.stiffness(), B.op('*', B.op('*', B.ref(n.youngs_modulus()), B.ref(n.area())), matrix_param(B, I.stiffness)));
    fp.param(a.damping(), modal_damping(B, damping, beam.axial->count(), a.stiffness(), a.mass()));
    if (beam.y) fp.param(n.cross_mass('a', 'y'), B.op('*', mu, matrix_param(B, flex::cross_mass(*beam.axial, *beam.y))));
    if (beam.z) fp.param(n.cross_mass('a', 'z'), B.op('*', mu, matrix_param(B, flex::cross_mass(*beam.axial, *beam.z))));
  }
  if (beam.torsion) {
    const flex::RodIntegrals I = flex::rod_integrals(*beam.torsion);
    const BeamModesSym t = n.group('t');
    fp.param(n.shear_modulus(), body_term(d, beam_setting::G));
    fp.param(n.Ip(), B.op('+', B.ref(n.Iy()), B.ref(n.Iz())));  // polar moment of the section
    if (E J = body_term(d, beam_setting::torsion_constant)) fp.param(n.torsion_constant(), J);
    else fp.param(n.torsion_constant(), torsion_constant(B, *attr(d, beam_setting::section), n));
    E rhoIp = B.op('*', rho, B.ref(n.Ip()));
    fp.param(t.mean(), B.op('*', rhoIp, vector_param(B, I.mean)));
    fp.param(t.mass(), B.op('*', rhoIp, matrix_param(B, I.mass)));
    // a twisted section turns its principal axes: J_yz changes by -rho (Iz - Iy) theta per length
    fp.param(t.product(), B.op('*', B.op('*', rho, B.op('-', B.ref(n.Iz()), B.ref(n.Iy()))), vector_param(B, I.mean)));
    fp.param(t.stiffness(), B.op('*', B.op('*', B.ref(n.shear_modulus()), B.ref(n.torsion_constant())), matrix_param(B, I.stiffness)));
    fp.param(t.damping(), modal_damping(B, damping, beam.torsion->count(), t.stiffness(), t.mass()));
  }
}


/// Parameters of a beam: section, material and the modal integrals (constants).
void Beam::params(const FieldParams& fp) const {
  const Build& B = fp.B;
  const AstBody& d = fp.decl;
  const BeamSym n(d.name);
  const Beam& beam = *this;
  fp.param(n.length(), B.num(beam.length_m));
  fp.param(n.density(), body_term(d, beam_setting::density));
  fp.param(n.youngs_modulus(), body_term(d, beam_setting::E));
  if (E sec = body_term(d, beam_setting::section)) {
    const std::string& kind = sec->name;
    E a = sec->args[0], b = sec->args.size() > 1 ? sec->args[1] : nullptr;
    auto pw = [&](E x, double k) { return B.op('^', x, B.num(k)); };
    E pi = B.ref(Sym::pi());
    if (kind == "rectangle") {  // width along y, height along z
      fp.param(n.area(), B.op('*', a, b));
      fp.param(n.Iy(), B.op('/', B.op('*', a, pw(b, 3)), B.num(12)));
      fp.param(n.Iz(), B.op('/', B.op('*', b, pw(a, 3)), B.num(12)));
    } else if (kind == "circle") {
      fp.param(n.area(), B.op('/', B.op('*', pi, pw(a, 2)), B.num(4)));
      fp.param(n.Iy(), B.op('/', B.op('*', pi, pw(a, 4)), B.num(64)));
      fp.param(n.Iz(), B.ref(n.Iy()));
    } else {  // tube(outer, inner)
      fp.param(n.area(), B.op('/', B.op('*', pi, B.op('-', pw(a, 2), pw(b, 2))), B.num(4)));
      fp.param(n.Iy(), B.op('/', B.op('*', pi, B.op('-', pw(a, 4), pw(b, 4))), B.num(64)));
      fp.param(n.Iz(), B.ref(n.Iy()));
    }
  } else {
    fp.param(n.area(), body_term(d, beam_setting::area));
    fp.param(n.Iy(), body_term(d, beam_setting::Iy));
    fp.param(n.Iz(), body_term(d, beam_setting::Iz));
  }
  E rho = B.ref(n.density()), L = B.ref(n.length()), mu = B.ref(n.mass_per_length());
  fp.param(n.mass_per_length(), B.op('*', rho, B.ref(n.area())));  // kg/m
  fp.param(n.mass(), B.op('*', mu, L));
  // about the frame origin, undeformed: the line's x^2 moment plus the sections' own inertia
  E line = B.op('/', B.op('*', mu, B.op('^', L, B.num(3))), B.num(3));
  if (beam.origin_m != 0) {  // int s^2 mu ds over [-c, L - c]
    const double c = beam.origin_m, hi = beam.length_m - c;
    line = B.op('*', mu, B.num((hi * hi * hi + c * c * c) / 3));
  }
  E Iy = B.op('*', B.op('*', rho, L), B.ref(n.Iy())), Iz = B.op('*', B.op('*', rho, L), B.ref(n.Iz()));
  fp.param(n.J0(), B.call("diag", {B.op('+', Iy, Iz), B.op('+', line, Iy), B.op('+', line, Iz)}));
  // what the joints' code reads of every body: the reference point is the frame origin
  fp.param(n.com(), B.vec(0, 0, 0));
  fp.param(n.inertia(), B.ref(n.J0()));
  E damping = body_term(d, beam_setting::damping);
  for (const auto& [plane, modes] : {std::pair{'y', &beam.y}, std::pair{'z', &beam.z}}) {
    if (!*modes) continue;
    const flex::ModalIntegrals I = flex::modal_integrals(**modes);
    const BeamModesSym p = n.group(plane);
    E EI = B.op('*', B.ref(n.youngs_modulus()), B.ref(plane == 'y' ? n.Iz() : n.Iy()));  // deflection along y bends about z
    if (beam.mean_axes) {
      // what the mean axes remove, and how small it is for these modes (per unit mass and length)
      double largest = 0;
      for (double x : I.mean) largest = std::max(largest, std::abs(x) / beam.length_m);
      for (double x : I.moment) largest = std::max(largest, std::abs(x) / (beam.length_m * beam.length_m));
      fp.diags.note(d.loc, fmt::format("beam `{}` in mean axes (frame = {}): its free-free modes along body {} are "
                                     "orthogonal to the rigid motions (int phi dm and int x phi dm are {:.1e} of m L "
                                     "and m L^2), so the compiler leaves the translational coupling `{}` and the "
                                     "rotational coupling `{}` out of the mass matrix",
                                     d.name, beam.tisserand ? "tisserand" : "buckens", plane, largest, p.mean().str(),
                                     p.moment().str()));
      if (beam.tisserand)
        fp.diags.note(d.loc, fmt::format("beam `{}` in Tisserand's frame: its origin is the mass centre (x = {} m along "
                                       "the beam), the foreshortening of bending is measured from its mean so it moves "
                                       "no mass (thesis eq. 5.30), and int phi x phi dm is zero for one bending plane "
                                       "(5.34): the axial-acceleration coupling `{}` drops out too, and the frame's "
                                       "translation decouples from rotation and modes (eqs. 5.35-5.38)",
                                       d.name, beam.origin_m, p.load().str()));
    } else {
      fp.param(p.mean(), B.op('*', mu, vector_param(B, I.mean)));
      fp.param(p.moment(), B.op('*', mu, vector_param(B, I.moment)));
    }
    fp.param(p.mass(), B.op('*', mu, matrix_param(B, I.mass)));
    fp.param(p.stiffness(), B.op('*', EI, matrix_param(B, I.bending)));
    if (beam.geometric_stiffness) {
      if (!beam.tisserand) fp.param(p.load(), B.op('*', mu, matrix_param(B, I.load)));
      fp.param(p.spin(), B.op('*', mu, matrix_param(B, I.spin)));
    }
    fp.param(p.damping(), modal_damping(B, damping, (*modes)->count(), p.stiffness(), p.mass()));
  }
  if (beam.origin_m != 0 && !beam.tisserand)
    fp.diags.note(d.loc, fmt::format("beam `{}` with its frame at the mass centre (frame = centre, x = {} m along the beam): "
                                   "its free-free modes are measured from the section there (each mode's rigid motion "
                                   "phi(c) + phi'(c) (x - c) subtracted), so no coupling term drops out of the mass matrix",
                                   d.name, beam.origin_m));
  if (beam.y && beam.z) fp.param(n.cross_mass('y', 'z'), B.op('*', mu, matrix_param(B, flex::cross_mass(*beam.y, *beam.z))));
  rod_params(fp);
  for (const auto& [pt, x] : beam.point_x) {
    for (const auto& [plane, modes] : {std::pair{'y', &beam.y}, std::pair{'z', &beam.z}}) {
      if (!*modes) continue;
      // (rounding left where a mode is exactly zero, at a clamped root, is
      // snapped to the zero it is, so that it folds out of the equations)
      const double L = beam.length_m;
      auto clean = [](double v, double scale) { return std::abs(v) <= 1e-12 * scale ? 0.0 : v; };
      std::vector<double> phi, slope;
      for (int i = 0; i < (*modes)->count(); ++i)
        phi.push_back(clean((*modes)->shape(i, x), 1.0)), slope.push_back(clean((*modes)->shape(i, x, 1), 1.0 / L));
      fp.param(n.shape(pt, plane), vector_param(B, phi));
      fp.param(n.slope(pt, plane), vector_param(B, slope));
      if (beam.geometric_stiffness) fp.param(n.shortening(pt, plane), matrix_param(B, flex::axial_up_to(**modes, x)));
    }
    for (const auto& [group, modes] : {std::pair{'a', &beam.axial}, std::pair{'t', &beam.torsion}}) {
      if (!*modes) continue;
      std::vector<double> chi;
      for (int i = 0; i < (*modes)->count(); ++i) chi.push_back(std::abs((*modes)->shape(i, x)) <= 1e-12 ? 0.0 : (*modes)->shape(i, x));
      fp.param(n.shape(pt, group), vector_param(B, chi));
    }
  }
}

bool Beam::origin_fixed() const {
  const double x = origin_m;
  auto zero = [&](double v, double scale) { return std::abs(v) <= 1e-12 * scale; };
  for (const auto* modes : {&y, &z}) {
    if (!*modes) continue;
    for (int i = 0; i < (*modes)->count(); ++i)
      if (!zero((*modes)->shape(i, x), 1.0) || !zero((*modes)->shape(i, x, 1), 1.0 / length_m)) return false;
  }
  for (const auto* modes : {&axial, &torsion}) {
    if (!*modes) continue;
    for (int i = 0; i < (*modes)->count(); ++i)
      if (!zero((*modes)->shape(i, x), 1.0)) return false;
  }
  return true;  // (the foreshortening integral from the root to x = 0 is empty)
}

/// The body-frame position of a point of a beam, deflected: [x - 1/2 eta^T a(x) eta, w_y, w_z].
E Beam::point(const Build& B, const FlexibleSym& body, const std::string& pt, const Eta& eta) const {
  const Beam& beam = *this;
  const BeamSym n(body);
  E x = B.num(beam.point_x.at(pt) - beam.origin_m);
  std::vector<E> wy, wz;
  for (std::size_t i = 0; i < eta.y.size(); ++i) wy.push_back(B.op('*', B.at(B.ref(n.shape(pt, 'y')), static_cast<int>(i) + 1), eta.y[i]));
  for (std::size_t i = 0; i < eta.z.size(); ++i) wz.push_back(B.op('*', B.at(B.ref(n.shape(pt, 'z')), static_cast<int>(i) + 1), eta.z[i]));
  if (beam.geometric_stiffness) {
    E a = B.op('+', quadratic(B, n.shortening(pt, 'y'), eta.y, eta.y), quadratic(B, n.shortening(pt, 'z'), eta.z, eta.z));
    x = B.op('-', x, B.op('*', B.num(0.5), a));
  }
  if (!eta.axial.empty()) x = B.op('+', x, vec_dot(B, n.shape(pt, 'a'), eta.axial));  // stretch
  return B.list({x, sum_of(B, wy), sum_of(B, wz)});
}

/// The small rotation of the section at a point (body axes): [0, -w_z', w_y'].
E Beam::slope(const Build& B, const FlexibleSym& body, const std::string& pt, const Eta& eta) const {
  const BeamSym n(body);
  std::vector<E> ty, tz;
  for (std::size_t i = 0; i < eta.y.size(); ++i) ty.push_back(B.op('*', B.at(B.ref(n.slope(pt, 'y')), static_cast<int>(i) + 1), eta.y[i]));
  for (std::size_t i = 0; i < eta.z.size(); ++i) tz.push_back(B.op('*', B.at(B.ref(n.slope(pt, 'z')), static_cast<int>(i) + 1), eta.z[i]));
  E twist = eta.torsion.empty() ? B.num(0) : vec_dot(B, n.shape(pt, 't'), eta.torsion);
  return B.list({twist, B.neg(sum_of(B, tz)), sum_of(B, ty)});
}

/// Where a modal coordinate leaves the model's range: the value at which
/// that mode alone tilts the beam by its slope limit somewhere (the
/// kinematics keep slopes to second order). A mode growing that far is
/// almost always an instability: the run stops and says which.
Limits Beam::limits(const std::string& body) const {
  const Beam& beam = *this;
  Limits limits;
  add_bending_limits(body, limits);
  // stretch: the linear strain model holds to small strains; twist: to the slope limit, as bending
  for (const auto& [what, modes] : {std::pair{"stretch", &beam.axial}, std::pair{"twist", &beam.torsion}}) {
    if (!*modes) continue;
    for (int i = 0; i < (*modes)->count(); ++i) {
      const bool stretch = what[0] == 's';
      const double k = (*modes)->k_L(i) / beam.length_m, peak = std::sqrt(2.0) * (stretch ? k : 1.0);
      limits.push_back(
          {(stretch ? kStrainLimit : beam.slope_limit_rad) / peak,
           stretch ? fmt::format("axial mode {} of beam `{}` ({}) strains it by more than {:g}, beyond the small strains of "
                                 "its linear model. Likely cause: an instability, or a load far beyond the material's",
                                 i + 1, body, flex::rod_ends_name((*modes)->ends()), kStrainLimit)
                   : fmt::format("torsion mode {} of beam `{}` ({}) twists it by more than {:g} rad, beyond the small "
                                 "rotations of its linear model (`slope_limit`). Likely cause: an instability, or a torque "
                                 "far beyond the section's",
                                 i + 1, body, flex::rod_ends_name((*modes)->ends()), beam.slope_limit_rad)});
    }
  }
  return limits;
}

void Beam::add_bending_limits(const std::string& body, Limits& limits) const {
  const Beam& beam = *this;
  for (const auto& [plane, modes] : {std::pair{"y", &beam.y}, std::pair{"z", &beam.z}}) {
    if (!*modes) continue;
    for (int i = 0; i < (*modes)->count(); ++i) {
      double peak_slope = 0;
      for (int k = 0; k <= 1000; ++k)
        peak_slope = std::max(peak_slope, std::abs((*modes)->shape(i, beam.length_m * k / 1000, 1)));
      limits.push_back(
          {beam.slope_limit_rad / peak_slope,
           fmt::format("mode {} of beam `{}` ({}, bending along body {}) tilts it by more than {:g} rad, beyond the "
                       "moderate slopes the modal model holds for (`slope_limit`). Likely cause: an instability - the "
                       "beam compressed beyond its buckling load, or spinning faster than its first natural frequency "
                       "without geometric stiffness",
                       i + 1, body, flex::supports_name((*modes)->supports()), plane, beam.slope_limit_rad)});
    }
  }
}

/// K and D block-diagonal by group: bending along y and z, stretch, twist.
void Beam::stiffness_and_damping(const Build& B, const FlexibleSym& body, Rows& K, Rows& D) const {
  const Beam& beam = *this;
  const BeamSym n(body);
  for (const auto& [plane, modes, off] : {std::tuple{'y', &beam.y, 0}, std::tuple{'z', &beam.z, beam.offset_z()}}) {
    if (!*modes) continue;
    for (int i = 0; i < (*modes)->count(); ++i)
      for (int j = 0; j < (*modes)->count(); ++j) {
        K[static_cast<std::size_t>(off + i)][static_cast<std::size_t>(off + j)] = idx2(B, B.ref(n.group(plane).stiffness()), i + 1, j + 1);
        D[static_cast<std::size_t>(off + i)][static_cast<std::size_t>(off + j)] = idx2(B, B.ref(n.group(plane).damping()), i + 1, j + 1);
      }
  }
  for (const auto& [group, count, off] : {std::tuple{'a', beam.axial ? beam.axial->count() : 0, beam.offset_axial()},
                                          std::tuple{'t', beam.torsion ? beam.torsion->count() : 0, beam.offset_torsion()}})
    for (int i = 0; i < count; ++i)
      for (int j = 0; j < count; ++j) {
        K[static_cast<std::size_t>(off + i)][static_cast<std::size_t>(off + j)] = idx2(B, B.ref(n.group(group).stiffness()), i + 1, j + 1);
        D[static_cast<std::size_t>(off + i)][static_cast<std::size_t>(off + j)] = idx2(B, B.ref(n.group(group).damping()), i + 1, j + 1);
      }
}

}  // namespace mbgc::multibody::detail

namespace mbgc::multibody::detail {

/// A flat tube along the beam (width L/25 along y, L/50 along z, 24
/// sections), each section moved by every mode as a whole: bending along y
/// or z, stretch along x, and twist turning the section about x.
ir::Drawing Beam::drawing(double) const {
  ir::Drawing d;
  d.shape = ir::Drawing::Shape::Mesh;
  constexpr int kSections = 24;
  const double hy = length_m / 50, hz = length_m / 100;
  std::vector<double> x;
  for (int k = 0; k <= kSections; ++k) x.push_back(length_m * k / kSections);
  std::vector<double> body_x;
  for (double xk : x) body_x.push_back(xk - origin_m);
  add_tube(d, body_x, hy, hz);
  const std::size_t vertices = d.vertices.size() / 3;
  auto field = [&](auto displacement) {  // displacement(x, y, z) -> [dx, dy, dz] of the vertex at beam station x
    std::vector<double> out(3 * vertices);
    for (std::size_t v = 0; v < vertices; ++v) {
      const std::array<double, 3> u = displacement(x[v / 4], d.vertices[3 * v + 1], d.vertices[3 * v + 2]);
      for (std::size_t c = 0; c < 3; ++c) out[3 * v + c] = std::abs(u[c]) <= 1e-12 ? 0.0 : u[c];  // (a clamped root's rounding)
    }
    d.mode_shapes.push_back(std::move(out));
  };
  for (int i = 0; i < (y ? y->count() : 0); ++i) field([&](double s, double, double) { return std::array<double, 3>{0, y->shape(i, s), 0}; });
  for (int i = 0; i < (z ? z->count() : 0); ++i) field([&](double s, double, double) { return std::array<double, 3>{0, 0, z->shape(i, s)}; });
  for (int i = 0; i < (axial ? axial->count() : 0); ++i)
    field([&](double s, double, double) { return std::array<double, 3>{axial->shape(i, s), 0, 0}; });
  for (int i = 0; i < (torsion ? torsion->count() : 0); ++i)
    field([&](double s, double py, double pz) {
      const double twist = torsion->shape(i, s);
      return std::array<double, 3>{0, -twist * pz, twist * py};
    });
  return d;
}

}  // namespace mbgc::multibody::detail
