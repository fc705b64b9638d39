// multibody/body_kind.hpp — what a body is, as a type: ground, a particle
// (a mass: it translates, it does not turn), a rigid body (a mass and an
// inertia), or a flexible body (a floating frame and a deformation field,
// deformation.hpp: a beam, a modal body). Code whose work differs by kind
// visits it, one case per kind (visit()), so that a kind added here is a
// compile error wherever it is not handled yet; the questions asked most are
// members.
#pragma once

#include <memory>
#include <utility>
#include <variant>

#include "multibody/deformation.hpp"

namespace mbgc::multibody::detail {

struct Ground {};
struct Particle {};
struct Rigid {};
struct Flexible {
  std::shared_ptr<Deformation> field;
};

/// std::visit's overload set: one callable per kind.
template <class... F>
struct Cases : F... {
  using F::operator()...;
};
template <class... F>
Cases(F...) -> Cases<F...>;

class BodyKind {
 public:
  BodyKind(Ground k) : kind_(k) {}
  BodyKind(Particle k) : kind_(k) {}
  BodyKind(Rigid k) : kind_(k) {}
  BodyKind(Flexible k) : kind_(std::move(k)) {}

  bool ground() const { return std::holds_alternative<Ground>(kind_); }
  bool particle() const { return std::holds_alternative<Particle>(kind_); }
  /// Whether it has an orientation and an angular velocity (a rigid or a flexible body).
  bool turns() const { return std::holds_alternative<Rigid>(kind_) || std::holds_alternative<Flexible>(kind_); }
  /// A flexible body's deformation field; null for the other kinds.
  const Deformation* field() const {
    const Flexible* f = std::get_if<Flexible>(&kind_);
    return f ? f->field.get() : nullptr;
  }

  /// `cases` called with the kind (Ground, Particle, Rigid or Flexible): one per kind.
  template <class... F>
  decltype(auto) visit(F&&... cases) const {
    return std::visit(Cases{std::forward<F>(cases)...}, kind_);
  }

 private:
  std::variant<Ground, Particle, Rigid, Flexible> kind_;
};

}  // namespace mbgc::multibody::detail
