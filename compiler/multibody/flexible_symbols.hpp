// multibody/flexible_symbols.hpp — the names what each kind of flexible body
// writes of its own (beam.cpp, modal_body.cpp): its section, material and
// modal integrals, and its points' mode shapes, as parameters. The
// floating-frame fragment they share is FlexibleSym's (symbols.hpp).
#pragma once

#include <cstddef>
#include <set>
#include <string>

#include <fmt/format.h>

#include "multibody/symbols.hpp"

namespace mbgc::multibody::detail {

/// A group of a beam's modes (BeamSym::group): the integrals of its mode
/// shapes phi over the beam, scaled to the section, as parameters.
class BeamModesSym : public Sym {
 public:
  Sym mean() const { return part("mean"); }            // int phi dm
  Sym moment() const { return part("moment"); }        // int x phi dm
  Sym mass() const { return part("mass"); }            // int phi phi^T dm: the modal mass
  Sym stiffness() const { return part("stiffness"); }  // the modal stiffness
  Sym damping() const { return part("damping"); }      // the modal damping
  /// Bending: the foreshortening's coupling with axial acceleration, and the
  /// geometric stiffness under spin.
  Sym load() const { return part("load"); }
  Sym spin() const { return part("spin"); }
  /// Twist: the change of J_yz as a non-circular section turns.
  Sym product() const { return part("product"); }

 private:
  friend class BeamSym;
  explicit BeamModesSym(const Sym& group) : Sym(group) {}
};

/// The built-in beam (`flexible = beam`): its section and material, its
/// modes by group, and at each point the mode shapes there. A group is
/// 'y' or 'z' (bending along body y or z), 'a' (stretch) or 't' (twist).
class BeamSym : public FlexibleSym {
 public:
  explicit BeamSym(const std::string& body) : FlexibleSym(body) {}
  explicit BeamSym(const FlexibleSym& body) : FlexibleSym(body) {}

  // material and section
  Sym length() const { return part(beam_setting::length); }
  Sym density() const { return part(beam_setting::density); }
  Sym youngs_modulus() const { return part(beam_setting::E); }
  Sym shear_modulus() const { return part(beam_setting::G); }
  Sym area() const { return part(beam_setting::area); }
  Sym Iy() const { return part(beam_setting::Iy); }  // second moments of area about y and z
  Sym Iz() const { return part(beam_setting::Iz); }
  Sym Ip() const { return part("Ip", beam_setting::Iy.dimension); }  // the polar moment, Iy + Iz
  Sym torsion_constant() const { return part(beam_setting::torsion_constant); }
  Sym mass_per_length() const { return part("mu", units::dim::mass() / units::dim::length()); }
  /// A flexible body's parts and those above: what a beam's point cannot be named.
  static const std::set<std::string>& parts() {
    static const std::set<std::string> all = [] {
      std::set<std::string> out = FlexibleSym::parts();
      out.insert({"length", "density", "E", "G", "area", "Iy", "Iz", "Ip", "torsion_constant", "mu"});
      return out;
    }();
    return all;
  }

  /// The integrals of group g's modes.
  BeamModesSym group(char g) const { return BeamModesSym(part(std::string(1, g))); }
  /// int phi_g phi_h^T dm of two groups' modes (bending y with z; stretch with bending).
  Sym cross_mass(char g, char h) const { return part(fmt::format("{}{}.mass", g, h)); }

  /// At point p: group g's mode shapes, and (bending) their slopes and the
  /// foreshortening int_0^x phi' phi'^T up to the point.
  Sym shape(const std::string& p, char g) const { return part(fmt::format("{}.{}.shape", p, g)); }
  Sym slope(const std::string& p, char plane) const { return part(fmt::format("{}.{}.slope", p, plane)); }
  Sym shortening(const std::string& p, char plane) const { return part(fmt::format("{}.{}.shortening", p, plane)); }
};

/// A body from a modal-data file (`flexible = modal("arm.mbm")`): the
/// inertia invariants of its field and its nodes' mode shapes, as
/// parameters. An axis is 0, 1, 2 for x, y, z.
class ModalSym : public FlexibleSym {
 public:
  explicit ModalSym(const std::string& body) : FlexibleSym(body) {}
  explicit ModalSym(const FlexibleSym& body) : FlexibleSym(body) {}

  Sym first_moment() const { return part("first_moment"); }  // int r0 dm
  Sym mean() const { return part("mean"); }                  // int Phi dm (3 x count)
  /// J(eta)_ij = J0_ij + J1_ij . eta + eta^T J2_ij eta (i <= j).
  Sym J1(std::size_t i, std::size_t j) const { return part(fmt::format("J1.{}{}", axis(i), axis(j))); }
  Sym J2(std::size_t i, std::size_t j) const { return part(fmt::format("J2.{}{}", axis(i), axis(j))); }
  /// The rotation-mode coupling about axis i: its constant part and its part linear in eta.
  Sym coupling(std::size_t i) const { return part(fmt::format("coupling.{}", axis(i))); }
  Sym coupling_eta(std::size_t i) const { return part(fmt::format("coupling_eta.{}", axis(i))); }
  Sym modal_mass() const { return part("modal_mass"); }
  Sym stiffness() const { return part("stiffness"); }
  Sym damping() const { return part("damping"); }
  /// Node p's mode shapes (its displacement per mode) and slopes (its small rotation per mode).
  Sym shape(const std::string& p) const { return part(fmt::format("{}.shape", p)); }
  Sym slope(const std::string& p) const { return part(fmt::format("{}.slope", p)); }
  /// A flexible body's parts and those above: what a node of its file cannot be named.
  static const std::set<std::string>& parts() {
    static const std::set<std::string> all = [] {
      std::set<std::string> out = FlexibleSym::parts();
      out.insert({"first_moment", "mean", "J1", "J2", "coupling", "coupling_eta", "modal_mass", "stiffness", "damping"});
      return out;
    }();
    return all;
  }

 private:
  static char axis(std::size_t i) { return "xyz"[i]; }
};

}  // namespace mbgc::multibody::detail
