// multibody/collect.hpp — the multibody layer's first pass: it reads the
// bodies, joints, force elements, contacts, tyres and model settings of a
// program, checks each setting against its table (settings.hpp) and what
// the text tells of its value (shapes.hpp), reads modal-data and mesh
// files, and returns the Model (model.hpp) the later passes write the bond
// graph from. Errors go to the diagnostics; nothing is written.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "ir/ast.hpp"
#include "ir/diagnostics.hpp"
#include "ir/drawing.hpp"
#include "multibody/expand.hpp"
#include "multibody/joint_kind.hpp"
#include "multibody/model.hpp"
#include "multibody/settings.hpp"
#include "multibody/shapes.hpp"

namespace mbgc::multibody::detail {

using namespace mbgc::ir;  // the multibody layer reads and builds the AST's statements throughout

class Beam;

class Collector {
 public:
  Collector(ir::SourceManager& sources, Diagnostics& diags, const ExpandOptions& options)
      : sources_(sources), diags_(diags), search_dirs_(options.search_dirs), override_(options.constraints),
        strategy_(options.constraints.value_or(Strategy::Auto)),
        contact_strategy_(options.contacts.value_or(ContactStrategy::Unilateral)) {}

  /// The program's model; check the diagnostics for errors before using it.
  Model run(const AstProgram& in);

 private:
  // ---- bodies, joints, force elements and model settings (collect.cpp)
  void collect(const AstProgram& in);
  bool connector_name_ok(const AstJoint& j, std::map<std::string, const AstJoint*>& seen);
  void duplicate(const char* what, const std::string& name, const SourceLoc& at, const SourceLoc& first);
  void setting(const AstSetting& st);
  std::optional<Strategy> strategy_of(const AstExpr& v, const char* key);
  void add_body(const AstBody& b);
  /// The points of `b` into `body`; none may take a name of `reserved` (the body's own parts, its symbol's).
  void add_points(Body& body, const AstBody& b, const std::string& owner, const std::set<std::string>& reserved);
  std::optional<Side> side(const AstEndpoint& ep);
  void add_force(const AstJoint& f);
  /// A connector's settings by key into `attrs`: an unknown key (with a
  /// did-you-mean, else `unknown_hint`) or a key given twice is an error.
  bool collect_settings(const AstJoint& c, const std::vector<std::string>& keys,
                        std::map<std::string, const AstAttr*>& attrs, const std::string& unknown_hint);
  void check_joint_constant(const JointKind& kind, const AstJoint& j, const AstAttr& at);
  void add_joint(const AstJoint& j);

  /// Reports a setting whose shape is known and wrong, or that depends on time (shapes.cpp).
  void check_shape(const AstExpr& value, const std::string& what, const Expected& want, bool constant = true);

  // ---- settings of flexible bodies: beams and modal-data files (flexible_settings.cpp;
  // their tables: settings.hpp)
  void check_frame(Beam& beam, const AstBody& b, const AstAttr* given);
  bool tisserand_allowed(const Beam& beam, const AstBody& b, const SourceLoc& loc);
  void add_flexible_body(Body& body, const AstBody& b, const AstAttr& kind);
  int mode_count(const AstExpr& v) const;
  void record_setting(std::map<std::string, const AstAttr*>& given, const AstAttr& a, const AstBody& b);
  void read_slope_limit(double& limit_rad, const AstBody& b, const AstAttr& a);
  void add_modal_body(Body& body, const AstBody& b, const AstExpr& v);
  void check_section(const AstExpr& v);

  // ---- contacts and tyres (contacts.cpp, tyres.cpp)
  void add_contact(const AstJoint& c);
  void check_polygon(const Contact& c);
  void add_tyre(const AstJoint& t);
  void check_profile(const Tyre& t, const AstExpr& v);

  // ---- a body's `shape` (drawing.cpp)
  std::shared_ptr<Drawing> read_shape(const AstBody& b, const AstExpr& v);

  ir::SourceManager& sources_;                // modal-data and mesh files join it (diagnostics, depfile)
  Diagnostics& diags_;
  std::vector<std::string> search_dirs_;      // mbgc -I: where modal-data and mesh files are looked for
  std::optional<Strategy> override_;          // mbgc --constraints
  Strategy strategy_;                         // the model-level strategy
  ContactStrategy contact_strategy_;          // of contacts without their own (mbgc --contacts)
  Model m_;
  Constants constants_{m_.params};
  std::map<std::string, SourceLoc> point_locs_;  // "body.point" -> declaration
  std::map<std::string, SourceLoc> instances_;   // component instances (their parts are named `instance.part`)
  std::set<std::string> repeated_;               // names reported as declared in every loop iteration
};

}  // namespace mbgc::multibody::detail
