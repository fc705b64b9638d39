// The fixed-step methods (solvers/fixed_step.hpp) against closed forms: each
// one's order of convergence measured by halving the step, its events
// located to that order, its energy witness converging at that order, and
// what each is for (the symplectic Euler's bounded energy, the implicit
// ones' stability on a stiff model). The expected ratios are 2^order from the
// registry (mbgrt/integrators.hpp); the bands around them are those of an
// asymptotic ratio at these steps, not fitted to the runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "harness.hpp"
#include "models.hpp"

namespace mbgrt::test {
namespace {

/// The fixed-step integrators of the registry.
std::vector<IntegratorInfo> fixed_step_methods() {
  std::vector<IntegratorInfo> out;
  for (const IntegratorInfo& i : kIntegrators)
    if (!i.adaptive) out.push_back(i);
  return out;
}

std::vector<std::string> args_for(const IntegratorInfo& i, double step, std::vector<std::string> extra = {}) {
  std::vector<std::string> args{"--solver", i.name, "--step", std::to_string(step)};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

/// The oscillator with its layout (x a position, v a velocity) and its
/// energy balance: stored 1/2 v^2 + 1/2 omega^2 x^2, absorbed by the damper
/// 2 zeta omega v^2, nothing supplied.
class MechanicalOscillator : public Oscillator {
 public:
  using Oscillator::Oscillator;
  UnknownRole unknown_role(std::size_t i) const override { return i == 0 ? UnknownRole::position : UnknownRole::velocity; }
  bool has_energy_balance() const override { return true; }
  void stored_energy(double, const double* y, const double*, double* out) override {
    const double w = p("omega");
    out[0] = 0.5 * y[1] * y[1] + 0.5 * w * w * y[0] * y[0];
  }
  void power(double, const double* y, const double*, double* out) override {
    out[0] = 0.0;
    out[1] = 2 * p("zeta") * p("omega") * y[1] * y[1];
  }
};

/// x' = cos t - k (x - sin t), x(0) = 0: x = sin t for every k. Time-varying,
/// and stiff for a large k.
class Forced : public TestModel {
 public:
  explicit Forced(double k) {
    param("k", k);
    settings.t_end_s = 2.0;
    settings.interval_s = 0.1;
  }
  const char* name() const override { return "forced"; }
  std::size_t size() const override { return 1; }
  std::string variable_name(std::size_t) const override { return "x"; }
  std::vector<std::string> output_names() const override { return {"x"}; }
  void initial(double, double* y, double*) override { y[0] = 0.0; }
  void derivative(double t, const double* y, double* dy) override {
    dy[0] = std::cos(t) - p("k") * (y[0] - std::sin(t));
  }
  void outputs(double, const double* y, const double*, double* out) override { out[0] = y[0]; }
};

/// x' = -x from 1 with an event where x falls through 1/2: at t = ln 2.
class HalfLife : public Decay {
 public:
  HalfLife() {
    param("k", 1.0);
    param("x0", 1.0);
  }
  std::size_t event_count() const override { return 1; }
  void event_functions(double, const double* y, const double*, double* g) override { g[0] = y[0] - 0.5; }
  std::string event_name(std::size_t) const override { return "half"; }
  bool set_event_mode(std::size_t, bool on) override {
    const bool changed = on != on_;
    on_ = on;
    return changed;
  }

 private:
  bool on_ = true;
};

/// The largest |x - exact(t)| over the rows.
template <class Exact>
double max_error(const RunResult& r, Exact exact) {
  const Csv csv = parse_csv(r.csv);
  double worst = 0;
  for (const auto& row : csv.rows) worst = std::max(worst, std::abs(row[1] - exact(row[0])));
  return worst;
}

/// The run summary's "energy residual X J at most".
double energy_residual(const std::string& err) {
  const std::string label = "energy       residual ";
  const auto at = err.find(label);
  return at == std::string::npos ? std::nan("") : std::stod(err.substr(at + label.size()));
}

/// Halving the step divides an error of order p by 2^p: within a band of a
/// factor 1.25 either way (the next term of the error's expansion at these
/// steps), or, where the quantity may converge an order faster than the
/// state (`or_faster`), from 2^p / 1.25 to 2^(p + 1) x 1.25.
void expect_order(const IntegratorInfo& i, double coarse, double fine, const char* what, bool or_faster = false) {
  ASSERT_GT(fine, 1e-13) << i.name << ": the errors must stay above rounding for the ratio to mean anything";
  const double expected = std::pow(2.0, i.order), ratio = coarse / fine;
  EXPECT_GT(ratio, expected / 1.25) << i.name << " " << what << ": " << coarse << " -> " << fine;
  EXPECT_LT(ratio, expected * (or_faster ? 2.5 : 1.25)) << i.name << " " << what << ": " << coarse << " -> " << fine;
}

TEST(FixedStep, EachMethodConvergesAtItsOrderOnAnOscillator) {
  for (const IntegratorInfo& i : fixed_step_methods()) {
    auto error = [&](double h) {
      MechanicalOscillator m;
      RunResult r = run(m, args_for(i, h, {"--t-end", "2"}));
      EXPECT_EQ(r.status, 0) << i.name << ": " << r.err;
      return max_error(r, [](double t) { return std::cos(2 * t); });
    };
    expect_order(i, error(0.02), error(0.01), "x(t) = cos 2t");
  }
}

TEST(FixedStep, EachMethodConvergesAtItsOrderOnATimeVaryingModel) {
  // (the symplectic Euler needs positions and velocities, which this model has not)
  for (const IntegratorInfo& i : fixed_step_methods()) {
    if (i.needs_layout) continue;
    auto error = [&](double h) {
      Forced m(1.0);
      RunResult r = run(m, args_for(i, h));
      EXPECT_EQ(r.status, 0) << i.name << ": " << r.err;
      return max_error(r, [](double t) { return std::sin(t); });
    };
    expect_order(i, error(0.05), error(0.025), "x(t) = sin t");
  }
}

TEST(FixedStep, EachMethodLocatesAnEventToItsOrder) {
  for (const IntegratorInfo& i : fixed_step_methods()) {
    if (i.needs_layout) continue;
    auto event_error = [&](double h) {
      HalfLife m;
      const std::string log = temp_path("half_life.csv");
      RunResult r = run(m, args_for(i, h, {"--event-log", log}));
      EXPECT_EQ(r.status, 0) << i.name << ": " << r.err;
      // the log's one row after its header: t,event,name,...
      const std::string text = read_file(log);
      const auto row = text.find('\n');
      EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 2) << i.name << ": one switch\n" << text;
      return row == std::string::npos ? 1.0 : std::abs(std::stod(text.substr(row + 1)) - std::numbers::ln2);
    };
    expect_order(i, event_error(0.1), event_error(0.05), "event at ln 2");
  }
}

TEST(FixedStep, EachMethodsEnergyWitnessConvergesAtItsOrder) {
  // A damped oscillator: the witness's residual (stored energy against the
  // integral of what the damper absorbed) is the method's error in energy.
  // It falls at least as fast as the method's order (a witness integrated by
  // a lower-order rule would fall slower), and may fall an order faster: an
  // oscillator's energy error is a method's amplitude error, which for
  // Heun, for one, is an order higher than its phase error.
  for (const IntegratorInfo& i : fixed_step_methods()) {
    auto residual = [&](double h) {
      MechanicalOscillator m(2.0, 0.1);
      RunResult r = run(m, args_for(i, h, {"--t-end", "2"}));
      EXPECT_EQ(r.status, 0) << i.name << ": " << r.err;
      return energy_residual(r.err);
    };
    expect_order(i, residual(0.02), residual(0.01), "energy residual", true);
  }
}

TEST(FixedStep, TheSymplecticEulersEnergyStaysBoundedWhereExplicitEulersGrows) {
  // 1,000 periods of the undamped oscillator at h omega = 0.1: explicit
  // Euler multiplies the energy by 1 + (h omega)^2 each step (about e^625
  // over the run); the symplectic Euler's energy error stays of order
  // h omega, period after period.
  const std::vector<std::string> args = {"--step", "0.05", "--t-end", "3141.6", "--interval", "1"};
  MechanicalOscillator symplectic;
  std::vector<std::string> a = args;
  a.insert(a.end(), {"--solver", "symplectic_euler"});
  RunResult r = run(symplectic, a);
  ASSERT_EQ(r.status, 0) << r.err;
  const Csv csv = parse_csv(r.csv);
  double worst = 0;
  for (std::size_t k = 0; k < csv.rows.size(); ++k) worst = std::max(worst, std::abs(csv.at(k, "energy") - 2.0) / 2.0);
  EXPECT_LT(worst, 0.1) << "relative energy error over 1,000 periods";
  MechanicalOscillator euler;
  a = args;
  a.insert(a.end(), {"--solver", "euler"});
  r = run(euler, a);
  ASSERT_EQ(r.status, 0) << r.err;
  const Csv grown = parse_csv(r.csv);
  EXPECT_GT(grown.at(grown.rows.size() - 1, "energy"), 1e250) << "explicit Euler's energy grows without bound";
}

TEST(FixedStep, TheImplicitMethodsFollowAStiffModelAtStepsFarBeyondTheExplicitLimit) {
  // k = 1e6 at h = 0.01: h k = 1e4, against an explicit stability limit of
  // h k < 2 to 2.8. The fast mode damps every error at once, so what is
  // left is one step's: the linearly implicit Euler's tends to h^2 / 2 sin t
  // as h k grows (its step is then sin t + h cos t), the second-order
  // methods' is smaller. Without the f_t term the linearly implicit methods
  // lose an order here (errors of about h).
  for (const IntegratorInfo& i : fixed_step_methods()) {
    Forced m(1e6);
    RunResult r = run(m, args_for(i, 0.01));
    if (!i.implicit) {
      EXPECT_NE(r.status, 0) << i.name << " cannot be stable at h k = 1e4";
      continue;
    }
    ASSERT_EQ(r.status, 0) << i.name << ": " << r.err;
    EXPECT_LT(max_error(r, [](double t) { return std::sin(t); }), 0.01 * 0.01 / 2 * 1.01) << i.name;
  }
}

TEST(FixedStep, RhoInfIsGeneralizedAlphasDampingOfTheModesAStepCannotResolve) {
  // An oscillator of omega = 1e5 at h = 0.1 (h omega = 1e4, where the
  // method's roots are -rho_inf to 1e-4). The first-order form has two
  // roots per mode and puts both there (a double root), so after n steps
  // the amplitude is between rho_inf^n and n rho_inf^(n - 1) of the start:
  // 1 keeps it, 0.5 leaves 1e-3 to 2e-2 after 10 steps, 0 removes it.
  auto amplitude_after_one_second = [](const char* rho) {
    MechanicalOscillator m(1e5);
    RunResult r = run(m, {"--solver", "generalized_alpha", "--step", "0.1", "--t-end", "1", "--rho-inf", rho});
    EXPECT_EQ(r.status, 0) << r.err;
    const Csv csv = parse_csv(r.csv);
    return std::sqrt(csv.at(csv.rows.size() - 1, "energy") / (0.5 * 1e10));
  };
  EXPECT_NEAR(amplitude_after_one_second("1"), 1.0, 1e-6);
  EXPECT_GT(amplitude_after_one_second("0.5"), std::pow(0.5, 10));
  EXPECT_LT(amplitude_after_one_second("0.5"), 10 * std::pow(0.5, 9));
  EXPECT_LT(amplitude_after_one_second("0"), 1e-6);
}

TEST(FixedStep, RhoInfIsForGeneralizedAlphaAndWithinZeroToOne) {
  MechanicalOscillator a, b;
  RunResult r = run(a, {"--solver", "rk4", "--rho-inf", "0.5"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(Contains(r.err, "--rho-inf applies to --solver generalized_alpha only")) << r.err;
  r = run(b, {"--solver", "generalized_alpha", "--rho-inf", "1.5"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(Contains(r.err, "--rho-inf must be from 0 to 1")) << r.err;
}

TEST(FixedStep, TheSymplecticEulerRefusesAModelWithoutPositionsAndVelocities) {
  Decay m;
  RunResult r = run(m, {"--solver", "symplectic_euler"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(Contains(r.err, "needs each unknown to be a position or a velocity")) << r.err;
  EXPECT_TRUE(r.csv.empty());
}

}  // namespace
}  // namespace mbgrt::test
