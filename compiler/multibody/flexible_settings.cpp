// multibody/flexible_settings.cpp — settings of flexible bodies: beams and modal-data files.
#include "multibody/collect.hpp"

#include "multibody/beam.hpp"
#include "multibody/flexible_symbols.hpp"
#include "multibody/modal_body.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <ranges>
#include <set>
#include <tuple>

#include <fmt/format.h>

namespace mbgc::multibody::detail {

namespace {
/// A point a modal-data file gives, as the literal [x, y, z] a model would write.
ir::AstExprPtr literal_point(const ir::SourceLoc& loc, const std::array<double, 3>& x) {
  auto list = std::make_shared<ir::AstExpr>();
  list->kind = ir::AstExpr::Kind::List;
  list->loc = loc;
  for (double v : x) {
    auto n = std::make_shared<ir::AstExpr>();
    n->kind = ir::AstExpr::Kind::Number;
    n->loc = loc;
    n->number = v;
    list->args.push_back(std::move(n));
  }
  return list;
}
}  // namespace

// ---- 1b. flexible bodies -------------------------------------------------------------
/// The floating frame (thesis Ch. 5). `joint`: attached to the beam at
/// x = 0, which the mode set must leave in place (every set but free_free).
/// `buckens`: the mean axes, whose conditions int u dm = 0 and
/// int r0 x u dm = 0 free-free modes satisfy (they are orthogonal to the
/// rigid motions); those two couplings then drop out of M(eta), and the
/// compiler says so. The default is the one the mode sets allow.
void Collector::check_frame(Beam& beam, const AstBody& b, const AstAttr* given) {
  bool any_free = false, all_free = true;
  auto count_set = [&](bool free) {
    any_free = any_free || free;
    all_free = all_free && free;
  };
  for (const auto* modes : {&beam.y, &beam.z})
    if (*modes) count_set((*modes)->supports() == flex::Supports::FreeFree);
  for (const auto* modes : {&beam.axial, &beam.torsion})
    if (*modes) count_set((*modes)->ends() == flex::RodEnds::FreeFree);
  std::string frame = all_free && any_free ? "buckens" : "joint";
  SourceLoc loc = b.loc;
  if (given) {
    const AstExpr& v = *given->value;
    loc = v.loc;
    if (v.kind != AstExpr::Kind::Name) {
      diags_.error(v.loc, "a floating frame is a name", "write frame = joint, frame = centre, frame = buckens or frame = tisserand");
      return;
    }
    frame = v.name;
    if (frame == "principal") {
      diags_.error(v.loc, "frame = principal is not implemented",
                   "the principal-axis frame only diagonalises the inertia and makes the modal coordinates "
                   "dependent (thesis §5.2.2); write frame = joint, centre, buckens or tisserand");
      return;
    }
    if (frame != "joint" && frame != "buckens" && frame != "centre" && frame != "tisserand") {
      diags_.error(v.loc, fmt::format("unknown floating frame `{}`", frame),
                   "write frame = joint, frame = centre, frame = buckens or frame = tisserand");
      return;
    }
  }
  if (frame == "joint" && any_free) {
    diags_.error(loc, fmt::format("free-free modes move the end x = 0 of beam `{}`, so its frame cannot be fixed there", b.name),
                 all_free ? "write frame = buckens (the mean axes the free-free modes define) or frame = centre (fixed "
                            "to the section at the mass centre)"
                          : "give every mode set free_free modes with frame = buckens, or none");
    return;
  }
  if (frame == "buckens" && !all_free) {
    diags_.error(loc, fmt::format("the mean axes (frame = buckens) of beam `{}` need modes orthogonal to its rigid motions", b.name),
                 "give every mode set free_free(n) modes, or use frame = joint");
    return;
  }
  if (frame == "centre") {
    if (!all_free || beam.axial || beam.torsion) {
      diags_.error(loc, fmt::format("a frame at the mass centre of beam `{}` needs free-free bending modes", b.name),
                   beam.axial || beam.torsion ? "stretch and twist in a centre frame are not implemented yet: use frame = "
                                                "buckens with free_free modes, or frame = joint"
                                              : "give every plane free_free(n) modes (the frame then holds the centre "
                                                "section in place), or use frame = joint");
      return;
    }
    // the frame holds the centre section: each mode is measured from it
    beam.origin_m = beam.length_m / 2;
    for (auto* modes : {&beam.y, &beam.z})
      if (*modes) *modes = (*modes)->anchored_at(beam.origin_m);
  }
  if (frame == "tisserand" && !tisserand_allowed(beam, b, loc)) return;
  beam.mean_axes = frame == "buckens" || frame == "tisserand";
  beam.tisserand = frame == "tisserand";
  if (beam.tisserand) {
    beam.origin_m = beam.length_m / 2;
    for (auto* modes : {&beam.y, &beam.z})
      if (*modes) *modes = (*modes)->in_tisserand_frame();
  }
}

/// Tisserand's frame (thesis §5.2.4) asks that the deformation carry no
/// linear and no angular momentum relative to the frame. With free-free
/// bending modes in one plane both hold identically (5.30 with the origin
/// at the mass centre and the foreshortening measured from its mean; 5.34
/// because int phi_k x phi_l dm = 0 for deflections along one axis).
/// Any other mode set makes 5.34 the nonholonomic constraint
/// eta^T G eta' = 0, whose row G^T eta vanishes at the undeformed shape:
/// a multiplier for it is undefined where every run starts.
bool Collector::tisserand_allowed(const Beam& beam, const AstBody& b, const SourceLoc& loc) {
  const bool free_y = beam.y && beam.y->supports() == flex::Supports::FreeFree;
  const bool free_z = beam.z && beam.z->supports() == flex::Supports::FreeFree;
  if (beam.torsion) {
    diags_.error(loc, fmt::format("twist in Tisserand's frame of beam `{}` is not implemented", b.name),
                 "use frame = buckens (the same mean axes to first order), or leave out modes_torsion");
    return false;
  }
  std::string why;
  if (beam.axial)
    why = "stretch couples with bending in int phi_k x phi_l dm (u along x, w along y: their cross product is not zero)";
  else if (beam.y && beam.z)
    why = "with bending in two planes int phi_y,k x phi_z,l dm is not zero (a whirling beam carries angular momentum "
          "about its axis)";
  if (!why.empty()) {
    diags_.error(loc, fmt::format("Tisserand's frame of beam `{}` would be a nonholonomic constraint", b.name),
                 fmt::format("{}, so the frame's condition eta^T G eta' = 0 (thesis eq. 5.34) constrains the modes, and "
                             "its row G^T eta vanishes at the undeformed shape; use frame = buckens (the same mean "
                             "axes to first order), or free_free bending in one plane only",
                             why));
    return false;
  }
  if (!free_y && !free_z) {
    diags_.error(loc, fmt::format("Tisserand's frame (mean axes) of beam `{}` needs free-free modes", b.name),
                 "its modes must be orthogonal to the rigid motions: give the beam free_free(n) bending modes in "
                 "one plane, or use frame = joint");
    return false;
  }
  return true;
}

void Collector::add_flexible_body(Body& body, const AstBody& b, const AstAttr& kind) {
  const AstExpr& v = *kind.value;
  if (v.kind == AstExpr::Kind::Call && v.name == "modal") {
    add_modal_body(body, b, v);
    return;
  }
  if (v.kind != AstExpr::Kind::Name || v.name != "beam") {
    diags_.error(v.loc, "unknown kind of flexible body",
                 "write flexible = beam (a uniform Euler-Bernoulli beam along the body's x axis) or flexible = "
                 "modal(\"file.mbm\") (a reduced body from an FE program, docs/modal_format.md)");
    return;
  }
  auto beam = std::make_shared<Beam>();
  std::map<std::string, const AstAttr*> given;
  std::vector<std::string> names = setting_names(beam_setting::kAll);
  std::sort(names.begin(), names.end());
  std::set<std::string> meant;  // settings a misspelt one was taken for: not reported missing too
  for (const AstAttr& a : b.attrs) {
    if (!find_setting(beam_setting::kAll, a.key)) {
      std::string near = closest_name(a.key, names);
      meant.insert(near);
      const char* computed = (a.key == body_setting::mass.name || a.key == body_setting::inertia.name || a.key == body_setting::com.name)
                                 ? "a beam's mass, inertia and centre of mass follow from its length, density and section; remove it"
                                 : nullptr;
      diags_.error(a.loc, fmt::format("flexible body `{}` has no setting `{}`", b.name, a.key),
                   computed ? std::string(computed)
                   : near.empty() ? fmt::format("a beam takes {}", fmt::join(names, ", "))
                                  : fmt::format("did you mean `{}`?", near));
      continue;
    }
    record_setting(given, a, b);
  }
  auto has = [&](const Setting& s) { return given.count(s.name) > 0; };
  auto need = [&](const Setting& s) -> const AstAttr* {
    auto it = given.find(s.name);
    if (it != given.end()) return it->second;
    if (!meant.count(s.name))
      diags_.error(b.loc, fmt::format("flexible body `{}` has no `{}`", b.name, s.name), fmt::format("give {}", s.what));
    return nullptr;
  };
  if (const AstAttr* len = need(beam_setting::length)) {
    auto v = constants_.constant_of(*len->value);
    if (!v || !(*v > 0))
      diags_.error(len->value->loc, fmt::format("the length of beam `{}` must be a positive constant", b.name),
                   "the compiler integrates the mode shapes over the length: write a number or a constant parameter");
    else beam->length_m = *v;
  }
  need(beam_setting::density);
  need(beam_setting::E);
  if (has(beam_setting::section) && (has(beam_setting::area) || has(beam_setting::Iy) || has(beam_setting::Iz)))
    diags_.error(given.at(beam_setting::section.name)->loc, fmt::format("beam `{}` has both `section` and section properties", b.name),
                 "give either section = rectangle(...)/circle(...)/tube(...) or area, Iy and Iz");
  else if (!has(beam_setting::section)) {
    need(beam_setting::area);
    need(beam_setting::Iy);
    need(beam_setting::Iz);
  } else check_section(*given.at(beam_setting::section.name)->value);
  for (const Setting* modes : {&beam_setting::modes_xy, &beam_setting::modes_xz}) {
    const char* plane = modes->name;
    auto it = given.find(plane);
    if (it == given.end() || beam->length_m <= 0) continue;
    const AstExpr& v = *it->second->value;
    flex::Supports sup{};
    const int n = mode_count(v);
    if (!n || !flex::supports_from_name(v.name, &sup)) {
      diags_.error(v.loc, fmt::format("`{}` of beam `{}` is not a mode set", plane, b.name),
                   "write supports(number of modes): clamped_free(3), pinned_pinned(2), clamped_pinned(2) or free_free(2); "
                   "1 to 12 modes");
      continue;
    }
    (modes == &beam_setting::modes_xy ? beam->y : beam->z).emplace(sup, beam->length_m, n);
  }
  for (const Setting* modes : {&beam_setting::modes_axial, &beam_setting::modes_torsion}) {
    const char* key = modes->name;
    auto it = given.find(key);
    if (it == given.end() || beam->length_m <= 0) continue;
    const AstExpr& v = *it->second->value;
    flex::RodEnds ends{};
    const int n = mode_count(v);
    if (!n || !flex::rod_ends_from_name(v.name, &ends)) {
      diags_.error(v.loc, fmt::format("`{}` of beam `{}` is not a mode set", key, b.name),
                   "write ends(number of modes): fixed_free(2), fixed_fixed(2) or free_free(2); 1 to 12 modes");
      continue;
    }
    (modes == &beam_setting::modes_axial ? beam->axial : beam->torsion).emplace(ends, beam->length_m, n);
  }
  if (has(beam_setting::modes_torsion)) {
    need(beam_setting::G);
    if (!has(beam_setting::section) && !has(beam_setting::torsion_constant))
      diags_.error(given.at(beam_setting::modes_torsion.name)->loc, fmt::format("beam `{}` twists but has no torsion constant", b.name),
                   "give torsion_constant (m^4), or a section = rectangle(...)/circle(...)/tube(...) to compute it from");
  } else {
    for (const Setting* torsion : {&beam_setting::G, &beam_setting::torsion_constant})
      if (const char* key = torsion->name; given.count(key))
        diags_.error(given.at(key)->loc, fmt::format("`{}` of beam `{}` is for torsion, which it has no modes of", key, b.name),
                     "give modes_torsion = fixed_free(1) (or another mode set), or remove it");
  }
  if (!has(beam_setting::modes_xy) && !has(beam_setting::modes_xz) && !has(beam_setting::modes_axial) && !has(beam_setting::modes_torsion))
    diags_.error(b.loc, fmt::format("beam `{}` has no modes", b.name),
                 "give the assumed modes of at least one bending plane, e.g. modes_xy = clamped_free(3), or of "
                 "stretch or twist (modes_axial, modes_torsion)");
  beam->geometric_stiffness = std::string_view(beam_setting::geometric_stiffness.by_default.value) == "on";
  if (auto g = given.find(beam_setting::geometric_stiffness.name); g != given.end()) {
    const AstExpr& v = *g->second->value;
    auto flag = constants_.constant_of(v);  // 1 or 0: a parameter, so that `mbgc --set` can switch it
    if (v.kind == AstExpr::Kind::Name && (v.name == "on" || v.name == "off")) beam->geometric_stiffness = v.name == "on";
    else if (flag && (*flag == 0 || *flag == 1)) beam->geometric_stiffness = *flag == 1;
    else diags_.error(v.loc, "geometric_stiffness is `on` or `off` (or a constant 1 or 0)",
                      "on: the dynamic geometric stiffness of the axial load (spin stiffening, buckling); off: the linear "
                      "model the thesis compares against");
  }
  check_frame(*beam, b, has(beam_setting::frame) ? given.at(beam_setting::frame.name) : nullptr);
  if (auto s = given.find(beam_setting::slope_limit.name); s != given.end()) read_slope_limit(beam->slope_limit_rad, b, *s->second);
  body.kind = Flexible{beam};
  add_points(body, b, b.name, BeamSym::parts());
  for (const AstPoint& p : b.points) {
    bool on_axis = false;
    if (p.value->kind == AstExpr::Kind::List && p.value->args.size() == 3) {
      auto x = constants_.constant_of(*p.value->args[0]), y = constants_.constant_of(*p.value->args[1]), z = constants_.constant_of(*p.value->args[2]);
      const double c = beam->origin_m;  // body x is measured from the frame's origin
      if (x && y && z && *y == 0 && *z == 0 && *x >= -c && *x <= beam->length_m - c) {
        on_axis = true;
        beam->point_x[p.name] = *x + c;
      }
    }
    if (!on_axis && beam->length_m > 0)
      diags_.error(p.value->loc, fmt::format("point `{}` is not on the axis of beam `{}`", p.name, b.name),
                   beam->origin_m == 0
                       ? fmt::format("points of a beam are [x, 0, 0] with x a constant from 0 to its length {} m: the "
                                     "joint there sees the beam's deflection and slope at x",
                                     beam->length_m)
                       : fmt::format("points of a beam are [x, 0, 0] with x a constant from {} to {} m (its frame is at "
                                     "the centre): the joint there sees the beam's deflection and slope at x",
                                     -beam->origin_m, beam->length_m - beam->origin_m));
  }
  m_.bodies[b.name] = body;
  m_.body_order.push_back(b.name);
}

/// The n of a mode set `name(n)` (n a whole constant, 1 to 12); 0 if it is not one.
int Collector::mode_count(const AstExpr& v) const {
  if (v.kind != AstExpr::Kind::Call || v.args.size() != 1) return 0;
  auto n = constants_.constant_of(*v.args[0]);
  return n && *n >= 1 && *n <= 12 && *n == std::floor(*n) ? static_cast<int>(*n) : 0;
}

/// A flexible body's known setting: reported if given twice, its shape checked.
void Collector::record_setting(std::map<std::string, const AstAttr*>& given, const AstAttr& a, const AstBody& b) {
  if (auto [first, fresh] = given.emplace(a.key, &a); !fresh) {
    auto& d = diags_.error(a.loc, fmt::format("`{}` of body `{}` is given twice", a.key, b.name), "keep one of them");
    d.notes.push_back({first->second->loc, "first given here"});
  }
  if (const Setting* s = find_setting(body_setting::kAll, a.key); s && s->expected)  // an initial value
    check_shape(*a.value, fmt::format("`{}` of body `{}`", a.key, b.name), *s->expected);
}

void Collector::read_slope_limit(double& limit_rad, const AstBody& b, const AstAttr& a) {
  auto v = constants_.constant_of(*a.value);
  if (!v || !(*v > 0) || *v > 1.5)
    diags_.error(a.value->loc, fmt::format("the slope limit of flexible body `{}` must be a constant in (0, 1.5] rad", b.name),
                 fmt::format("the modal model keeps slopes to second order: beyond about 0.3 rad its curvature is off by "
                             "more than 14 %; the default is {}",
                             beam_setting::slope_limit.by_default.value));
  else limit_rad = *v;
}

/// `flexible = modal("file.mbm")`: a reduced body whose mass, stiffness and
/// nodes come from a modal-data file (docs/modal_format.md). The model
/// adds only its damping ratio, slope limit and initial state.
void Collector::add_modal_body(Body& body, const AstBody& b, const AstExpr& v) {
  if (v.args.size() != 1 || v.args[0]->kind != AstExpr::Kind::String) {
    diags_.error(v.loc, "modal(...) takes the name of a modal-data file", "write flexible = modal(\"arm.mbm\")");
    body.points_unknown = true;
    m_.bodies[b.name] = body;
    m_.body_order.push_back(b.name);
    return;
  }
  static const std::vector<std::string> keys = setting_names(modal_setting::kAll);
  double slope_limit_rad = beam_setting::slope_limit.by_default.number();
  std::map<std::string, const AstAttr*> given;
  for (const AstAttr& a : b.attrs) {
    if (std::find(keys.begin(), keys.end(), a.key) == keys.end()) {
      // what a beam, or a rigid body, takes that the file gives
      const bool from_file = a.key == body_setting::mass.name || a.key == body_setting::inertia.name ||
                             a.key == body_setting::com.name || a.key.rfind("modes", 0) == 0 ||
                             find_setting({&beam_setting::length, &beam_setting::E, &beam_setting::density,
                                           &beam_setting::section},
                                          a.key);
      diags_.error(a.loc, fmt::format("flexible body `{}` from a modal-data file has no setting `{}`", b.name, a.key),
                   a.key == beam_setting::geometric_stiffness.name
                       ? std::string("a modal-data body is linear in its modal coordinates (format version 1): no "
                                     "geometric stiffness; use flexible = beam where stress stiffening matters")
                   : a.key == beam_setting::frame.name ? std::string("its frame is the one its file is written in")
                   : from_file ? std::string("its mass, inertia, stiffness and modes come from the file; remove it")
                               : fmt::format("a modal body takes {}", fmt::join(keys, ", ")));
      continue;
    }
    record_setting(given, a, b);
  }
  for (const AstPoint& p : b.points)
    diags_.error(p.loc, fmt::format("point `{}`: the points of modal body `{}` are the nodes of its file", p.name, b.name),
                 "add the node to the file (records point, shape and slope) and attach joints to it by name");
  if (auto s = given.find(beam_setting::slope_limit.name); s != given.end()) read_slope_limit(slope_limit_rad, b, *s->second);
  if (auto s = given.find(modal_setting::stiffness_scale.name); s != given.end()) {
    // a parameter may stand here (the simulator's --set changes it); its value as written must already hold
    auto k = constants_.constant_of(*s->second->value);
    if (k && !(*k > 0 && std::isfinite(*k)))
      diags_.error(s->second->value->loc,
                   fmt::format("the stiffness scale of modal body `{}` is {}: it must be positive", b.name, *k),
                   "stiffness_scale multiplies the file's modal stiffness (as a Young's modulus times k would): "
                   "1 keeps it, 10 makes the body 10 times stiffer");
  }
  const AstExpr& file = *v.args[0];
  auto data = flex::read_modal_file(file.name, file.loc, search_dirs_, sources_, diags_);
  if (!data) {
    body.points_unknown = true;  // registered all the same: joints to it are not reported again
    m_.bodies[b.name] = body;
    m_.body_order.push_back(b.name);
    return;
  }
  for (const auto& [name, pt] : data->points) {
    if (ModalSym::parts().count(name)) {
      diags_.error(file.loc, fmt::format("the modal-data file names a point `{}`, which body `{}` uses for itself", name, b.name),
                   "rename the node in the file");
      continue;
    }
    body.points[name] = literal_point(file.loc, pt.position);
    point_locs_[BodySym(b.name).point(name).str()] = file.loc;
  }
  auto modal = std::make_shared<ModalBody>(std::make_shared<const flex::ModalData>(std::move(*data)));
  modal->slope_limit_rad = slope_limit_rad;
  body.kind = Flexible{modal};
  m_.bodies[b.name] = body;
  m_.body_order.push_back(b.name);
}

void Collector::check_section(const AstExpr& v) {
  static const std::map<std::string, std::size_t> arity = {{"rectangle", 2}, {"circle", 1}, {"tube", 2}};
  auto it = v.kind == AstExpr::Kind::Call ? arity.find(v.name) : arity.end();
  if (it == arity.end() || it->second != v.args.size())
    diags_.error(v.loc, "unknown beam section",
                 "write rectangle(width_y, height_z), circle(diameter) or tube(outer_diameter, inner_diameter), in m; "
                 "or give area, Iy and Iz instead of section");
}

}  // namespace mbgc::multibody::detail
