// Unit tests for reduce/events: which steps of a reduced system are events,
// which are time events, where each comes from, and the time kinks of min
// and max written as steps (tests/numeric/events_test.cpp runs them).
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "pipeline.hpp"

namespace {

using namespace mbgc_test;

std::unique_ptr<Compiled> reduce(const std::string& text) { return run(text, Stage::Reduce); }

const char* kCharge =
    "param C = 2\nparam v1 = 0.4\nparam t0 = 0.5\nparam a = 1\n"
    "Sf src = step(t0) + heaviside(cap.e - v1) + 2 * heaviside(cap.e - v1) + heaviside(a - 0.5)\n"
    "C cap = C\n0 n : src -> cap\noutput v = cap.e\n";

TEST(FindEvents, StepsThatChangeDuringARunAreEventsOnceEachAndParameterStepsAreNot) {
  auto c = reduce(kCharge);
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::ReducedSystem& r = c->reduced;
  ASSERT_EQ(r.events.size(), 2u);  // the same step twice is one event; heaviside(a - 0.5) is a constant
  std::set<std::string> args;
  for (const ir::EventRelation& ev : r.events) {
    args.insert(str(ev.arg, r.graph));
    EXPECT_EQ(ev.time_event, str(ev.arg, r.graph) == "t - t0");
    EXPECT_EQ(ev.loc.line, 5);  // the Sf's line
    EXPECT_EQ(ev.origin.substr(0, ev.origin.find(':')), "Sf src");
  }
  EXPECT_EQ(args, (std::set<std::string>{"t - t0", "cap.e - v1"}));
  EXPECT_FALSE(r.for_events.empty());  // cap.e is computed for the event functions
}

TEST(FindEvents, AMinOrMaxWithAKinkInTimeBecomesAStepAndOneOfAStateDoesNot) {
  auto c = reduce("param C = 2\nparam t0 = 0.35\nparam vmax = 1\n"
                  "Sf src = ramp(t0) + min(cap.e, vmax)\nC cap = C\n0 n : src -> cap\noutput v = cap.e\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::ReducedSystem& r = c->reduced;
  ASSERT_EQ(r.events.size(), 1u);  // ramp's max(0, t - t0); min(cap.e, vmax) stays a min
  EXPECT_TRUE(r.events[0].time_event);
  bool min_left = false;
  for (const ir::Assignment& a : r.assignments)
    if (a.value && str(a.value, r.graph).find("min(") != std::string::npos) min_left = true;
  EXPECT_TRUE(min_left);
  // Its function crosses zero at t0 and nowhere else.
  auto arg_at = [&](double t) { return eval(r.events[0].arg, evaluate(r, {{"cap.q", 0.0}}, t)); };
  EXPECT_EQ(arg_at(0.35), 0.0);
  EXPECT_LT(arg_at(0.2) * arg_at(0.5), 0.0);
}

TEST(FindEvents, AModelWithoutStepsHasNone) {
  auto c = reduce("param V = 5\nSe src = V\nR r = 2\nC c = 0.1\n1 loop : src -> r, c\noutput vc = c.e\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_TRUE(c->reduced.events.empty());
  EXPECT_TRUE(c->reduced.for_events.empty());
}

}  // namespace

TEST(FindEvents, SelectIsAChoiceNotAnEventAndNeitherIsTheKinkOfAMinInADerivative) {
  // select(x) picks between two expressions that agree at x = 0; a min of a
  // state in a law whose derivative is taken (its MTF's modulus, its
  // Jacobian) selects a side by select, not heaviside.
  auto c = reduce("param C = 2\nparam vmax = 1\n"
                  "Sf src = select(cap.e - vmax) * vmax + (1 - select(cap.e - vmax)) * cap.e + min(cap.e, vmax)\n"
                  "C cap = C\n0 n : src -> cap\noutput v = cap.e\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_TRUE(c->reduced.events.empty());
  EXPECT_FALSE(c->reduced.jacobian.empty());
}

TEST(FindEvents, AUnilateralContactIsOneEventAndItsFrictionAnother) {
  auto c = reduce("Se f = [1, 1, 0]\nI m = diag(1, 1, 1)\nC s = diag(1, 1, 1) { q0 = [1, 1, 1] }\n"
                  "CN stop { g = s.q; restitution = 0.5; friction = 0.3 }\n"
                  "1 v : f -> m, s, stop\noutput closed = stop.closed\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::ReducedSystem& r = c->reduced;
  ASSERT_EQ(r.contacts.size(), 1u);
  ASSERT_EQ(r.events.size(), 2u);
  EXPECT_EQ(r.events[0].contact, 0);
  EXPECT_FALSE(r.events[0].friction);
  EXPECT_EQ(r.events[1].contact, 0);
  EXPECT_TRUE(r.events[1].friction);
  EXPECT_EQ(r.events[0].origin, "contact stop");
  EXPECT_EQ(str(r.events[0].step, r.graph), "stop.closed");
  EXPECT_EQ(str(r.events[1].step, r.graph), "stop.stick");
  EXPECT_TRUE(r.contacts[0].friction);
}
