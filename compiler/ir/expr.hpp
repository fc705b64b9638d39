// ir/expr.hpp — symbolic scalar expressions, the currency of every pass after
// resolve. Immutable, shared trees; the smart constructors fold constants and
// apply the trivial identities (x+0, x*1, x*0, --x, ...), so "constant folding"
// happens everywhere by construction. Every node carries a structural hash so
// equality and common-subexpression detection are cheap.
//
// Leaves refer to model quantities by integer id; the pass that owns the ids
// (resolve for parameters, equations for variables) provides their names when
// printing through a `Namer`.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace mbgc::ir {

enum class Op : unsigned char {
  Const,  // value
  Param,  // id: a model parameter (known before the run, overridable)
  Var,    // id: an equation-system variable (state, effort, flow, signal, ...)
  Time,   // the simulation time t
  Neg,    // -a
  Add,    // a + b
  Sub,    // a - b
  Mul,    // a * b
  Div,    // a / b
  Pow,    // a ^ b
  Call,   // fn(args...)
  Der,    // d/dt of args[0] (derivative causality; removed by reduce)
};

enum class Fn : unsigned char {
  Sin, Cos, Tan, Asin, Acos, Atan, Atan2, Sinh, Cosh, Tanh,
  Exp, Log, Sqrt, Abs, Sign, Min, Max,
  Step,   // heaviside(x): 1 if x >= 0 else 0 (the language's step(t0) is heaviside(t - t0))
  Select, // select(x): 1 if x >= 0 else 0 like heaviside, but not an event: a choice between two
          // expressions that agree where x = 0 (a contact polygon's nearest edge)
  Frozen, // frozen(x): x, with derivative 0 (a contact's tangent directions and arms: the rows
          // of a material point's relative velocity)
};

struct Node;

/// A counted reference to an immutable node: what std::shared_ptr<const Node>
/// was, at half the size and without atomic counts (the compiler runs on one
/// thread). The count lives in the node; the last reference frees it.
class Expr {
 public:
  Expr() noexcept = default;
  Expr(std::nullptr_t) noexcept {}  // NOLINT: implicit, like a pointer
  /// Takes a new reference to n (n may be null).
  explicit Expr(const Node* n) noexcept;
  Expr(const Expr& o) noexcept;
  Expr(Expr&& o) noexcept : p_(o.p_) { o.p_ = nullptr; }
  Expr& operator=(const Expr& o) noexcept {
    Expr copy(o);
    swap(copy);
    return *this;
  }
  Expr& operator=(Expr&& o) noexcept {
    Expr moved(std::move(o));
    swap(moved);
    return *this;
  }
  ~Expr();

  const Node* get() const noexcept { return p_; }
  const Node* operator->() const noexcept { return p_; }
  const Node& operator*() const noexcept { return *p_; }
  explicit operator bool() const noexcept { return p_ != nullptr; }
  void reset() noexcept { Expr().swap(*this); }
  void swap(Expr& o) noexcept {
    const Node* t = p_;
    p_ = o.p_;
    o.p_ = t;
  }
  friend bool operator==(const Expr& a, const Expr& b) noexcept { return a.p_ == b.p_; }
  friend bool operator==(const Expr& a, std::nullptr_t) noexcept { return a.p_ == nullptr; }

 private:
  const Node* p_ = nullptr;
};

/// A node's operands: none for leaves, one for Neg and Der, two for the binary
/// operators, a function's arity (one or two) for Call. Never more than two,
/// so they live in the node itself: a walk reads one cache line per node.
class Operands {
 public:
  static constexpr std::size_t kMax = 2;
  Operands() = default;
  /// Throws std::invalid_argument for more than kMax operands (a caller bug).
  explicit Operands(std::vector<Expr> v);
  std::size_t size() const noexcept { return a_[1] ? 2 : (a_[0] ? 1 : 0); }
  bool empty() const noexcept { return !a_[0]; }
  const Expr& operator[](std::size_t i) const noexcept { return a_[i]; }
  const Expr* begin() const noexcept { return a_; }
  const Expr* end() const noexcept { return a_ + size(); }
  /// A copy as a vector (what the smart constructors take).
  std::vector<Expr> to_vector() const { return std::vector<Expr>(begin(), end()); }
  operator std::vector<Expr>() const { return to_vector(); }  // NOLINT: reads like the vector it was

 private:
  Expr a_[kMax];  // the operands in order; null past the last
};

/// The constructors below hash-cons: a node they make is the only live node
/// of its structure (op, constant bits, id, function and operand pointers), so
/// structurally equal trees they build are one shared DAG, and a walk or memo
/// by pointer visits each distinct sub-expression once.
///
/// Laid out in one 64-byte cache line, operands included: a 1000-rod chain
/// makes about half a million of them, and every pass walks them.
struct Node {
  mutable std::uint32_t refs = 0;  // the Exprs that point here (Expr maintains it)
  Op op = Op::Const;
  Fn fn = Fn::Sin;          // Call
  unsigned char flags = 0;  // kHas* below
  bool interned = false;    // in the constructors' table of unique nodes
  bool canonical = false;   // interned, and so are its operands, recursively: equal() is pointer equality
  int id = -1;              // Param, Var; Const: its literal's unit (units::literal_unit), -1 for none
  double value = 0.0;       // Const
  Operands args;            // operands (1 for Neg/Der, 2 for binary, the arity for Call)
  std::size_t hash = 0;     // structural hash, set by the constructors
  // Summaries of the sub-tree, set by the constructors (valid when canonical),
  // so that walks skip the parts that cannot matter to them:
  std::uint64_t var_mask = 0;   // bit (id % 64) for each Var id in the sub-tree (inside Der too)
  static constexpr unsigned char kHasTime = 1, kHasDer = 2, kHasParam = 4,
                                 kHasNonFinite = 8,   // a constant inf or NaN
                                 kHasDivByZero = 16;  // a division by the constant 0
  mutable std::uint64_t mark = 0;  // visited mark of the variable walks in expr.cpp (never nested)

  Node() = default;
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;
  ~Node();                  // leaves the table
};

inline Expr::Expr(const Node* n) noexcept : p_(n) {
  if (p_) ++p_->refs;
}
inline Expr::Expr(const Expr& o) noexcept : p_(o.p_) {
  if (p_) ++p_->refs;
}
inline Expr::~Expr() {
  if (p_ && --p_->refs == 0) delete p_;
}

// ---- construction (all fold constants and simplify trivially) -------------
// Canonical forms (listed at the top of expr.cpp): -0.0 is stored as 0.0; a Neg
// never wraps a Const or a Neg; signs float out of * and / ((-2)*x is -(2*x));
// constant factors go left and merge (3*(2*x) is 6*x); a + (-b) is a - b.
// Division by a constant zero is never folded.
/// `unit` >= 0: a literal written with a unit (`2 {mm}`, v in SI), an index
/// the units layer gives that unit's dimension (units::literal_unit), so that
/// the check reads it. Folding it with another constant drops it (the
/// result is a number the check takes as it takes any: a unit of its own).
Expr constant(double v, int unit = -1);
Expr param(int id);
Expr var(int id);
Expr time();
Expr neg(const Expr& a);
Expr add(const Expr& a, const Expr& b);
Expr sub(const Expr& a, const Expr& b);
Expr mul(const Expr& a, const Expr& b);
Expr div(const Expr& a, const Expr& b);
Expr pow(const Expr& a, const Expr& b);
/// Throws std::invalid_argument if args.size() != arity(fn) (a caller bug).
Expr call(Fn fn, std::vector<Expr> args);
/// der(Const) = der(Param) = 0 and der(t) = 1; any other operand stays a Der node.
Expr der(const Expr& a);

/// Number of arguments a function takes (min == max for all but none today).
int arity(Fn fn);
/// Name as written in the language and in dumps ("sin", "atan2", "step", ...).
const char* fn_name(Fn fn);

// ---- inspection -------------------------------------------------------------
bool is_const(const Expr& e, double* value = nullptr);
bool is_zero(const Expr& e);
bool is_one(const Expr& e);
/// Structural equality (same tree shape, ops, ids and constant bits).
bool equal(const Expr& a, const Expr& b);
struct ExprHash { std::size_t operator()(const Expr& e) const { return e->hash; } };
struct ExprEqual { bool operator()(const Expr& a, const Expr& b) const { return equal(a, b); } };

/// Ids of the Var leaves in e (inside Der too).
void collect_vars(const Expr& e, std::unordered_set<int>& out);
void collect_vars(const std::vector<Expr>& roots, std::unordered_set<int>& out);  // of all roots, one walk
/// Does Var `id` occur in e (inside Der too)? What collect_vars would say, without the set.
bool mentions_var(const Expr& e, int id);
/// Is every Var leaf of e the variable `id` (also true when e has none)?
bool mentions_only_var(const Expr& e, int id);
void collect_params(const Expr& e, std::unordered_set<int>& out);
bool depends_on_time(const Expr& e);
bool contains_der(const Expr& e);
/// Node count of the tree as printed: a shared sub-tree counts once per
/// occurrence, so structurally equal trees have equal sizes (saturates at
/// SIZE_MAX). For swell checks and CSE heuristics.
std::size_t size(const Expr& e);

// ---- transformation -----------------------------------------------------------
/// Replace Var leaves by the mapped expressions (others unchanged).
Expr substitute(const Expr& e, const std::unordered_map<int, Expr>& by_var);
/// The same substitution applied to many expressions: what substitute() sets
/// up from the whole map on every call (a mask of its variables) is set up
/// once, and the rewritten sub-expressions are remembered between calls
/// (a pass that substitutes into each of N equations stays linear in N).
class Substitution {
 public:
  explicit Substitution(std::unordered_map<int, Expr> by_var);
  ~Substitution();
  Substitution(Substitution&&) noexcept;
  Substitution& operator=(Substitution&&) noexcept;
  Expr operator()(const Expr& e);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};
/// Generic rewrite: f is called on every node, top-down; it returns nullptr to
/// keep the node (its operands are then visited and the node rebuilt through
/// the smart constructors), else the replacement, which is not visited further.
Expr rewrite(const Expr& e, const std::function<Expr(const Expr&)>& f);

/// The same operation on new operands, through the smart constructors (so the
/// result is re-simplified); e itself if the operands are unchanged.
Expr with_operands(const Expr& e, std::vector<Expr> operands);

/// Partial derivative with respect to Var `id`. Step' = 0, Abs' = Sign, Sign' = 0,
/// Min/Max' select the active branch with Step. Der nodes are treated as opaque
/// (derivative 0, also when they contain the variable) — callers expand Der first.
Expr diff_var(const Expr& e, int id);
/// Partial derivative with respect to time (explicit t only; Var leaves and Der
/// nodes have derivative 0).
Expr diff_time(const Expr& e);

/// If e is affine in the variables `unknowns`, write e = sum_j coeff[j]*x_j + rest
/// with coefficients and rest free of the unknowns, and return true
/// (coeff[j] = diff_var(e, unknowns[j]), rest = e with the unknowns set to 0).
/// Returns false, leaving coeff and rest untouched, if a coefficient depends on
/// an unknown, or an unknown occurs inside der(), step() or sign(). The ids in
/// `unknowns` must be distinct.
bool affine_in(const Expr& e, const std::vector<int>& unknowns,
               std::vector<Expr>& coeff, Expr& rest);

// ---- printing ------------------------------------------------------------------
/// Names for leaves. `var` / `param` must return a valid identifier in the
/// target syntax; `time` defaults to "t". An empty `var` / `param` prints
/// "v<id>" / "p<id>".
struct Namer {
  std::function<std::string(int)> var;
  std::function<std::string(int)> param;
  std::string time = "t";
};

/// Model syntax (used by dumps and diagnostics): infix, minimal parentheses,
/// shortest round-trip constants ("0.4", "1e-06").
std::string to_string(const Expr& e, const Namer& names);
/// C++ syntax: std::sin, std::pow, doubles always with a decimal point or
/// exponent ("2.0", "0.4"), Step as ((x) >= 0.0 ? 1.0 : 0.0), min/max via
/// std::fmin/std::fmax, Sign via a ternary, infinities and NaN through
/// std::numeric_limits (the text needs <cmath> and <limits>). Der must have been
/// removed: a leftover one prints as MBGC_DER_NOT_REMOVED(...), which does not
/// compile.
///
/// With `ops`, also adds to it the floating-point operations of the printed
/// text, counted by the printer as it writes them (so exactly what the text
/// says, before the C++ compiler's own optimisations):
///   add     each binary + and -
///   mul     each binary *, including those of x^2 and x^3 written as (x*x)
///           and (x*x*x) (one and two)
///   div     each binary /
///   neg     each unary minus applied at run time; not the sign of a numeric
///           literal: -2.0 * x is the literal -2.0 times x (one mul)
///   call    each call of a math function: std::sin, ..., std::pow,
///           std::sqrt, std::exp, std::fabs, std::fmin, std::fmax
///   compare each comparison: step's >= (one), sign's > and < (two)
/// Reads of variables, parameters and constants cost nothing. sign(x) writes
/// its argument twice, so x's operations count twice, as written.
struct CppOps {
  std::size_t add = 0, mul = 0, div = 0, neg = 0, call = 0, compare = 0;
  std::size_t total() const { return add + mul + div + neg + call + compare; }
  CppOps& operator+=(const CppOps& o) {
    add += o.add, mul += o.mul, div += o.div, neg += o.neg, call += o.call, compare += o.compare;
    return *this;
  }
  bool operator==(const CppOps&) const = default;
};
std::string to_cpp(const Expr& e, const Namer& names, CppOps* ops = nullptr);
/// Sub-expressions printed as a name: `named` returns the name of a node that
/// has one (a common subexpression defined before), else nullptr.
using NamedNodes = std::function<const std::string*(const Expr&)>;
/// to_cpp, printing each named node as its name, exactly as if it were a
/// variable of that name (what substituting variables for them would print;
/// a named node costs no operations).
std::string to_cpp(const Expr& e, const Namer& names, const NamedNodes& named, CppOps* ops = nullptr);

}  // namespace mbgc::ir
