// Touch fitted to the reader (issue 26): the 1-up/2-down staircase and the per-motor gains of the
// tactile engine.
#include "Tactile/Staircase.h"
#include "Tactile/TactileEngine.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::tactile;

namespace {
/// Runs a staircase against a reader who feels every level ≥ threshold (deterministic).
Staircase runDeterministic(int threshold, StaircaseParams p = {})
{
    Staircase s(p);
    for (int i = 0; i < 200 && !s.done(); ++i) s.answer(s.level() >= threshold);
    return s;
}
} // namespace

TEST_CASE("staircase: the 1-up/2-down rule, step by step", "[touchfit]")
{
    // Levitt's rule written out by hand for a reader whose threshold is 6, start 8, steps 4-2-1:
    // 8 y y -> 4 n (reversal, step 2) -> 6 y y (reversal, step 1) -> 5 n (reversal at 5, counted)
    // -> 6 y y (reversal at 6) -> 5 n (5) -> 6 ...
    Staircase s;
    const int expectLevels[] {8, 8, 4, 6, 6, 5, 6, 6, 5};
    for (int level : expectLevels) {
        REQUIRE(s.level() == level);
        s.answer(level >= 6);
    }
    CHECK(s.reversals() == 3);   // at 5, 6 and 5 again (the step had reached 1 by then)
    CHECK(s.level() == 6);
}

TEST_CASE("staircase: a deterministic reader's threshold is found exactly, at every level", "[touchfit]")
{
    for (int t = 1; t <= 15; ++t) {
        const Staircase s = runDeterministic(t);
        INFO("threshold " << t << " trials " << s.trials());
        CHECK(s.done());
        CHECK(s.felt());
        CHECK(s.threshold() == t);
        CHECK(s.trials() <= 30);
    }
}

TEST_CASE("staircase: never felt ends at the top as not felt; always felt ends at the bottom", "[touchfit]")
{
    Staircase never;
    for (int i = 0; i < 100 && !never.done(); ++i) never.answer(false);
    CHECK(never.done());
    CHECK_FALSE(never.felt());
    CHECK(never.threshold() == 15);
    CHECK(never.trials() < 20);
    Staircase always;
    for (int i = 0; i < 100 && !always.done(); ++i) always.answer(true);
    CHECK(always.done());
    CHECK(always.threshold() == 1);
}

TEST_CASE("staircase: a noisy reader (psychometric slope) is found within one level", "[touchfit]")
{
    // P(felt) = logistic((level - t) / 0.5): the 70.7 % point is t + 0.44, within a level of t.
    std::mt19937_64 rng(7);
    int within = 0, runs = 0;
    for (int t = 3; t <= 12; ++t)
        for (int rep = 0; rep < 20; ++rep) {
            Staircase s;
            std::uniform_real_distribution<double> u(0.0, 1.0);
            while (!s.done()) s.answer(u(rng) < 1.0 / (1.0 + std::exp(-(s.level() - t) / 0.5)));
            ++runs;
            within += std::abs(s.threshold() - t) <= 1;
        }
    INFO(within << " of " << runs);
    CHECK(within >= runs * 8 / 10);
}

TEST_CASE("touch profile gains: scaled before shaping and safety, per physical motor, both arms", "[touchfit]")
{
    for (ArmSide side : {ArmSide::Right, ArmSide::Left}) {
        TactileConfig c;
        c.side = side;
        c.motorGain[0] = 2.0f;    // m1: the wrist row's left motor on the wearer's body
        c.motorGain[2] = 0.5f;    // m3
        c.motorGain[4] = 10.0f;   // m5: would exceed 15
        TactileEngine e;
        e.prepare(c);
        // Soft targets (no jump-start spike) at level 4 on the whole wrist row and m5.
        for (int m : {0, 1, 2, 4}) e.setSoftLevel(m, 4.0f);
        MotorLevels out {};
        for (int i = 0; i < 10; ++i) out = e.tick(0.005);
        INFO("side " << (side == ArmSide::Left ? "left" : "right"));
        // Physical motors: m1 gets 8, m3 gets 2 on either arm (the intents land mirrored on the
        // left arm, and the gain follows the physical motor); m2 unchanged.
        CHECK(out[0] == 8);
        CHECK(out[1] == 4);
        CHECK(out[2] == 2);
        // m5: 40 clamps to 15 and the safety stage still limits a long run above the rating.
        CHECK(out[4] == 15);
        for (int i = 0; i < 200; ++i) out = e.tick(0.005);
        CHECK(out[4] <= kRatedLevel);
    }
    // Bad gains are ignored (1).
    TactileConfig c;
    c.motorGain[0] = std::nanf("");
    c.motorGain[1] = -3.0f;
    TactileEngine e;
    e.prepare(c);
    e.setSoftLevel(0, 4.0f);
    e.setSoftLevel(1, 4.0f);
    MotorLevels out {};
    for (int i = 0; i < 10; ++i) out = e.tick(0.005);
    CHECK(out[0] == 4);
    CHECK(out[1] == 4);
}
