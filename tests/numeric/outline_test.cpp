// outline_test.cpp — codegen/outline writes the articulated-body elimination
// of bodies with the same equations once, as a function called per body. It
// must change where the arithmetic is written, never the arithmetic: the
// derivative (and the outputs) of each model compiled with and without
// outlining agree bit for bit, at the initial state and at a state moved off
// it (and so do their energy witness's power and their bodies' poses).
// Without a kinematic tree (the multiplier form, a DAE) the equations of
// each body and joint are grouped and outlined instead, and so are the rows
// each one writes (a body's residual rows, a joint's constraint rows and
// their derivatives): its residual, constraints, constraint Jacobian, outputs,
// energy witness and body poses agree bit for bit likewise (outlined, power()
// and stored_energy() read what they both need from witness_values(), which
// the inline form does not write: codegen/shared_values). And the
// outlined form must actually be used (its file reads `_shape1(`), so that
// the test cannot pass by comparing a model with itself.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "inline_binary_tree.hpp"
#include "inline_chain.hpp"
#include "inline_fourbar_row.hpp"
#include "inline_n_four_bar.hpp"
#include "outline_binary_tree.hpp"
#include "outline_chain.hpp"
#include "outline_fourbar_row.hpp"
#include "outline_n_four_bar.hpp"

namespace {

void expect_same_numbers(mbgrt::Model& outlined, mbgrt::Model& plain) {
  ASSERT_EQ(outlined.size(), plain.size());
  const std::size_t n = plain.size();
  std::vector<double> y(n), yp(n), y2(n), yp2(n);
  outlined.initial(0.0, y.data(), yp.data());
  plain.initial(0.0, y2.data(), yp2.data());
  for (int moved = 0; moved < 2; ++moved) {
    if (moved)
      for (std::size_t i = 0; i < n; ++i) y[i] += 0.05 * std::sin(1.0 + 0.7 * static_cast<double>(i));
    std::vector<double> a(n), b(n);
    outlined.derivative(0.1, y.data(), a.data());
    plain.derivative(0.1, y.data(), b.data());
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_TRUE(std::isfinite(a[i])) << plain.variable_name(i);
      EXPECT_EQ(std::memcmp(&a[i], &b[i], sizeof(double)), 0)
          << plain.variable_name(i) << ": " << a[i] << " outlined, " << b[i] << " inline (state " << moved << ")";
    }
    const std::size_t m = plain.output_names().size();
    std::vector<double> oa(m), ob(m);
    outlined.outputs(0.1, y.data(), yp.data(), oa.data());
    plain.outputs(0.1, y.data(), yp.data(), ob.data());
    for (std::size_t k = 0; k < m; ++k)
      EXPECT_EQ(std::memcmp(&oa[k], &ob[k], sizeof(double)), 0) << plain.output_names()[k];
    std::vector<double> pa(2), pb(2);
    outlined.power(0.1, y.data(), yp.data(), pa.data());
    plain.power(0.1, y.data(), yp.data(), pb.data());
    for (std::size_t k = 0; k < 2; ++k) EXPECT_EQ(std::memcmp(&pa[k], &pb[k], sizeof(double)), 0) << "power " << k;
    std::vector<double> ba(12 * plain.body_count()), bb(12 * plain.body_count());
    outlined.body_poses(0.1, y.data(), yp.data(), ba.data());
    plain.body_poses(0.1, y.data(), yp.data(), bb.data());
    for (std::size_t k = 0; k < ba.size(); ++k) EXPECT_EQ(std::memcmp(&ba[k], &bb[k], sizeof(double)), 0) << "body_poses " << k;
  }
}

void expect_same_bits(const std::vector<double>& a, const std::vector<double>& b, const char* what, int moved) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_TRUE(std::isfinite(a[i])) << what << "[" << i << "]";
    EXPECT_EQ(std::memcmp(&a[i], &b[i], sizeof(double)), 0)
        << what << "[" << i << "]: " << a[i] << " outlined, " << b[i] << " inline (state " << moved << ")";
  }
}

/// A DAE (the multiplier form): residual, constraints, their Jacobian,
/// outputs, the energy witness (stored energy and power) and the bodies' poses.
void expect_same_residuals(mbgrt::Model& outlined, mbgrt::Model& plain) {
  ASSERT_EQ(outlined.size(), plain.size());
  ASSERT_TRUE(plain.is_dae());
  const std::size_t n = plain.size();
  std::vector<double> y(n), yp(n), y2(n), yp2(n);
  outlined.initial(0.0, y.data(), yp.data());
  plain.initial(0.0, y2.data(), yp2.data());
  expect_same_bits(y, y2, "y0", 0);
  for (int moved = 0; moved < 2; ++moved) {
    if (moved)
      for (std::size_t i = 0; i < n; ++i) {
        y[i] += 0.05 * std::sin(1.0 + 0.7 * static_cast<double>(i));
        yp[i] += 0.1 * std::cos(0.3 + 1.1 * static_cast<double>(i));
      }
    std::vector<double> a(n), b(n);
    outlined.residual(0.1, y.data(), yp.data(), a.data());
    plain.residual(0.1, y.data(), yp.data(), b.data());
    expect_same_bits(a, b, "residual", moved);
    const std::size_t c = plain.position_constraint_count() + plain.velocity_constraint_count();
    std::vector<double> ca(c), cb(c);
    outlined.constraints(0.1, y.data(), ca.data());
    plain.constraints(0.1, y.data(), cb.data());
    expect_same_bits(ca, cb, "constraints", moved);
    const std::size_t m = plain.output_names().size();
    std::vector<double> oa(m), ob(m);
    outlined.outputs(0.1, y.data(), yp.data(), oa.data());
    plain.outputs(0.1, y.data(), yp.data(), ob.data());
    expect_same_bits(oa, ob, "outputs", moved);
    std::vector<long> starts, columns;
    plain.constraint_jacobian_pattern(starts, columns);
    std::vector<double> ja(columns.size()), jb(columns.size());
    outlined.constraint_jacobian(0.1, y.data(), ja.data());
    plain.constraint_jacobian(0.1, y.data(), jb.data());
    expect_same_bits(ja, jb, "constraint_jacobian", moved);
    std::vector<double> pa(2), pb(2);
    outlined.power(0.1, y.data(), yp.data(), pa.data());
    plain.power(0.1, y.data(), yp.data(), pb.data());
    expect_same_bits(pa, pb, "power", moved);
    std::vector<double> ha(1), hb(1);
    outlined.stored_energy(0.1, y.data(), yp.data(), ha.data());
    plain.stored_energy(0.1, y.data(), yp.data(), hb.data());
    expect_same_bits(ha, hb, "stored_energy", moved);
    ASSERT_GT(plain.body_count(), 0u);
    std::vector<double> ba(12 * plain.body_count()), bb(12 * plain.body_count());
    outlined.body_poses(0.1, y.data(), yp.data(), ba.data());
    plain.body_poses(0.1, y.data(), yp.data(), bb.data());
    expect_same_bits(ba, bb, "body_poses", moved);
  }
}

/// The generated header of model `target` (mbgc_add_model's), as text.
std::string header(const std::string& target) {
  std::ifstream in(std::string(MODELS_DIR) + "/" + target + "_include/" + target + ".hpp");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void expect_outlined(const std::string& name, const char* method = "derivative_and_power") {
  const std::string outlined = header("outline_" + name), plain = header("inline_" + name);
  ASSERT_FALSE(outlined.empty());
  EXPECT_NE(outlined.find(std::string(method) + "_shape1("), std::string::npos) << name << ": nothing outlined";
  EXPECT_EQ(plain.find("_shape1("), std::string::npos) << name << ": --outline never outlined";
}

}  // namespace

TEST(Outline, ChainOfTwelveRodsGivesTheSameNumbersInline) {
  outlined_chain::chain_model a;
  inline_chain::chain_model b;
  expect_outlined("chain");
  expect_same_numbers(a, b);
}

TEST(Outline, BinaryTreeOfFifteenRodsGivesTheSameNumbersInline) {
  outlined_binary_tree::binary_tree_model a;
  inline_binary_tree::binary_tree_model b;
  expect_outlined("binary_tree");
  expect_same_numbers(a, b);
}

TEST(Outline, RowOfFourFourBarsWithCutJointsGivesTheSameNumbersInline) {
  outlined_fourbar_row::fourbar_row_model a;
  inline_fourbar_row::fourbar_row_model b;
  expect_outlined("fourbar_row");
  expect_same_numbers(a, b);
}

TEST(Outline, RowOfFourFourBarsWithMultipliersGivesTheSameNumbersInline) {
  outlined_n_four_bar::n_four_bar_model a;
  inline_n_four_bar::n_four_bar_model b;
  expect_outlined("n_four_bar", "residual");
  expect_outlined("n_four_bar", "constraints");
  expect_outlined("n_four_bar", "constraint_jacobian");
  expect_outlined("n_four_bar", "body_poses");
  expect_same_residuals(a, b);
}
