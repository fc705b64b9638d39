// Hand-written models with known solutions, standing in for generated code.
#pragma once

#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "mbgrt/model.hpp"

namespace mbgrt::test {

/// Parameters by name plus the boilerplate every model needs.
class TestModel : public Model {
 public:
  const char* source_file() const override { return "test.mbg"; }
  std::vector<ParameterInfo> parameters() const override {
    std::vector<ParameterInfo> out;
    for (const auto& [name, value] : defaults_) out.push_back({name, value, ""});
    return out;
  }
  bool set_parameter(const std::string& name, double value) override {
    if (!defaults_.count(name)) return false;
    values_[name] = value;
    return true;
  }
  Settings default_settings() const override { return settings; }

  Settings settings;
  int terminal_calls = 0;
  double terminal_t = std::nan("");
  void terminal(double t, const double*) override {
    ++terminal_calls;
    terminal_t = t;
  }

 protected:
  void param(const std::string& name, double value) { defaults_[name] = values_[name] = value; }
  double p(const std::string& name) const { return values_.at(name); }

 private:
  std::map<std::string, double> defaults_, values_;
};

/// x' = -k x, x(0) = x0: x(t) = x0 exp(-k t).
class Decay : public TestModel {
 public:
  Decay() {
    param("k", 0.5);
    param("x0", 2.0);
    settings.t_end_s = 2.0;
    settings.interval_s = 0.1;
  }
  const char* name() const override { return "decay"; }
  std::unique_ptr<Model> make_new() const override { return std::make_unique<Decay>(); }
  std::size_t size() const override { return 1; }
  std::string variable_name(std::size_t) const override { return "x"; }
  std::vector<std::string> output_names() const override { return {"x"}; }
  void initial(double, double* y, double*) override { y[0] = p("x0"); }
  void derivative(double, const double* y, double* dy) override { dy[0] = -p("k") * y[0]; }
  void outputs(double, const double* y, const double*, double* out) override { out[0] = y[0]; }
  double exact(double t) const { return p("x0") * std::exp(-p("k") * t); }
};

/// x'' + 2 zeta omega x' + omega^2 x = 0 with x(0) = x0, x'(0) = 0.
class Oscillator : public TestModel {
 public:
  explicit Oscillator(double omega = 2.0, double zeta = 0.0) {
    param("omega", omega);
    param("zeta", zeta);
    param("x0", 1.0);
    settings.t_end_s = 10.0;
    settings.interval_s = 0.1;
  }
  const char* name() const override { return "oscillator"; }
  std::size_t size() const override { return 2; }
  std::string variable_name(std::size_t i) const override { return i == 0 ? "mass.x" : "mass.v"; }
  std::vector<std::string> output_names() const override { return {"x", "v", "energy"}; }
  void initial(double, double* y, double*) override {
    y[0] = p("x0");
    y[1] = 0.0;
  }
  void derivative(double, const double* y, double* dy) override {
    const double w = p("omega");
    dy[0] = y[1];
    dy[1] = -2 * p("zeta") * w * y[1] - w * w * y[0];
  }
  void outputs(double, const double* y, const double*, double* out) override {
    const double w = p("omega");
    out[0] = y[0];
    out[1] = y[1];
    out[2] = 0.5 * y[1] * y[1] + 0.5 * w * w * y[0] * y[0];
  }
};

/// Two uncoupled damped oscillators (listed fastest first) and a first-order lag.
class ThreeModes : public TestModel {
 public:
  ThreeModes() { settings.t_end_s = 1.0; }
  const char* name() const override { return "three_modes"; }
  std::size_t size() const override { return 5; }
  std::string variable_name(std::size_t i) const override {
    std::string s(1, 's');  // not "s" + std::to_string(i): a false -Wrestrict from GCC 12 at -O3 (PR 105329)
    return s += std::to_string(i);
  }
  std::vector<std::string> output_names() const override { return {"s0"}; }
  void initial(double, double* y, double*) override {
    for (int i = 0; i < 5; ++i) y[i] = 0.1 * (i + 1);
  }
  void derivative(double, const double* y, double* dy) override {
    oscillator(5.0, 0.02, y, dy);
    oscillator(2.0, 0.1, y + 2, dy + 2);
    dy[4] = -7.0 * y[4];
  }
  void outputs(double, const double* y, const double*, double* out) override { out[0] = y[0]; }

 private:
  static void oscillator(double w, double z, const double* y, double* dy) {
    dy[0] = y[1];
    dy[1] = -2 * z * w * y[1] - w * w * y[0];
  }
};

/// x' = -x^3, x(0) = 1: x(t) = 1 / sqrt(1 + 2 t), Jacobian -3 x^2.
class CubicDecay : public TestModel {
 public:
  CubicDecay() { settings.t_end_s = 2.0; }
  const char* name() const override { return "cubic_decay"; }
  std::size_t size() const override { return 1; }
  std::string variable_name(std::size_t) const override { return "x"; }
  std::vector<std::string> output_names() const override { return {"x"}; }
  void initial(double, double* y, double*) override { y[0] = 1.0; }
  void derivative(double, const double* y, double* dy) override { dy[0] = -y[0] * y[0] * y[0]; }
  void outputs(double, const double* y, const double*, double* out) override { out[0] = y[0]; }
};

/// Index-1 DAE: x' = -x + z, 0 = z + 2 x, so x = x0 exp(-3 t), z = -2 x.
/// The initial guess for z (and for y') is deliberately inconsistent.
class SmallDae : public TestModel {
 public:
  SmallDae() {
    param("x0", 1.0);
    settings.t_end_s = 1.0;
    settings.interval_s = 0.05;
    settings.solver = Solver::ida;
    settings.rtol = 1e-9;
    settings.atol = 1e-11;
  }
  const char* name() const override { return "small_dae"; }
  std::size_t size() const override { return 2; }
  std::string variable_name(std::size_t i) const override { return i == 0 ? "mass.x" : "link.z"; }
  std::vector<std::string> output_names() const override { return {"x", "z", "xdot"}; }
  bool is_dae() const override { return true; }
  void differential_ids(double* id) const override {
    id[0] = 1.0;
    id[1] = 0.0;
  }
  void initial(double, double* y, double* yp) override {
    y[0] = p("x0");
    y[1] = 0.0;
    yp[0] = 0.0;
    yp[1] = 0.0;
  }
  void residual(double, const double* y, const double* yp, double* r) override {
    r[0] = yp[0] + y[0] - y[1];
    r[1] = y[1] + 2 * y[0];
  }
  void outputs(double, const double* y, const double* yp, double* out) override {
    out[0] = y[0];
    out[1] = y[1];
    out[2] = yp ? yp[0] : std::nan("");
  }
};

/// level' = sqrt(1 - t): finite up to t = 1, NaN after. level(t) = 2/3 (1 - (1 - t)^1.5).
class DrainingTank : public TestModel {
 public:
  DrainingTank() {
    settings.t_end_s = 2.0;
    settings.interval_s = 0.1;
  }
  const char* name() const override { return "draining_tank"; }
  std::size_t size() const override { return 2; }
  std::string variable_name(std::size_t i) const override {
    return i == 0 ? "clock" : "tank.level";
  }
  std::vector<std::string> output_names() const override { return {"level"}; }
  void initial(double, double* y, double*) override { y[0] = y[1] = 0.0; }
  void derivative(double t, const double*, double* dy) override {
    dy[0] = 1.0;
    dy[1] = std::sqrt(1.0 - t);
  }
  void outputs(double, const double* y, const double*, double* out) override { out[0] = y[1]; }
  static double exact(double t) { return 2.0 / 3.0 * (1.0 - std::pow(1.0 - t, 1.5)); }
};

/// x' = x^2, x(0) = 1: x = 1 / (1 - t) blows up at t = 1.
class BlowUp : public TestModel {
 public:
  BlowUp() {
    settings.t_end_s = 2.0;
    settings.interval_s = 0.1;
  }
  const char* name() const override { return "blow_up"; }
  std::size_t size() const override { return 1; }
  std::string variable_name(std::size_t) const override { return "x"; }
  std::vector<std::string> output_names() const override { return {"x"}; }
  void initial(double, double* y, double*) override { y[0] = 1.0; }
  void derivative(double, const double* y, double* dy) override { dy[0] = y[0] * y[0]; }
  void outputs(double, const double* y, const double*, double* out) override { out[0] = y[0]; }
};

/// x' = -lambda (x - cos t), lambda = 1e6: x follows cos t within ~1e-6 after a
/// fast transient. Stiff: an explicit method needs h < ~3.3e-6 to stay stable.
class Stiff : public TestModel {
 public:
  Stiff() {
    settings.t_end_s = 1.0;
    settings.interval_s = 0.1;
  }
  const char* name() const override { return "stiff"; }
  std::size_t size() const override { return 1; }
  std::string variable_name(std::size_t) const override { return "x"; }
  std::vector<std::string> output_names() const override { return {"x"}; }
  void initial(double, double* y, double*) override { y[0] = 0.0; }
  void derivative(double t, const double* y, double* dy) override {
    dy[0] = -1e6 * (y[0] - std::cos(t));
  }
  void outputs(double, const double* y, const double*, double* out) override { out[0] = y[0]; }
};

/// Throws from derivative() after t = 0.5, which generated code must never do.
class Throwing : public Decay {
 public:
  const char* name() const override { return "throwing"; }
  void derivative(double t, const double* y, double* dy) override {
    if (t > 0.5) throw std::runtime_error("table lookup out of range");
    Decay::derivative(t, y, dy);
  }
};

/// Outputs that are exact functions of t, for checking the CSV text itself.
class Clock : public TestModel {
 public:
  Clock() {
    settings.t_end_s = 1.0;
    settings.interval_s = 0.1;
    settings.solver = Solver::rk4;
  }
  const char* name() const override { return "clock"; }
  std::size_t size() const override { return 1; }
  std::string variable_name(std::size_t) const override { return "c"; }
  std::vector<std::string> output_names() const override { return {"a.b", "third_of_t"}; }
  void initial(double, double* y, double*) override { y[0] = 0.0; }
  void derivative(double, const double*, double* dy) override { dy[0] = 1.0; }
  void outputs(double t, const double* y, const double*, double* out) override {
    out[0] = y[0];
    out[1] = t / 3.0;
  }
};

}  // namespace mbgrt::test
