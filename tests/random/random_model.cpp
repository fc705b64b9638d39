// random_model: writes one random, valid .mbg model to standard output, for
// the random-model test (tests/random/CMakeLists.txt, issue 19): mbgc must
// accept it, its C++ must compile with -Wall -Wextra -Werror, and the
// simulator must run 1 s of simulated time with every value finite.
//
//   random_model bondgraph|multibody SEED
//
// bondgraph: a tree of alternating 0- and 1-junctions, scalar or multibonds
//   of dimension 2 or 3, joined by bonds or through a TF or GY, with C, I and
//   R elements on every junction (nonlinear laws in the scalar case) and one
//   or two sources. Valid by construction: effort sources sit only on
//   1-junctions and flow sources only on 0-junctions, so no source fixes a
//   junction's common variable and no two sources can conflict; multibond and
//   nonlinear graphs are also built explicit (no storage in derivative
//   causality, no R in a loop: BondGraphWriter::junction); every element is
//   passive (positive values, monotone laws), so the energy stays bounded.
// multibody: a tree of 1 to 6 bodies (rigid bodies, particles, at most one
//   beam), each joined to ground or to an earlier body by a joint of a kind
//   that fits both ends (docs/language.md, section 7), under random gravity
//   and constraint strategy, with joint springs, prescribed motions, springs
//   between points and applied loads.
//
// The same seed gives the same model everywhere: std::mt19937_64 is fully
// specified by the standard, and its output is mapped to numbers here (the
// standard distributions are not specified bit for bit). Every number is
// printed with four significant digits, and the checks that make a model
// valid (the triangle inequality of an inertia, ...) keep margins that such
// rounding cannot eat. (A rotated inertia goes through std::sin and std::cos,
// whose last bit may differ between C libraries; four digits hide that but
// for a number that falls on a rounding boundary.)
#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <random>
#include <string>
#include <vector>

namespace {

// ---------------------------------------------------------------------------
// Random numbers and text
// ---------------------------------------------------------------------------

class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}

  // uniform in [lo, hi), from the top 53 bits of one draw
  double uniform(double lo, double hi) {
    const double unit = static_cast<double>(engine_() >> 11) * 0x1.0p-53;
    return lo + (hi - lo) * unit;
  }
  // uniform in [lo, hi] (the modulo's bias is below 1e-17 for these ranges)
  int integer(int lo, int hi) { return lo + static_cast<int>(engine_() % static_cast<std::uint64_t>(hi - lo + 1)); }
  bool chance(double p) { return uniform(0, 1) < p; }
  double sign() { return chance(0.5) ? 1.0 : -1.0; }
  template <class T>
  const T& pick(const std::vector<T>& items) {
    return items[static_cast<std::size_t>(integer(0, static_cast<int>(items.size()) - 1))];
  }

 private:
  std::mt19937_64 engine_;
};

using Vec3 = std::array<double, 3>;
using Mat3 = std::array<Vec3, 3>;

std::string num(double x) {
  if (std::abs(x) < 1e-9) return "0";  // rounding noise of a rotated inertia
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", x);
  return text;
}

std::string vec(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + num(v[i]);
  return s + "]";
}
std::string vec(const Vec3& v) { return vec(std::vector<double>(v.begin(), v.end())); }

std::string matrix(const std::vector<std::vector<double>>& m) {
  std::string s = "[";
  for (std::size_t i = 0; i < m.size(); ++i) s += (i ? ", " : "") + vec(m[i]);
  return s + "]";
}

std::string join(const std::vector<std::string>& items) {
  std::string s;
  for (std::size_t i = 0; i < items.size(); ++i) s += (i ? ", " : "") + items[i];
  return s;
}

// settings block: " { a = 1; b = 2 }", or nothing
std::string settings(const std::vector<std::string>& items) {
  if (items.empty()) return "";
  std::string s = " { ";
  for (std::size_t i = 0; i < items.size(); ++i) s += (i ? "; " : "") + items[i];
  return s + " }";
}

Vec3 unit_vector(Random& rng) {
  // one of the coordinate axes now and then, else a random direction
  if (rng.chance(0.25)) {
    Vec3 v{0, 0, 0};
    v[static_cast<std::size_t>(rng.integer(0, 2))] = rng.sign();
    return v;
  }
  for (;;) {
    const Vec3 v{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
    const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (n > 0.3 && n <= 1) return {v[0] / n, v[1] / n, v[2] / n};
  }
}

Vec3 random_point(Random& rng, double size) {
  return {rng.uniform(-size, size), rng.uniform(-size, size), rng.uniform(-size, size)};
}

// ---------------------------------------------------------------------------
// Bond graphs
// ---------------------------------------------------------------------------

class BondGraphWriter {
 public:
  BondGraphWriter(Random& rng, std::uint64_t seed) : rng_(rng), seed_(seed) {}

  std::string write() {
    dim_ = rng_.chance(0.7) ? 1 : rng_.integer(2, 3);
    nonlinear_ = dim_ == 1 && rng_.chance(0.4);
    explicit_ = dim_ > 1 || nonlinear_;
    budget_ = rng_.integer(3, 12);
    junction(rng_.chance(0.5) ? '0' : '1', 0);
    Junction& root = junctions_.front();
    if (sources_ == 0) root.in.insert(root.in.begin(), source(root.type));  // every model is driven

    std::string s = "// random bond graph, seed " + std::to_string(seed_) + " (tests/random/random_model.cpp)\n";
    s += "model random_bondgraph_" + std::to_string(seed_) + "\n";
    for (const auto& line : params_) s += line + "\n";
    for (const auto& line : elements_) s += line + "\n";
    for (const auto& j : junctions_) {
      s += std::string(1, j.type) + " " + j.name;
      if (j.sized) s += " [" + std::to_string(dim_) + "]";
      s += " :" + (j.in.empty() ? "" : " " + join(j.in)) + " ->" + (j.out.empty() ? "" : " " + join(j.out)) + "\n";
    }
    if (outputs_.empty()) outputs_.push_back("output " + root.name + "_var = " + root.name + (root.type == '0' ? ".e" : ".f"));
    for (const auto& line : outputs_) s += line + "\n";
    if (rng_.chance(0.3)) s += "simulate { t_end = 1; interval = " + rng_.pick<std::string>({"0.01", "0.02", "0.05"}) + " }\n";
    return s;
  }

 private:
  struct Junction {
    char type;  // '0' or '1'
    std::string name;
    std::vector<std::string> in, out;  // bonds into and out of it
    bool sized = false;                // written with its dimension [n]
  };

  // A junction of type '0' or '1' with its own elements and, below depth 3,
  // child junctions; returns its index in junctions_. The bond to the parent
  // is listed by the parent (through a two-port, by both).
  //
  // Scalar linear graphs join anything: mbgc solves their algebraic loops and
  // derivative causality. Multibonds and nonlinear laws would need a matrix
  // or a law inverted there, which mbgc does not do (docs/limits.md, "Bond
  // graphs"), so those graphs are explicit by construction: each 1-junction has one I
  // that sets its flow, each 0-junction one C that sets its effort; any other
  // element takes its input from the junction (C and R on a 1-junction get
  // the flow, I and R on a 0-junction the effort) and the junctions are joined
  // so that neither side imposes what the other already has (below).
  std::size_t junction(char type, int depth) {
    const std::size_t index = junctions_.size();
    junctions_.push_back({type, (type == '0' ? "n" : "s") + std::to_string(index + 1), {}, {}, dim_ > 1 && rng_.chance(0.5)});
    std::vector<std::string> own;
    if (explicit_) {
      own.push_back(storage(type == '0'));
      if (budget_ > 0 && rng_.chance(0.6)) own.push_back(rng_.chance(0.6) ? resistor(type) : storage(type == '1'));
    } else {
      const int count = rng_.integer(1, 2);
      for (int i = 0; i < count && (i == 0 || budget_ > 0); ++i)  // past the budget, one element each
        own.push_back(rng_.chance(0.6) ? storage(rng_.chance(0.5)) : resistor(type));
    }
    // a passive element's bond may point either way: its signs follow its own power convention
    for (const auto& e : own) (rng_.chance(0.85) ? junctions_[index].out : junctions_[index].in).push_back(e);
    if (sources_ < 2 && rng_.chance(depth == 0 ? 0.5 : 0.25)) junctions_[index].in.push_back(source(type));

    const int children = depth >= 3 ? 0 : rng_.integer(depth == 0 ? 1 : 0, 2);
    for (int i = 0; i < children && budget_ > 0; ++i) child(index, depth);
    if (rng_.chance(0.2)) {
      const Junction& j = junctions_[index];
      outputs_.push_back("output " + j.name + "_var = " + j.name + (type == '0' ? ".e" : ".f"));
    }
    return index;
  }

  // A child junction, bonded straight to its parent (of the other type) or
  // through a TF or GY. In a scalar linear graph the two-port joins either
  // type and points either way. In an explicit graph a TF joins a 1-junction
  // (port 1: the flow in) to a 0-junction (port 2: the flow out), and a GY two
  // 1-junctions (each port's flow in, the other's effort out).
  void child(std::size_t parent, int depth) {
    const char type = junctions_[parent].type, other = type == '0' ? '1' : '0';
    const double kind = rng_.uniform(0, 1);
    if (kind < 0.6) {
      const std::size_t c = junction(other, depth + 1);
      (rng_.chance(0.8) ? junctions_[parent].out : junctions_[parent].in).push_back(junctions_[c].name);
      return;
    }
    const bool gyrator = kind >= 0.85 && !(explicit_ && type == '0');
    const std::string tp = two_port(gyrator ? "GY" : "TF");
    char child_type = rng_.chance(0.5) ? '0' : '1';
    bool downward = rng_.chance(0.8);  // parent -> tp -> child, else child -> tp -> parent (port 1 where power comes from)
    if (explicit_ && gyrator) child_type = '1';
    if (explicit_ && !gyrator) child_type = other, downward = type == '1';
    const std::size_t c = junction(child_type, depth + 1);
    (downward ? junctions_[parent].out : junctions_[parent].in).push_back(tp);
    if (downward) junctions_[c].in.insert(junctions_[c].in.begin(), tp);
    else junctions_[c].out.push_back(tp);
  }

  // a positive scalar, sometimes through a parameter
  std::string positive(const std::string& element, double lo, double hi) {
    const std::string v = num(rng_.uniform(lo, hi));
    if (!rng_.chance(0.3)) return v;
    params_.push_back("param " + element + "_value = " + v);
    return element + "_value";
  }

  // a value of the model's dimension: a scalar, or a symmetric positive
  // definite matrix (diagonally dominant)
  std::string spd(const std::string& element, double lo, double hi) {
    if (dim_ == 1) return positive(element, lo, hi);
    std::vector<double> d;
    for (int i = 0; i < dim_; ++i) d.push_back(rng_.uniform(lo, hi));
    if (rng_.chance(0.5)) {
      std::string s = "diag(";
      for (int i = 0; i < dim_; ++i) s += (i ? ", " : "") + num(d[static_cast<std::size_t>(i)]);
      return s + ")";
    }
    std::vector<std::vector<double>> m(static_cast<std::size_t>(dim_), std::vector<double>(static_cast<std::size_t>(dim_), 0));
    for (std::size_t i = 0; i < m.size(); ++i) m[i][i] = d[i];
    for (std::size_t i = 0; i < m.size(); ++i)
      for (std::size_t j = i + 1; j < m.size(); ++j)
        m[i][j] = m[j][i] = rng_.uniform(-0.3, 0.3) * std::min(d[i], d[j]) / static_cast<double>(dim_ - 1);
    return matrix(m);
  }

  std::vector<double> initial(double size) {
    std::vector<double> v;
    for (int i = 0; i < dim_; ++i) v.push_back(rng_.uniform(-size, size));
    return v;
  }
  std::string initial_text(double size) {
    const auto v = initial(size);
    return dim_ == 1 ? num(v[0]) : vec(v);
  }

  // a C (capacitor) or an I, with a linear value or, in a nonlinear graph
  // now and then, a law; sometimes an initial state; its state an output
  std::string storage(bool capacitor) {
    --budget_;
    const std::string name = (capacitor ? "c" : "m") + std::to_string(++element_count_);
    std::vector<std::string> set;
    std::string line;
    if (capacitor) {
      if (nonlinear_ && rng_.chance(0.4)) {
        set.push_back("e = " + num(rng_.uniform(0.2, 5)) + " * q + " + num(rng_.uniform(0.1, 2)) + " * q^3");
        line = "C " + name;
      } else {
        line = "C " + name + " = " + spd(name, 0.2, 5);
      }
      if (rng_.chance(0.6)) set.push_back("q0 = " + initial_text(1));
      outputs_.push_back("output " + name + "_q = " + name + ".q");
    } else {
      if (nonlinear_ && rng_.chance(0.3)) {
        set.push_back("f = p / " + num(rng_.uniform(0.2, 5)));
        line = "I " + name;
      } else {
        line = "I " + name + " = " + spd(name, 0.2, 5);
        if (rng_.chance(0.2)) set.push_back("f0 = " + initial_text(1));
      }
      if (set.empty() && rng_.chance(0.5)) set.push_back("p0 = " + initial_text(1));
      outputs_.push_back("output " + name + "_p = " + name + ".p");
    }
    elements_.push_back(line + settings(set));
    return name;
  }

  // a resistor on a junction of this type
  std::string resistor(char junction_type) {
    --budget_;
    const std::string name = "r" + std::to_string(++element_count_);
    if (nonlinear_ && rng_.chance(0.4)) {
      // e = r f + c f^3 or e = r f + c f |f| (f = ... of e on a 0-junction,
      // whose effort it gets): monotone, so passive
      const std::string in = junction_type == '1' ? "f" : "e", out = junction_type == '1' ? "e" : "f";
      const std::string cubic = rng_.chance(0.5) ? " * " + in + "^3" : " * " + in + " * abs(" + in + ")";
      elements_.push_back("R " + name + settings({out + " = " + num(rng_.uniform(0.2, 5)) + " * " + in + " + " +
                                                  num(rng_.uniform(0.1, 2)) + cubic}));
    } else {
      elements_.push_back("R " + name + " = " + spd(name, 0.2, 5));
    }
    if (rng_.chance(0.3)) outputs_.push_back("output " + name + "_f = " + name + ".f");
    return name;
  }

  // a source of the kind that cannot conflict on this junction: Se on a
  // 1-junction, Sf on a 0-junction
  std::string source(char junction_type) {
    ++sources_;
    const bool effort = junction_type == '1';
    const std::string name = (effort ? "se" : "sf") + std::to_string(++element_count_);
    std::vector<std::string> parts;
    for (int i = 0; i < dim_; ++i) parts.push_back(time_function());
    const std::string value = dim_ == 1 ? parts[0] : "[" + join(parts) + "]";
    elements_.push_back(std::string(effort ? "Se " : "Sf ") + name + " = " + value);
    if (rng_.chance(0.5)) outputs_.push_back("output " + name + "_power = " + power(name));
    return name;
  }
  std::string power(const std::string& element) const {
    if (dim_ == 1) return element + ".e * " + element + ".f";
    return "dot(" + element + ".e, " + element + ".f)";
  }

  std::string time_function() {
    const double a = rng_.sign() * rng_.uniform(0.2, 5);
    switch (rng_.integer(0, 5)) {
      case 0: return num(a);
      case 1: return "sine(" + num(a) + ", " + num(rng_.uniform(0.2, 3)) + ")";
      case 2: return "sine(" + num(a) + ", " + num(rng_.uniform(0.2, 3)) + ", " + num(rng_.uniform(0, 3)) + ")";
      case 3: return num(a) + " * (1 - exp(-t / " + num(rng_.uniform(0.1, 1)) + "))";
      case 4: return num(a) + " * cos(" + num(rng_.uniform(0.5, 10)) + " * t)";
      default: return "step(" + num(rng_.uniform(0.1, 0.8)) + ", " + num(a) + ")";
    }
  }

  // TF or GY of the model's dimension: a scalar modulus, or a diagonally
  // dominant (so invertible) matrix
  std::string two_port(const std::string& kind) {
    const std::string name = (kind == "TF" ? "tf" : "gy") + std::to_string(++element_count_);
    std::string value;
    if (dim_ == 1) {
      value = num(rng_.sign() * rng_.uniform(0.5, 2));
    } else {
      std::vector<std::vector<double>> m(static_cast<std::size_t>(dim_), std::vector<double>(static_cast<std::size_t>(dim_), 0));
      for (std::size_t i = 0; i < m.size(); ++i)
        for (std::size_t j = 0; j < m.size(); ++j)
          m[i][j] = i == j ? rng_.sign() * rng_.uniform(0.5, 2) : rng_.uniform(-0.2, 0.2);
      value = matrix(m);
    }
    elements_.push_back(kind + " " + name + " = " + value);
    if (rng_.chance(0.3)) outputs_.push_back("output " + name + "_f2 = " + name + ".f2");
    return name;
  }

  Random& rng_;
  std::uint64_t seed_;
  int dim_ = 1;
  bool nonlinear_ = false;  // scalar laws for some C, I and R
  bool explicit_ = false;   // built so that no storage is in derivative causality and no R in a loop
  int budget_ = 0;  // elements still to place (every junction takes one regardless)
  int sources_ = 0;
  int element_count_ = 0;
  std::vector<Junction> junctions_;
  std::vector<std::string> params_, elements_, outputs_;
};

// ---------------------------------------------------------------------------
// Multibody models
// ---------------------------------------------------------------------------

enum class BodyKind { rigid, particle, beam };

struct Body {
  std::string name;
  BodyKind kind = BodyKind::rigid;
  std::vector<std::string> lines;                    // its settings
  std::vector<std::pair<std::string, Vec3>> points;  // name, body-frame position
  double length = 0;                                 // a beam's
};

class MultibodyWriter {
 public:
  MultibodyWriter(Random& rng, std::uint64_t seed) : rng_(rng), seed_(seed) {}

  std::string write() {
    strategy_ = rng_.pick<std::string>({"lagrange", "coordinates", "penalty", "auto", "lagrange", "coordinates"});
    const int n = rng_.integer(1, 6);
    for (int i = 1; i <= n; ++i) {
      bodies_.push_back(body(i));
      joint(i - 1);
    }
    const int forces = rng_.integer(0, 2);
    for (int i = 1; i <= forces; ++i) force(i);
    body_outputs();

    std::string s = "// random multibody model, seed " + std::to_string(seed_) + " (tests/random/random_model.cpp)\n";
    s += "model random_multibody_" + std::to_string(seed_) + "\n";
    if (rng_.chance(0.85)) s += "gravity = " + gravity() + "\n";
    if (strategy_ != "auto" || rng_.chance(0.5)) s += "constraints = " + strategy_ + "\n";
    if (!ground_points_.empty()) {
      s += "ground {";
      for (const auto& [name, p] : ground_points_) s += " point " + name + " = " + vec(p) + ";";
      s.pop_back();
      s += " }\n";
    }
    for (const auto& b : bodies_) {
      s += "body " + b.name + " {";
      for (const auto& line : b.lines) s += "\n  " + line;
      for (const auto& [name, p] : b.points) s += "\n  point " + name + " = " + vec(p);
      s += "\n}\n";
    }
    for (const auto& line : joints_) s += line + "\n";
    for (const auto& line : forces_) s += line + "\n";
    for (const auto& line : outputs_) s += line + "\n";
    return s;
  }

 private:
  std::string gravity() {
    const Vec3 g = unit_vector(rng_);
    const double size = rng_.uniform(1, 10);
    return vec(Vec3{g[0] * size, g[1] * size, g[2] * size});
  }

  // Body i: a particle now and then, at most one beam, else a rigid body.
  Body body(int i) {
    Body b;
    const double kind = rng_.uniform(0, 1);
    if (kind < 0.15) b.kind = BodyKind::particle;
    else if (kind < 0.25 && !has_beam_) b.kind = BodyKind::beam, has_beam_ = true;
    b.name = (b.kind == BodyKind::particle ? "bob" : b.kind == BodyKind::beam ? "beam" : "link") + std::to_string(i);
    if (b.kind == BodyKind::rigid) rigid_settings(b);
    else if (b.kind == BodyKind::particle) b.lines.push_back("mass = " + num(rng_.uniform(0.2, 5)));
    else beam_settings(b);
    return b;
  }

  void rigid_settings(Body& b) {
    const double mass = rng_.uniform(0.2, 5);
    b.lines.push_back("mass = " + num(mass));
    b.lines.push_back("inertia = " + inertia(mass));
    if (rng_.chance(0.5)) b.lines.push_back("com = " + vec(random_point(rng_, 0.2)));
    b.points.push_back({"a", random_point(rng_, 0.3)});  // where its parent's joint holds it
  }

  // principal moments a, b, c with each below the sum of the other two (by a
  // margin), sometimes in axes turned by a random rotation
  std::string inertia(double mass) {
    const double scale = mass * rng_.uniform(0.005, 0.05);
    const double a = scale * rng_.uniform(0.5, 2), b = scale * rng_.uniform(0.5, 2);
    const double c = std::abs(a - b) + rng_.uniform(0.2, 0.8) * (a + b - std::abs(a - b));
    if (rng_.chance(0.5)) return "diag(" + num(a) + ", " + num(b) + ", " + num(c) + ")";
    const Mat3 r = rotation(unit_vector(rng_), rng_.uniform(0, 3.14));
    const Vec3 d{a, b, c};
    // R diag(a, b, c) R^T, its lower triangle a copy of the upper one (so
    // that the printed matrix is symmetric to the last digit)
    std::vector<std::vector<double>> m(3, std::vector<double>(3, 0));
    for (std::size_t i = 0; i < 3; ++i)
      for (std::size_t j = i; j < 3; ++j) {
        for (std::size_t k = 0; k < 3; ++k) m[i][j] += r[i][k] * d[k] * r[j][k];
        m[j][i] = m[i][j];
      }
    return matrix(m);
  }

  static Mat3 rotation(const Vec3& u, double angle) {
    const double c = std::cos(angle), s = std::sin(angle), t = 1 - c;
    return {{{t * u[0] * u[0] + c, t * u[0] * u[1] - s * u[2], t * u[0] * u[2] + s * u[1]},
             {t * u[0] * u[1] + s * u[2], t * u[1] * u[1] + c, t * u[1] * u[2] - s * u[0]},
             {t * u[0] * u[2] - s * u[1], t * u[1] * u[2] + s * u[0], t * u[2] * u[2] + c}}};
  }

  // an aluminium strip with cantilever modes, held at its root
  void beam_settings(Body& b) {
    b.length = rng_.uniform(0.4, 1);
    b.lines.push_back("flexible = beam");
    b.lines.push_back("length = " + num(b.length) + "; density = 2700; E = 7e10");
    b.lines.push_back("section = rectangle(" + num(rng_.uniform(0.02, 0.04)) + ", " + num(rng_.uniform(0.01, 0.02)) + ")");
    b.lines.push_back("modes_xy = clamped_free(" + std::to_string(rng_.integer(1, 2)) + ")");
    if (rng_.chance(0.5)) b.lines.push_back("modes_xz = clamped_free(1)");
    b.lines.push_back("damping = " + num(rng_.uniform(0.01, 0.05)));
    b.points.push_back({"root", {0, 0, 0}});
    b.points.push_back({"tip", {b.length, 0, 0}});
  }

  // The joint kinds that may join parent and child (docs/language.md 7.4):
  // only spherical, distance and free take a particle, and in joint
  // coordinates only distance joins one (mbgc also refuses a spherical joint
  // whose parent is a particle there); a free joint has coordinates but no
  // rows, so with multipliers a floating body takes no joint at all.
  std::vector<std::string> joint_kinds(const Body* parent, const Body& child) const {
    const bool coordinates = strategy_ == "coordinates";
    const bool particle = child.kind == BodyKind::particle || (parent && parent->kind == BodyKind::particle);
    if (particle && coordinates) return {"distance"};
    if (particle) return {"distance", "spherical"};
    std::vector<std::string> kinds{"revolute", "revolute", "prismatic", "cylindrical", "screw",
                                   "spherical", "universal", "planar", "fixed", "distance"};
    if (coordinates) kinds.push_back("free");
    return kinds;
  }

  // the endpoint of a joint or force on body b (nullptr: ground): a new point
  // named `name` at a random place, a beam's tip, or a particle itself
  std::string endpoint(Body* b, const std::string& name) {
    if (!b) {
      ground_points_.push_back({name, random_point(rng_, 0.5)});
      return "ground." + name;
    }
    if (b->kind == BodyKind::particle) return b->name;
    if (b->kind == BodyKind::beam) return b->name + (rng_.chance(0.7) ? ".tip" : ".root");
    b->points.push_back({name, random_point(rng_, 0.4)});
    return b->name + "." + name;
  }

  // The joint that places body `index`: to ground or to an earlier body.
  void joint(int index) {
    Body& child = bodies_[static_cast<std::size_t>(index)];
    Body* parent = index == 0 || rng_.chance(0.3) ? nullptr : &bodies_[static_cast<std::size_t>(rng_.integer(0, index - 1))];
    const std::string kind = rng_.pick(joint_kinds(parent, child));
    const std::string name = "j" + std::to_string(index + 1);
    const std::string a = endpoint(parent, "c" + std::to_string(index + 1));
    const std::string b = child.kind == BodyKind::particle ? child.name
                          : child.kind == BodyKind::beam   ? child.name + ".root"
                                                           : child.name + ".a";
    joints_.push_back("joint " + name + " " + kind + "(" + a + ", " + b + ")" + settings(joint_settings(name, kind)));
  }

  std::vector<std::string> joint_settings(const std::string& j, const std::string& kind) {
    std::vector<std::string> s;
    const bool turns = kind == "revolute" || kind == "cylindrical" || kind == "screw";
    const bool slides = kind == "prismatic";
    // a spring and damper in the joint, or a prescribed motion (which takes
    // no initial coordinate or rate)
    const double driver = rng_.uniform(0, 1);
    const bool spring = (turns || slides) && driver < 0.3;
    const bool motion = (turns || slides) && driver >= 0.3 && driver < 0.4;

    if (kind != "free" && kind != "spherical" && kind != "distance") {  // a rod's axis is its direction (below)
      if (kind == "universal" || rng_.chance(0.3)) {
        s.push_back("axis_a = " + vec(unit_vector(rng_)));
        s.push_back("axis_b = " + vec(unit_vector(rng_)));
      } else if (rng_.chance(0.8)) {
        s.push_back("axis = " + vec(unit_vector(rng_)));
      }
    }
    const double size = slides ? 0.2 : 1;  // m or rad
    if ((turns || slides) && !motion) {
      if (rng_.chance(0.7)) s.push_back("q0 = " + num(rng_.uniform(-size, size)));
      if (rng_.chance(0.7)) s.push_back("rate0 = " + num(rng_.uniform(-2 * size, 2 * size)));
    }
    if (kind == "cylindrical") {
      if (rng_.chance(0.5)) s.push_back("d0 = " + num(rng_.uniform(-0.2, 0.2)));
      if (rng_.chance(0.5)) s.push_back("ddot0 = " + num(rng_.uniform(-0.4, 0.4)));
    }
    if (kind == "screw") s.push_back("pitch = " + num(rng_.sign() * rng_.uniform(0.01, 0.1)));
    if (kind == "distance") {
      s.push_back("length = " + num(rng_.uniform(0.3, 1)));
      s.push_back("axis = " + vec(unit_vector(rng_)));
    }
    if (kind == "spherical" && rng_.chance(0.7))
      s.push_back("rot0 = quat_axis_angle(" + vec(unit_vector(rng_)) + ", " + num(rng_.uniform(-1, 1)) + ")");
    if (kind == "free") {
      s.push_back("r0 = " + vec(random_point(rng_, 0.5)));
      if (rng_.chance(0.7)) s.push_back("v0 = " + vec(random_point(rng_, 1)));
      if (rng_.chance(0.7)) s.push_back("rot0 = quat_axis_angle(" + vec(unit_vector(rng_)) + ", " + num(rng_.uniform(-1, 1)) + ")");
      if (rng_.chance(0.7)) s.push_back("w0 = " + vec(random_point(rng_, 2)));
    }
    const std::string k = num(rng_.uniform(0.5, 20)), c = num(rng_.uniform(0.05, 2));
    if (spring && turns) {
      s.push_back("torque = -" + k + " * " + j + ".angle - " + c + " * " + j + ".rate");
    } else if (spring) {
      std::string f = "force = -" + k + " * " + j + ".displacement";
      if (strategy_ == "coordinates") f += " - " + c + " * " + j + ".displacement_rate";  // joint coordinates only
      s.push_back(f);
    } else if (motion) {
      s.push_back("motion = " + num(rng_.uniform(0.2, 1) * size) + " * sin(" + num(rng_.uniform(1, 6)) + " * t)");
    }

    // what to read from it
    if (turns) outputs_.push_back("output " + j + "_angle = " + j + ".angle");
    if (slides || kind == "cylindrical" || kind == "distance")
      outputs_.push_back("output " + j + "_d = " + j + ".displacement");
    if (kind != "free" && rng_.chance(0.2)) outputs_.push_back("output " + j + "_force = " + j + ".force");
    return s;
  }

  // a spring-damper from a ground anchor or between two bodies, or an applied
  // load on a body
  void force(int i) {
    const std::string name = "f" + std::to_string(i);
    Body* b = &bodies_[static_cast<std::size_t>(rng_.integer(0, static_cast<int>(bodies_.size()) - 1))];
    const std::string point = endpoint(b, "s" + std::to_string(i));
    if (rng_.chance(0.6)) {
      Body* a = nullptr;
      if (bodies_.size() > 1 && rng_.chance(0.4)) {
        a = &bodies_[static_cast<std::size_t>(rng_.integer(0, static_cast<int>(bodies_.size()) - 1))];
        if (a == b) a = nullptr;
      }
      std::string anchor;
      if (a) {
        anchor = endpoint(a, "t" + std::to_string(i));
      } else {
        // well away from where the bodies start, so that the line of the
        // spring never shrinks to nothing
        const Vec3 u = unit_vector(rng_);
        const double r = rng_.uniform(1.5, 2.5);
        ground_points_.push_back({"anchor" + std::to_string(i), {r * u[0], r * u[1], r * u[2]}});
        anchor = "ground.anchor" + std::to_string(i);
      }
      forces_.push_back("force " + name + "(" + anchor + ", " + point + ")" +
                        settings({"stiffness = " + num(rng_.uniform(1, 50)), "length = " + num(rng_.uniform(0.5, 2)),
                                  "damping = " + num(rng_.uniform(0.1, 2))}));
      outputs_.push_back("output " + name + "_length = " + name + ".length");
      return;
    }
    std::vector<std::string> s{"force = " + load()};
    if (b->kind != BodyKind::particle && rng_.chance(0.5)) s.push_back("torque = " + load());
    forces_.push_back("force " + name + "(ground, " + point + ")" + settings(s));
  }

  std::string load() {
    std::vector<std::string> parts;
    for (int i = 0; i < 3; ++i) {
      const std::string a = num(rng_.sign() * rng_.uniform(0.1, 2));
      parts.push_back(rng_.chance(0.5) ? a : a + " * sin(" + num(rng_.uniform(1, 10)) + " * t)");
    }
    return "[" + join(parts) + "]";
  }

  void body_outputs() {
    for (const auto& b : bodies_) {
      if (rng_.chance(0.5)) outputs_.push_back("output " + b.name + "_r = " + b.name + ".position");
      else outputs_.push_back("output " + b.name + "_x = " + b.name + ".position[" + std::to_string(rng_.integer(1, 3)) + "]");
      if (b.kind == BodyKind::beam) outputs_.push_back("output " + b.name + "_bend = " + b.name + ".tip.deflection[2]");
    }
    std::string energy;
    for (const auto& b : bodies_) energy += (energy.empty() ? "" : " + ") + b.name + ".kinetic_energy";
    outputs_.push_back("output kinetic = " + energy);
  }

  Random& rng_;
  std::uint64_t seed_;
  std::string strategy_;
  bool has_beam_ = false;
  std::vector<Body> bodies_;
  std::vector<std::pair<std::string, Vec3>> ground_points_;
  std::vector<std::string> joints_, forces_, outputs_;
};

[[noreturn]] void usage(const std::string& message) {
  std::cerr << "random_model: " << message << "\nusage: random_model bondgraph|multibody SEED\n";
  std::exit(2);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) usage("expected 2 arguments, got " + std::to_string(argc - 1));
  const std::string kind = argv[1];
  char* end = nullptr;
  errno = 0;
  const unsigned long long seed = std::strtoull(argv[2], &end, 10);
  if (end == argv[2] || *end != '\0' || errno == ERANGE || argv[2][0] == '-')
    usage(std::string("SEED must be a non-negative integer, got `") + argv[2] + "`");
  Random rng(seed);
  if (kind == "bondgraph") std::cout << BondGraphWriter(rng, seed).write();
  else if (kind == "multibody") std::cout << MultibodyWriter(rng, seed).write();
  else usage("KIND must be bondgraph or multibody, got `" + kind + "`");
  return 0;
}
