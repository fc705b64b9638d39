// ir/expr.cpp — see expr.hpp.
//
// Canonical forms produced by the smart constructors (other passes may rely on
// them, the unit tests pin them down):
//   * constants: -0.0 is stored as 0.0 and every NaN as the quiet NaN, so that
//     structural equality of constants is bit equality;
//   * a Neg never wraps a Const or another Neg;
//   * signs float outward through * and /: (-a)*b, a*(-b), (-2)*a and a/(-2)
//     become Neg(a*b), Neg(a*b), Neg(2*a) and Neg(a/2);
//   * a constant factor of a product is on the left, and c1*(c2*x) is (c1*c2)*x;
//   * a + (-b) is a - b, a - (-b) is a + b, also for negative constants b.
#include "ir/expr.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

namespace mbgc::ir {
namespace {

// ---- hashing ----------------------------------------------------------------

std::uint64_t mix64(std::uint64_t x) {  // splitmix64 finaliser
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

std::uint64_t combine(std::uint64_t h, std::uint64_t v) {
  return mix64(h ^ (mix64(v) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2)));
}

bool shallow_equal(const Node* a, const Node* b);

std::uint64_t var_bit(int id) { return std::uint64_t{1} << (static_cast<unsigned>(id) & 63u); }

// Can the sub-tree n contain one of the variables in `mask`? (Only canonical
// nodes carry the summaries; for others the answer is a conservative yes.)
bool may_mention(const Node* n, std::uint64_t mask) { return !n->canonical || (n->var_mask & mask) != 0; }
// Has the sub-tree n the flag? Conservative yes for non-canonical nodes.
bool may_have(const Node* n, unsigned char flag) { return !n->canonical || (n->flags & flag) != 0; }

// The table of unique nodes (hash-consing): open addressing with linear
// probing over (hash, node) slots, so that a look-up costs about one cache
// line, and no allocation per node. A node is found by its shallow parts
// (op, constant bits, id, function) and its operand pointers.
class InternTable {
 public:
  struct Key {
    std::uint64_t hash;
    Op op;
    double value;
    int id;
    Fn fn;
    const std::vector<Expr>& args;
    bool matches(const Node* n) const {
      if (n->hash != hash || n->op != op || n->args.size() != args.size()) return false;
      switch (op) {
        case Op::Const:
          if (std::bit_cast<std::uint64_t>(n->value) != std::bit_cast<std::uint64_t>(value) || n->id != id) return false;
          break;
        case Op::Param:
        case Op::Var:
          if (n->id != id) return false;
          break;
        case Op::Call:
          if (n->fn != fn) return false;
          break;
        default: break;
      }
      for (std::size_t i = 0; i < args.size(); ++i)
        if (n->args[i] != args[i]) return false;
      return true;
    }
  };

  /// The live node equal to `key`, else nullptr; `slot` is where to insert it.
  const Node* find(const Key& key, std::size_t& slot) {
    if ((size_ + 1) * 2 > slots_.size()) grow();
    std::size_t i = static_cast<std::size_t>(key.hash) & mask_;
    while (const Node* n = slots_[i].node) {
      if (slots_[i].hash == key.hash && key.matches(n)) return n;
      i = (i + 1) & mask_;
    }
    slot = i;
    return nullptr;
  }
  /// Right after a find() that returned nullptr with this slot.
  void insert_at(std::size_t slot, const Node* n) {
    slots_[slot] = {static_cast<std::uint64_t>(n->hash), n};
    ++size_;
  }
  void erase(const Node* n) {
    std::size_t i = static_cast<std::size_t>(n->hash) & mask_;
    while (slots_[i].node != n) i = (i + 1) & mask_;  // it is in the table
    // Backward-shift deletion: no tombstones, probe runs stay unbroken.
    std::size_t j = i;
    for (;;) {
      j = (j + 1) & mask_;
      if (!slots_[j].node) break;
      std::size_t home = static_cast<std::size_t>(slots_[j].hash) & mask_;
      bool stays = i <= j ? (i < home && home <= j) : (i < home || home <= j);
      if (stays) continue;
      slots_[i] = slots_[j];
      i = j;
    }
    slots_[i] = {};
    --size_;
  }

 private:
  struct Slot {
    std::uint64_t hash = 0;
    const Node* node = nullptr;
  };
  void grow() {
    std::vector<Slot> old = std::move(slots_);
    slots_.assign(old.empty() ? 1024 : old.size() * 2, Slot{});
    mask_ = slots_.size() - 1;
    for (const Slot& s : old) {
      if (!s.node) continue;
      std::size_t i = static_cast<std::size_t>(s.hash) & mask_;
      while (slots_[i].node) i = (i + 1) & mask_;
      slots_[i] = s;
    }
  }
  std::vector<Slot> slots_;
  std::size_t mask_ = 0;
  std::size_t size_ = 0;
};
InternTable& intern_table() {
  static InternTable* table = new InternTable();  // never destroyed: static Exprs outlive it otherwise
  return *table;
}

Expr make(Op op, std::vector<Expr> args, double value = 0.0, int id = -1, Fn fn = Fn::Sin) {
  std::uint64_t h = mix64(static_cast<std::uint64_t>(op) + 0x51afd7ed558ccdULL);
  switch (op) {
    case Op::Const:
      h = combine(h, std::bit_cast<std::uint64_t>(value));
      if (id >= 0) h = combine(h, static_cast<std::uint64_t>(id));  // a literal's unit
      break;
    case Op::Param:
    case Op::Var: h = combine(h, static_cast<std::uint64_t>(static_cast<std::int64_t>(id))); break;
    case Op::Call: h = combine(h, static_cast<std::uint64_t>(fn)); break;
    default: break;
  }
  for (const Expr& a : args) h = combine(h, a->hash);
  InternTable& table = intern_table();
  std::size_t slot = 0;
  const InternTable::Key key{static_cast<std::uint64_t>(static_cast<std::size_t>(h)), op, value, id, fn, args};
  if (const Node* existing = table.find(key, slot)) return Expr(existing);
  Node* n = new Node();
  n->op = op;
  n->args = Operands(std::move(args));
  switch (op) {
    case Op::Const: n->value = value, n->id = id; break;
    case Op::Param:
    case Op::Var: n->id = id; break;
    case Op::Call: n->fn = fn; break;
    default: break;
  }
  n->hash = static_cast<std::size_t>(h);
  bool canonical = true;
  unsigned char flags = 0;
  std::uint64_t mask = 0;
  switch (op) {
    case Op::Const:
      if (!std::isfinite(value)) flags |= Node::kHasNonFinite;
      break;
    case Op::Param: flags |= Node::kHasParam; break;
    case Op::Var: mask |= var_bit(id); break;
    case Op::Time: flags |= Node::kHasTime; break;
    case Op::Der: flags |= Node::kHasDer; break;
    case Op::Div:
      if (n->args[1]->op == Op::Const && n->args[1]->value == 0.0) flags |= Node::kHasDivByZero;
      break;
    default: break;
  }
  for (const Expr& a : n->args) {
    canonical = canonical && a->canonical;
    flags |= a->flags;
    mask |= a->var_mask;
  }
  n->flags = flags;
  n->var_mask = mask;
  table.insert_at(slot, n);
  n->interned = true;
  n->canonical = canonical;
  return Expr(n);
}

Expr make1(Op op, const Expr& a) { return make(op, {a}); }
Expr make2(Op op, const Expr& a, const Expr& b) { return make(op, {a, b}); }

const Expr& zero() {
  static const Expr z = make(Op::Const, {}, 0.0);
  return z;
}
const Expr& one() {
  static const Expr o = make(Op::Const, {}, 1.0);
  return o;
}

bool cval(const Expr& e, double& v) {
  if (e->op != Op::Const) return false;
  v = e->value;
  return true;
}

double eval_fn(Fn fn, const double* x) {
  switch (fn) {
    case Fn::Sin: return std::sin(x[0]);
    case Fn::Cos: return std::cos(x[0]);
    case Fn::Tan: return std::tan(x[0]);
    case Fn::Asin: return std::asin(x[0]);
    case Fn::Acos: return std::acos(x[0]);
    case Fn::Atan: return std::atan(x[0]);
    case Fn::Atan2: return std::atan2(x[0], x[1]);
    case Fn::Sinh: return std::sinh(x[0]);
    case Fn::Cosh: return std::cosh(x[0]);
    case Fn::Tanh: return std::tanh(x[0]);
    case Fn::Exp: return std::exp(x[0]);
    case Fn::Log: return std::log(x[0]);
    case Fn::Sqrt: return std::sqrt(x[0]);
    case Fn::Abs: return std::fabs(x[0]);
    case Fn::Sign: return x[0] > 0.0 ? 1.0 : (x[0] < 0.0 ? -1.0 : 0.0);
    case Fn::Min: return std::fmin(x[0], x[1]);
    case Fn::Max: return std::fmax(x[0], x[1]);
    case Fn::Step: return x[0] >= 0.0 ? 1.0 : 0.0;
    case Fn::Frozen: return x[0];
    case Fn::Select: return x[0] >= 0.0 ? 1.0 : 0.0;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

// ---- structural equality ----------------------------------------------------

bool shallow_equal(const Node* a, const Node* b) {
  if (a->hash != b->hash || a->op != b->op || a->args.size() != b->args.size()) return false;
  switch (a->op) {
    case Op::Const:
      return std::bit_cast<std::uint64_t>(a->value) == std::bit_cast<std::uint64_t>(b->value) && a->id == b->id;
    case Op::Param:
    case Op::Var:
      return a->id == b->id;
    case Op::Call:
      return a->fn == b->fn;
    default:
      return true;
  }
}

enum class Cmp { Equal, Different, OutOfBudget };

// Plain recursion with a work budget: enough for ordinary trees, and no
// allocation. Separately built DAGs with heavy sharing would make it
// exponential, so past the budget we restart with a memo of proven pairs.
Cmp equal_budget(const Node* a, const Node* b, long& budget) {
  if (a == b) return Cmp::Equal;
  if (!shallow_equal(a, b)) return Cmp::Different;
  if (--budget < 0) return Cmp::OutOfBudget;
  for (std::size_t i = 0; i < a->args.size(); ++i) {
    Cmp c = equal_budget(a->args[i].get(), b->args[i].get(), budget);
    if (c != Cmp::Equal) return c;
  }
  return Cmp::Equal;
}

struct PairHash {
  std::size_t operator()(const std::pair<const Node*, const Node*>& p) const {
    return static_cast<std::size_t>(combine(reinterpret_cast<std::uintptr_t>(p.first),
                                            reinterpret_cast<std::uintptr_t>(p.second)));
  }
};
using PairSet = std::unordered_set<std::pair<const Node*, const Node*>, PairHash>;

bool equal_memo(const Node* a, const Node* b, PairSet& proven) {
  if (a == b) return true;
  if (!shallow_equal(a, b)) return false;
  if (a->args.empty()) return true;
  if (proven.count({a, b})) return true;
  for (std::size_t i = 0; i < a->args.size(); ++i)
    if (!equal_memo(a->args[i].get(), b->args[i].get(), proven)) return false;
  proven.insert({a, b});
  return true;
}

// ---- traversal helpers --------------------------------------------------------

// Calls f on every distinct node (by pointer) of e; stops early when f returns false.
template <class F>
void visit_unique(const Expr& e, F&& f) {
  std::unordered_set<const Node*> seen;
  std::vector<const Node*> stack{e.get()};
  while (!stack.empty()) {
    const Node* n = stack.back();
    stack.pop_back();
    if (!seen.insert(n).second) continue;
    if (!f(n)) return;
    for (const Expr& a : n->args) stack.push_back(a.get());
  }
}

// Rebuild e with new operands through the smart constructors; returns e itself
// when nothing changed.
Expr rebuild(const Expr& e, std::vector<Expr> args) {
  bool same = true;
  for (std::size_t i = 0; i < args.size(); ++i)
    if (args[i] != e->args[i]) same = false;
  if (same) return e;
  switch (e->op) {
    case Op::Neg: return neg(args[0]);
    case Op::Add: return add(args[0], args[1]);
    case Op::Sub: return sub(args[0], args[1]);
    case Op::Mul: return mul(args[0], args[1]);
    case Op::Div: return div(args[0], args[1]);
    case Op::Pow: return pow(args[0], args[1]);
    case Op::Call: return call(e->fn, std::move(args));
    case Op::Der: return der(args[0]);
    default: return e;  // leaves have no operands
  }
}

class Rewriter {
 public:
  explicit Rewriter(const std::function<Expr(const Expr&)>& f) : f_(f) {}
  Expr run(const Expr& e) {
    auto it = memo_.find(e.get());
    if (it != memo_.end()) return it->second;
    Expr r = f_(e);
    if (!r) {
      std::vector<Expr> args;
      args.reserve(e->args.size());
      for (const Expr& a : e->args) args.push_back(run(a));
      r = rebuild(e, std::move(args));
    }
    memo_.emplace(e.get(), r);
    return r;
  }

 private:
  const std::function<Expr(const Expr&)>& f_;
  std::unordered_map<const Node*, Expr> memo_;
};

// ---- differentiation ------------------------------------------------------------

class Differentiator {
 public:
  Differentiator(int id, bool wrt_time) : id_(id), wrt_time_(wrt_time) {}

  Expr d(const Expr& e) {
    // A sub-tree without the variable (or t) has derivative exactly 0 (what
    // compute() would build from zero operands), unless an inf/NaN constant
    // or a division by 0 makes a 0*inf or a 0/0 along the way.
    if (e->canonical && !(e->flags & (Node::kHasNonFinite | Node::kHasDivByZero)) &&
        (wrt_time_ ? !(e->flags & Node::kHasTime) : !(e->var_mask & var_bit(id_))))
      return zero();
    auto it = memo_.find(e.get());
    if (it != memo_.end()) return it->second;
    Expr r = compute(e);
    memo_.emplace(e.get(), r);
    return r;
  }

 private:
  Expr compute(const Expr& e) {
    switch (e->op) {
      case Op::Const:
      case Op::Param:
      case Op::Der:  // opaque
        return zero();
      case Op::Var:
        return (!wrt_time_ && e->id == id_) ? one() : zero();
      case Op::Time:
        return wrt_time_ ? one() : zero();
      case Op::Neg:
        return neg(d(e->args[0]));
      case Op::Add:
        return add(d(e->args[0]), d(e->args[1]));
      case Op::Sub:
        return sub(d(e->args[0]), d(e->args[1]));
      case Op::Mul: {
        const Expr &a = e->args[0], &b = e->args[1];
        return add(mul(d(a), b), mul(a, d(b)));
      }
      case Op::Div: {
        const Expr &a = e->args[0], &b = e->args[1];
        Expr da = d(a), db = d(b);
        if (is_zero(db)) return div(da, b);
        Expr b2 = pow(b, constant(2.0));
        if (is_zero(da)) return neg(div(mul(a, db), b2));
        return div(sub(mul(da, b), mul(a, db)), b2);
      }
      case Op::Pow: {
        const Expr &a = e->args[0], &b = e->args[1];
        Expr da = d(a), db = d(b);
        if (is_zero(db)) {
          if (is_zero(da)) return zero();
          return mul(mul(b, pow(a, sub(b, one()))), da);
        }
        Expr log_a = call(Fn::Log, {a});
        if (is_zero(da)) return mul(e, mul(db, log_a));
        return mul(e, add(mul(db, log_a), div(mul(b, da), a)));
      }
      case Op::Call:
        return call_derivative(e);
    }
    return zero();
  }

  Expr call_derivative(const Expr& e) {
    const std::vector<Expr>& x = e->args;
    switch (e->fn) {
      case Fn::Atan2: {
        const Expr &y = x[0], &xx = x[1];
        Expr dy = d(y), dx = d(xx);
        if (is_zero(dy) && is_zero(dx)) return zero();
        return div(sub(mul(xx, dy), mul(y, dx)),
                   add(pow(xx, constant(2.0)), pow(y, constant(2.0))));
      }
      case Fn::Frozen:
        return zero();
      case Fn::Min:
      case Fn::Max: {
        const Expr &a = x[0], &b = x[1];
        Expr da = d(a), db = d(b);
        if (is_zero(da) && is_zero(db)) return zero();
        // (a kink of min/max is integrated through, not an event: its derivative selects a side)
        Expr s = e->fn == Fn::Min ? call(Fn::Select, {sub(b, a)}) : call(Fn::Select, {sub(a, b)});
        return add(mul(s, da), mul(sub(one(), s), db));
      }
      default:
        break;
    }
    const Expr& a = x[0];
    Expr da = d(a);
    if (is_zero(da)) return zero();
    Expr two = constant(2.0);
    Expr fp;
    switch (e->fn) {
      case Fn::Sin: fp = call(Fn::Cos, {a}); break;
      case Fn::Cos: fp = neg(call(Fn::Sin, {a})); break;
      case Fn::Tan: fp = add(one(), pow(e, two)); break;
      case Fn::Asin: fp = div(one(), call(Fn::Sqrt, {sub(one(), pow(a, two))})); break;
      case Fn::Acos: fp = neg(div(one(), call(Fn::Sqrt, {sub(one(), pow(a, two))}))); break;
      case Fn::Atan: fp = div(one(), add(one(), pow(a, two))); break;
      case Fn::Sinh: fp = call(Fn::Cosh, {a}); break;
      case Fn::Cosh: fp = call(Fn::Sinh, {a}); break;
      case Fn::Tanh: fp = sub(one(), pow(e, two)); break;
      case Fn::Exp: fp = e; break;
      case Fn::Log: return div(da, a);
      case Fn::Sqrt: return div(da, mul(two, e));
      case Fn::Abs: fp = call(Fn::Sign, {a}); break;
      case Fn::Sign:
      case Fn::Step:
      case Fn::Select:
      case Fn::Frozen: return zero();
      case Fn::Atan2:
      case Fn::Min:
      case Fn::Max: return zero();  // handled above
    }
    return mul(fp, da);
  }

  int id_;
  bool wrt_time_;
  std::unordered_map<const Node*, Expr> memo_;
};

}  // namespace

static_assert(sizeof(void*) != 8 || sizeof(Node) == 64, "a node is one cache line");

Operands::Operands(std::vector<Expr> v) {
  if (v.size() > kMax) throw std::invalid_argument(fmt::format("mbgc::ir::Operands: {} operands, at most {}", v.size(), kMax));
  for (std::size_t i = 0; i < v.size(); ++i) a_[i] = std::move(v[i]);
}

// ---- construction ---------------------------------------------------------------

Expr constant(double v, int unit) {
  if (std::isnan(v)) v = std::numeric_limits<double>::quiet_NaN();
  if (unit >= 0) return make(Op::Const, {}, v == 0.0 ? 0.0 : v, unit);
  if (v == 0.0) return zero();  // also maps -0.0 to 0.0
  if (v == 1.0) return one();
  return make(Op::Const, {}, v);
}

Expr param(int id) { return make(Op::Param, {}, 0.0, id); }
Expr var(int id) { return make(Op::Var, {}, 0.0, id); }

Expr time() {
  static const Expr t = make(Op::Time, {});
  return t;
}

Expr neg(const Expr& a) {
  double x = 0.0;
  if (cval(a, x)) return constant(-x, a->id);  // -2 {m} keeps its unit
  if (a->op == Op::Neg) return a->args[0];
  return make1(Op::Neg, a);
}

/// The argument u if e is fn(u)*fn(u), else null.
static const Node* square_of_call(const Expr& e, Fn fn) {
  if (e->op != Op::Mul || e->args[0].get() != e->args[1].get()) return nullptr;
  const Expr& f = e->args[0];
  return f->op == Op::Call && f->fn == fn ? f->args[0].get() : nullptr;
}

Expr add(const Expr& a, const Expr& b) {
  double x = 0.0, y = 0.0;
  bool ca = cval(a, x), cb = cval(b, y);
  if (ca && cb) return constant(x + y);
  if (ca && x == 0.0) return b;
  if (cb && y == 0.0) return a;
  // cos(u)^2 + sin(u)^2 = 1 (a universal joint's turned axis, unit by construction)
  if (const Node* u = square_of_call(a, Fn::Cos); u && u == square_of_call(b, Fn::Sin)) return constant(1);
  if (const Node* u = square_of_call(a, Fn::Sin); u && u == square_of_call(b, Fn::Cos)) return constant(1);
  if (b->op == Op::Neg) return sub(a, b->args[0]);
  if (cb && y < 0.0) return sub(a, constant(-y, b->id));
  return make2(Op::Add, a, b);
}

Expr sub(const Expr& a, const Expr& b) {
  double x = 0.0, y = 0.0;
  bool ca = cval(a, x), cb = cval(b, y);
  if (ca && cb) return constant(x - y);
  if (cb && y == 0.0) return a;
  if (ca && x == 0.0) return neg(b);
  if (equal(a, b)) return zero();
  if (b->op == Op::Neg) return add(a, b->args[0]);
  if (cb && y < 0.0) return add(a, constant(-y, b->id));
  return make2(Op::Sub, a, b);
}

Expr mul(const Expr& a, const Expr& b) {
  double x = 0.0, y = 0.0;
  bool ca = cval(a, x), cb = cval(b, y);
  if (ca && cb) return constant(x * y);
  if ((ca && x == 0.0) || (cb && y == 0.0)) return zero();
  // x * 1 is x, unless the 1 has a unit (`1 {s} * v` is a length)
  if (ca && x == 1.0 && a->id < 0) return b;
  if (cb && y == 1.0 && b->id < 0) return a;
  bool na = a->op == Op::Neg, nb = b->op == Op::Neg;
  if (na && nb) return mul(a->args[0], b->args[0]);
  if (na) return neg(mul(a->args[0], b));
  if (nb) return neg(mul(a, b->args[0]));
  if (ca && x < 0.0) return neg(mul(constant(-x, a->id), b));  // also a*(-1) = -a
  if (cb && y < 0.0) return neg(mul(a, constant(-y, b->id)));
  if (cb) return mul(b, a);  // constants to the left
  if (ca && b->op == Op::Mul && b->args[0]->op == Op::Const)
    return mul(constant(x * b->args[0]->value), b->args[1]);
  return make2(Op::Mul, a, b);
}

namespace {

/// e >= 0 for every value of its variables, as far as its form shows (a
/// square, a sum or product of such, a non-negative constant).
bool non_negative(const Expr& e, int depth = 0);

/// e > 0 for every value of its variables, as far as its form shows:
/// 1 + s^2 is, x is not. Shallow (a few levels), so it stays cheap.
bool positive(const Expr& e, int depth = 0) {
  if (e->op == Op::Const) return e->value > 0.0;
  if (depth > 4) return false;
  switch (e->op) {
    case Op::Add:
      return (positive(e->args[0], depth + 1) && non_negative(e->args[1], depth + 1)) ||
             (non_negative(e->args[0], depth + 1) && positive(e->args[1], depth + 1));
    case Op::Mul:
    case Op::Div:
      return positive(e->args[0], depth + 1) && positive(e->args[1], depth + 1);
    case Op::Call:
      return e->fn == Fn::Exp || e->fn == Fn::Cosh;
    default:
      return false;
  }
}

bool non_negative(const Expr& e, int depth) {
  if (e->op == Op::Const) return e->value >= 0.0;
  if (depth > 4) return false;
  switch (e->op) {
    case Op::Add:
      return non_negative(e->args[0], depth + 1) && non_negative(e->args[1], depth + 1);
    case Op::Mul:
      return equal(e->args[0], e->args[1]) ||
             (non_negative(e->args[0], depth + 1) && non_negative(e->args[1], depth + 1));
    case Op::Pow: {
      double y = 0.0;
      return is_const(e->args[1], &y) && y == 2.0;
    }
    case Op::Call:
      return e->fn == Fn::Abs || e->fn == Fn::Sqrt || e->fn == Fn::Exp || e->fn == Fn::Cosh;
    default:
      return positive(e, depth);
  }
}

}  // namespace

Expr div(const Expr& a, const Expr& b) {
  double x = 0.0, y = 0.0;
  bool ca = cval(a, x), cb = cval(b, y);
  const bool by_zero = cb && y == 0.0;  // never folded away (but signs still float)
  if (ca && cb && !by_zero) return constant(x / y);
  if (ca && x == 0.0 && !by_zero) return zero();
  if (cb && y == 1.0 && b->id < 0) return a;
  if (equal(a, b) && positive(b)) return one();  // a section's R33, (1 + s^2) / (1 + s^2); x / x stays (x may be 0)
  bool na = a->op == Op::Neg, nb = b->op == Op::Neg;
  if (na && nb) return div(a->args[0], b->args[0]);
  if (na) return neg(div(a->args[0], b));
  if (nb) return neg(div(a, b->args[0]));
  if (ca && x < 0.0) return neg(div(constant(-x, a->id), b));
  if (cb && y < 0.0) return neg(div(a, constant(-y, b->id)));
  return make2(Op::Div, a, b);
}

Expr pow(const Expr& a, const Expr& b) {
  double x = 0.0, y = 0.0;
  bool ca = cval(a, x), cb = cval(b, y);
  if (ca && cb) return constant(std::pow(x, y));
  if (cb && y == 1.0) return a;
  if (cb && y == 0.0) return one();
  return make2(Op::Pow, a, b);
}

Expr call(Fn fn, std::vector<Expr> args) {
  if (static_cast<int>(args.size()) != arity(fn))
    throw std::invalid_argument(fmt::format("mbgc::ir::call: {}() takes {} argument(s), got {}",
                                            fn_name(fn), arity(fn), args.size()));
  double x[2] = {0.0, 0.0};
  bool all_const = true;
  for (std::size_t i = 0; i < args.size(); ++i)
    if (!cval(args[i], x[i])) all_const = false;
  if (all_const) return constant(eval_fn(fn, x));
  return make(Op::Call, std::move(args), 0.0, -1, fn);
}

Expr der(const Expr& a) {
  if (a->op == Op::Const || a->op == Op::Param) return zero();
  if (a->op == Op::Time) return one();
  return make1(Op::Der, a);
}

int arity(Fn fn) {
  switch (fn) {
    case Fn::Atan2:
    case Fn::Min:
    case Fn::Max: return 2;
    default: return 1;
  }
}

const char* fn_name(Fn fn) {
  switch (fn) {
    case Fn::Sin: return "sin";
    case Fn::Cos: return "cos";
    case Fn::Tan: return "tan";
    case Fn::Asin: return "asin";
    case Fn::Acos: return "acos";
    case Fn::Atan: return "atan";
    case Fn::Atan2: return "atan2";
    case Fn::Sinh: return "sinh";
    case Fn::Cosh: return "cosh";
    case Fn::Tanh: return "tanh";
    case Fn::Exp: return "exp";
    case Fn::Log: return "log";
    case Fn::Sqrt: return "sqrt";
    case Fn::Abs: return "abs";
    case Fn::Sign: return "sign";
    case Fn::Min: return "min";
    case Fn::Max: return "max";
    case Fn::Step: return "heaviside";
    case Fn::Frozen: return "frozen";
    case Fn::Select: return "select";
  }
  return "?";
}

// ---- inspection --------------------------------------------------------------------

bool is_const(const Expr& e, double* value) {
  if (e->op != Op::Const) return false;
  if (value) *value = e->value;
  return true;
}

bool is_zero(const Expr& e) { return e->op == Op::Const && e->value == 0.0; }
bool is_one(const Expr& e) { return e->op == Op::Const && e->value == 1.0; }

Node::~Node() {
  if (interned) intern_table().erase(this);
}

bool equal(const Expr& a, const Expr& b) {
  if (a == b) return true;
  if (!a || !b) return false;
  if (a->canonical && b->canonical) return false;  // hash-consed: one node per structure
  long budget = 4096;
  Cmp c = equal_budget(a.get(), b.get(), budget);
  if (c != Cmp::OutOfBudget) return c == Cmp::Equal;
  PairSet proven;
  return equal_memo(a.get(), b.get(), proven);
}

namespace {
// The variable walks: every distinct node once, told apart by a mark in the
// node (a fresh number per walk, 64 bits: never reused) rather than a set of
// visited pointers, entering only sub-trees that can hold a variable in
// `mask`. on_var returns false to stop. No callback can start another walk.
struct WalkState {
  std::uint64_t epoch = 0;         // shared by every instantiation of walk_vars: marks must not repeat
  std::vector<const Node*> stack;  // reused: no allocation per walk
};
WalkState& walk_state() {
  static WalkState state;
  return state;
}

template <class OnVar>
void walk_vars(const Node* const* roots, std::size_t count, std::uint64_t mask, OnVar&& on_var) {
  WalkState& ws = walk_state();
  std::vector<const Node*>& stack = ws.stack;
  const std::uint64_t mark = ++ws.epoch;
  stack.clear();
  for (std::size_t i = 0; i < count; ++i)
    if (may_mention(roots[i], mask)) stack.push_back(roots[i]);
  while (!stack.empty()) {
    const Node* n = stack.back();
    stack.pop_back();
    if (n->mark == mark) continue;
    n->mark = mark;
    if (n->op == Op::Var && !on_var(n->id)) return;
    for (const Expr& a : n->args)
      if (may_mention(a.get(), mask)) stack.push_back(a.get());
  }
}
constexpr std::uint64_t kAnyVar = ~std::uint64_t{0};
}  // namespace

// Same ids, inserted in the same order as a walk of every node would.
void collect_vars(const Expr& e, std::unordered_set<int>& out) {
  const Node* root = e.get();
  walk_vars(&root, 1, kAnyVar, [&](int id) {
    out.insert(id);
    return true;
  });
}

void collect_vars(const std::vector<Expr>& roots, std::unordered_set<int>& out) {
  // One walk over the union: the roots (a torn loop's matrix entries) share most nodes.
  std::vector<const Node*> r;
  r.reserve(roots.size());
  for (const Expr& e : roots) r.push_back(e.get());
  walk_vars(r.data(), r.size(), kAnyVar, [&](int id) {
    out.insert(id);
    return true;
  });
}

bool mentions_var(const Expr& e, int id) {
  bool found = false;
  const Node* root = e.get();
  walk_vars(&root, 1, var_bit(id), [&](int v) {
    found = v == id;
    return !found;
  });
  return found;
}

bool mentions_only_var(const Expr& e, int id) {
  if (e->canonical && (e->var_mask & ~var_bit(id)) != 0) return false;  // another variable is in there
  bool only = true;
  const Node* root = e.get();
  walk_vars(&root, 1, kAnyVar, [&](int v) {
    only = v == id;
    return only;
  });
  return only;
}

void collect_params(const Expr& e, std::unordered_set<int>& out) {
  if (!may_have(e.get(), Node::kHasParam)) return;
  visit_unique(e, [&](const Node* n) {
    if (n->op == Op::Param) out.insert(n->id);
    return true;
  });
}

bool depends_on_time(const Expr& e) {
  if (e->canonical) return (e->flags & Node::kHasTime) != 0;
  bool found = false;
  visit_unique(e, [&](const Node* n) {
    if (n->op == Op::Time) found = true;
    return !found;
  });
  return found;
}

bool contains_der(const Expr& e) {
  if (e->canonical) return (e->flags & Node::kHasDer) != 0;
  bool found = false;
  visit_unique(e, [&](const Node* n) {
    if (n->op == Op::Der) found = true;
    return !found;
  });
  return found;
}

namespace {
std::size_t tree_size(const Node* n, std::unordered_map<const Node*, std::size_t>& memo) {
  if (n->args.empty()) return 1;
  auto it = memo.find(n);
  if (it != memo.end()) return it->second;
  constexpr std::size_t kMax = std::numeric_limits<std::size_t>::max();
  std::size_t s = 1;
  for (const Expr& a : n->args) {
    std::size_t k = tree_size(a.get(), memo);
    s = (k > kMax - s) ? kMax : s + k;
  }
  memo.emplace(n, s);
  return s;
}
}  // namespace

std::size_t size(const Expr& e) {
  std::unordered_map<const Node*, std::size_t> memo;
  return tree_size(e.get(), memo);
}

// ---- transformation ----------------------------------------------------------------

namespace {
// substitute(): a Rewriter that does not enter sub-trees without a mapped
// variable (they would come back unchanged).
class Substituter {
 public:
  explicit Substituter(const std::unordered_map<int, Expr>& by_var) : by_var_(by_var) {
    for (const auto& [id, x] : by_var) mask_ |= var_bit(id);
  }
  Expr run(const Expr& e) {
    if (!may_mention(e.get(), mask_)) return e;
    if (e->op == Op::Var) {
      auto it = by_var_.find(e->id);
      return it == by_var_.end() ? e : it->second;
    }
    auto it = memo_.find(e.get());
    if (it != memo_.end()) return it->second.second;
    std::vector<Expr> args;
    args.reserve(e->args.size());
    for (const Expr& a : e->args) args.push_back(run(a));
    Expr r = rebuild(e, std::move(args));
    memo_.emplace(e.get(), std::pair{e, r});
    return r;
  }

 private:
  const std::unordered_map<int, Expr>& by_var_;
  std::uint64_t mask_ = 0;
  // node -> (the node, its result): the memo holds the node alive, so that
  // its address is not given to another expression while the memo lasts (a
  // Substitution lives across calls; a freed node's address reused by the
  // next expression found the first one's result).
  std::unordered_map<const Node*, std::pair<Expr, Expr>> memo_;
};
}  // namespace

Expr substitute(const Expr& e, const std::unordered_map<int, Expr>& by_var) {
  if (by_var.empty()) return e;
  return Substituter(by_var).run(e);
}

struct Substitution::Impl {  // on the heap: the substituter refers to the map, which must not move
  std::unordered_map<int, Expr> by_var;
  Substituter substituter;
  explicit Impl(std::unordered_map<int, Expr> m) : by_var(std::move(m)), substituter(by_var) {}
};
Substitution::Substitution(std::unordered_map<int, Expr> by_var) : impl_(std::make_unique<Impl>(std::move(by_var))) {}
Substitution::~Substitution() = default;
Substitution::Substitution(Substitution&&) noexcept = default;
Substitution& Substitution::operator=(Substitution&&) noexcept = default;
Expr Substitution::operator()(const Expr& e) { return impl_->by_var.empty() ? e : impl_->substituter.run(e); }

Expr rewrite(const Expr& e, const std::function<Expr(const Expr&)>& f) {
  return Rewriter(f).run(e);
}

Expr diff_var(const Expr& e, int id) { return Differentiator(id, false).d(e); }
Expr diff_time(const Expr& e) { return Differentiator(-1, true).d(e); }

bool affine_in(const Expr& e, const std::vector<int>& unknowns, std::vector<Expr>& coeff,
               Expr& rest) {
  const std::unordered_set<int> u(unknowns.begin(), unknowns.end());
  std::uint64_t umask = 0;
  for (int id : unknowns) umask |= var_bit(id);
  std::unordered_map<const Node*, bool> memo;
  // Does the subtree mention an unknown?
  std::function<bool(const Node*)> mentions = [&](const Node* n) -> bool {
    if (!may_mention(n, umask)) return false;
    if (n->op == Op::Var) return u.count(n->id) > 0;
    if (n->args.empty()) return false;
    auto it = memo.find(n);
    if (it != memo.end()) return it->second;
    bool r = false;
    for (const Expr& a : n->args)
      if (mentions(a.get())) {
        r = true;
        break;
      }
    memo.emplace(n, r);
    return r;
  };
  // Dependence the derivative does not see: Der is opaque, step/sign/select
  // have derivative 0 almost everywhere but are not affine, frozen is x.
  // Only sub-trees that mention an unknown can hide one.
  bool hidden = false;
  {
    std::unordered_set<const Node*> seen;
    std::vector<const Node*> stack;
    if (mentions(e.get())) stack.push_back(e.get());
    while (!stack.empty() && !hidden) {
      const Node* n = stack.back();
      stack.pop_back();
      if (!seen.insert(n).second) continue;
      bool opaque = n->op == Op::Der ||
                    (n->op == Op::Call && (n->fn == Fn::Step || n->fn == Fn::Sign || n->fn == Fn::Select ||
                                           n->fn == Fn::Frozen));
      if (opaque) hidden = true;  // it mentions an unknown: only such nodes are pushed
      for (const Expr& a : n->args)
        if (mentions(a.get())) stack.push_back(a.get());
    }
  }
  if (hidden) return false;

  std::vector<Expr> c;
  c.reserve(unknowns.size());
  for (int id : unknowns) {
    Expr ci = diff_var(e, id);
    if (mentions(ci.get())) return false;
    c.push_back(std::move(ci));
  }
  std::unordered_map<int, Expr> zeros;
  for (int id : unknowns) zeros.emplace(id, zero());
  rest = substitute(e, zeros);
  coeff = std::move(c);
  return true;
}

Expr with_operands(const Expr& e, std::vector<Expr> operands) { return rebuild(e, std::move(operands)); }

}  // namespace mbgc::ir
