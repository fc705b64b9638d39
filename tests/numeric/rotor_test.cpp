// rotor_test.cpp — rotors (multibody/rotors.hpp): a body symmetric about the
// revolute joint it spins on, written in a frame that leaves out its spin,
// moves as the same body written in its own frame (mbgc --no-rotors), and
// reads the same: its own axes, angular velocity, quaternion and Bryant
// angles, its angular momentum and its points. Which bodies are rotors is
// the golden test's (tests/golden/good/rotors.causality.txt).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "sim_run.hpp"

using namespace numeric;

namespace {

/// Both runs succeed on the same grid and every output agrees to `tol` of its peak.
void expect_same_run(const std::string& a_sim, const std::string& b_sim, const std::string& args, const std::string& tag,
                     double tol) {
  SimRun a = run(a_sim, args, tag + "_rotors");
  SimRun b = run(b_sim, args, tag + "_own_frames");
  ASSERT_EQ(a.status, 0) << a.log;
  ASSERT_EQ(b.status, 0) << b.log;
  ASSERT_EQ(a.csv.header, b.csv.header);
  ASSERT_GT(a.csv.rows.size(), 10u);
  for (std::size_t c = 1; c < a.csv.header.size(); ++c) {
    const std::string& name = a.csv.header[c];
    EXPECT_LE(max_difference(a.csv, b.csv, name), tol * std::max(b.csv.max_abs(name), 1e-3)) << name;
  }
}

}  // namespace

TEST(Rotors, ASpinningDiscOnATurntableMovesAndReadsAsInItsOwnFrame) {
  // The disc spins at 50 rad/s on a table turning about a tilted axis under
  // gravity: its gyroscopic torque loads the table's bearing and changes
  // the table's rate. A driven fan and a ball on a pendulum's tip are rotors
  // too; four lookalikes are not. Every output, the disc's own axes among
  // them, agrees with the run in the bodies' own frames to rounding.
  expect_same_run(ROTORS_SIM, ROTORS_OWN_FRAMES_SIM, "", "turntable", 1e-10);
}

TEST(Rotors, TheCarsWheelsAsRotorsGiveTheSameRun) {
  // The two-track car's four wheels are rotors (on the steered knuckles and
  // the rear carriers, on Magic Formula tyres, the rear ones driven): its
  // 8 s manoeuvre at a fixed step gives the same outputs as the car written
  // with every body in its own frame.
  expect_same_run(TWO_TRACK_SIM, TWO_TRACK_OWN_FRAMES_SIM, "--solver rk4 --step 1e-3", "two_track", 1e-9);
}
