// multibody/modal_body.hpp — a reduced flexible body from a modal-data file
// (`flexible = modal("arm.mbm")`, docs/modal_format.md): the same
// floating-frame equations as a beam, with M(eta) built from the file's
// inertia invariants for the linear field u = Phi(r0) eta. Every coefficient
// is a constant the compiler computes here and writes as a parameter, so the
// generated code reads J(eta)_xy = J0_xy + J1.xy . eta + eta' J2.xy eta.
#pragma once

#include <memory>

#include "flex/modal_file.hpp"
#include "multibody/deformation.hpp"
#include "multibody/flexible_symbols.hpp"

namespace mbgc::multibody::detail {

class ModalBody final : public Deformation {
 public:
  explicit ModalBody(std::shared_ptr<const flex::ModalData> data) : data_(std::move(data)) {}
  const std::vector<const Setting*>& settings() const override { return modal_setting::kAll; }
  int count() const override { return data_->count; }
  std::map<std::string, std::array<double, 3>> points() const override;
  /// No planes: every coordinate in Eta::y.
  Eta split(const std::function<E(int)>& eta) const override;
  void params(const FieldParams& p) const override;
  E first_moment(const Build& B, const FlexibleSym& n, const Eta& eta) const override;
  Rows translation_coupling(const Build& B, const FlexibleSym& n, const Eta& eta) const override;
  Rows mass_matrix(const Build& B, const FlexibleSym& n, const Eta& eta) const override;
  E point(const Build& B, const FlexibleSym& n, const std::string& pt, const Eta& eta) const override;
  E slope(const Build& B, const FlexibleSym& n, const std::string& pt, const Eta& eta) const override;
  bool origin_fixed() const override { return false; }  // the file does not say how the origin moves
  Limits limits(const std::string& body) const override;
  void stiffness_and_damping(const Build& B, const FlexibleSym& n, Rows& K, Rows& D) const override;
  ir::Drawing drawing(double scale) const override;
  std::string point_file() const override { return data_->path; }

 private:
  /// A node's deflected position (P = its shapes, at = its undeformed position) or small rotation (P = its slopes).
  static E node(const Build& B, const Sym& P, std::array<double, 3> at, const std::vector<E>& eta);
  std::shared_ptr<const flex::ModalData> data_;
};

}  // namespace mbgc::multibody::detail
