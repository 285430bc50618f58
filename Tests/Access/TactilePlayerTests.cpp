// The tactile player of the guided procedures: sequences play at their times through the engine
// and its safety stage, completion is reported, and the control-thread side is real-time.
#define ARMADILLO_REALTIME_GUARD_IMPLEMENTATION
#include "Access/TactilePlayer.h"
#include "Common/RealtimeGuard.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::tactile;
using namespace armadillo::access;
using armadillo::test::RealtimeGuard;

namespace {
constexpr double kPeriod = 0.005;   // s per packet (unpaced clock)
}

TEST_CASE("tactile player: a sequence plays at its times, soft levels exactly, and then reports completion", "[player]")
{
    TactilePlayer p(TactileConfig {}, kPeriod);
    TactileSegment a;
    a.at = 0.1;
    a.duration = 0.2;
    a.motors = 1u << 4;   // m5
    a.level = 3.0f;
    a.soft = true;
    const int n = p.play({a}, 0.1);
    CHECK(n == 1);
    std::vector<int> m5;
    for (int i = 0; i < 100 && p.completed() < 1; ++i) m5.push_back(p.onPacket(0.0)[4]);
    REQUIRE(p.completed() == 1);
    // 0.4 s in all (0.1 before, 0.2 on, 0.1 after) = 80 packets of 5 ms after the packet that
    // took the sequence (its anchor), so completion comes with packet 81; 40 packets on.
    CHECK(m5.size() == 81);
    int on = 0;
    for (std::size_t i = 0; i < m5.size(); ++i) {
        on += m5[i] > 0;
        if (m5[i] > 0) CHECK(m5[i] == 3);   // soft: no jump-start spike
    }
    CHECK(on == 40);
    CHECK(p.maxLevel(4) == 3);
    CHECK(p.maxLevel(0) == 0);
    // A normal (not soft) segment starts with the jump-start spike, and the next sequence waits
    // for the first to end.
    TactileSegment b = a;
    b.at = 0.0;
    b.soft = false;
    b.level = 5.0f;
    p.play({b});
    p.play({b});
    for (int i = 0; i < 200 && p.completed() < 3; ++i) p.onPacket(0.0);
    CHECK(p.completed() == 3);
    CHECK(p.maxLevel(4) == 15);
}

TEST_CASE("tactile player: a strong stimulus repeated without rest is limited by the safety stage", "[player]")
{
    TactilePlayer p(TactileConfig {}, kPeriod);
    TactileSegment s;
    s.duration = 2.0;   // a 2 s run at 12 is far beyond the 0.3 s allowed above the rating
    s.motors = 1u;
    s.level = 12.0f;
    s.soft = true;
    p.play({s});
    int run = 0, longest = 0, above = 0;
    for (int i = 0; i < 1000 && p.completed() < 1; ++i) {
        const MotorLevels out = p.onPacket(0.0);
        run = out[0] > kRatedLevel ? run + 1 : 0;
        longest = std::max(longest, run);
        above += out[0] > kRatedLevel;
    }
    CHECK(p.completed() == 1);
    // docs/TACTILE.md: a run above the rating lasts at most 0.3 s, and at most 30 % of any 2 s.
    CHECK(longest * kPeriod <= 0.3 + 1e-9);
    CHECK(above * kPeriod <= 0.6 + 1e-9);
    CHECK(above > 0);
}

TEST_CASE("tactile player: onPacket allocates, locks and throws nothing", "[player][realtime]")
{
    ARMADILLO_REQUIRE_GUARD();
    {   // the probe sees an allocation on this thread
        RealtimeGuard probe;
        std::vector<int> v(100);
        CHECK(probe.allocations() > 0);
    }
    TactilePlayer p(TactileConfig {}, kPeriod);
    std::vector<TactileSegment> seq;
    for (int k = 0; k < 40; ++k) {
        TactileSegment s;
        s.at = 0.05 * k;
        s.duration = 0.04;
        s.motors = static_cast<std::uint16_t>(1u << (k % 9));
        s.level = 1.0f + static_cast<float>(k % 10);
        s.soft = k % 2 == 0;
        seq.push_back(s);
    }
    p.play(seq, 0.2);
    p.play(seq, 0.2);
    RealtimeGuard guard;
    for (int i = 0; i < 2000; ++i) (void) p.onPacket(0.0);
    CHECK(guard.allocations() == 0);
    CHECK(guard.deallocations() == 0);
    CHECK(guard.locks() == 0);
    CHECK(guard.throws() == 0);
    CHECK(p.completed() == 2);
}
