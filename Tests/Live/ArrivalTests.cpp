// Live samples carry their arrival on the monotonic clock (LiveInput stamps it), and a control
// step can fuse only the samples that arrived by a cutoff (issue 36: the plugin places each
// step at its sample's arrival in the host's block, Live/Session/BlockControl). Real-time like the
// rest of the step (RealtimeLoopTests.cpp is this executable's guard TU).
#include "Common/RealtimeGuard.h"
#include "Core/Clock.h"
#include "Fusion/ArmTracker.h"
#include "Live/Step/ControlLoop.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::fusion;
using namespace armadillo::live;
using namespace armadillo::test;

namespace {

LiveImu restingSample(double t)
{
    LiveImu s;
    s.t = t;
    s.a[1] = 9.81f;   // face up, at rest
    s.m[0] = 0.0f;
    s.m[1] = -0.4f;
    s.m[2] = -0.2f;
    return s;
}

/// A time strictly after `t` on the monotonic clock (the clock's resolution is far below 1 µs;
/// this only spins until the next distinct reading).
double after(double t)
{
    double now = monotonicSeconds();
    while (!(now > t)) now = monotonicSeconds();
    return now;
}

} // namespace

TEST_CASE("live samples are stamped with their arrival on the monotonic clock", "[live][arrival]")
{
    LiveInput in;
    const double before = monotonicSeconds();
    LiveImu s = restingSample(1.0);
    s.arrival = -5.0;   // whatever the producer wrote: the mailbox stamps it
    REQUIRE(in.pushImu(s));
    in.storeOrientation(1.0, Eigen::Quaterniond::Identity());
    const double afterPush = monotonicSeconds();
    LiveImu got;
    REQUIRE(in.peekImu(got));
    CHECK(got.arrival >= before);
    CHECK(got.arrival <= afterPush);
    CHECK(in.imuWaiting() == 1);   // peek leaves it
    const LiveOrientation o = in.latest();
    CHECK(o.arrival >= before);
    CHECK(o.arrival <= afterPush);
}

TEST_CASE("a step fuses only the samples that arrived by its cutoff, in order, and says what waits next", "[live][arrival]")
{
    LiveInput in;
    ArmTracker tracker;
    LiveOrientation last;
    std::uint64_t used = 0;
    REQUIRE(in.pushImu(restingSample(0.010)));
    LiveImu front;
    REQUIRE(in.peekImu(front));
    const double firstArrival = front.arrival;
    (void) after(firstArrival);   // the next pushes are stamped later than the first
    REQUIRE(in.pushImu(restingSample(0.015)));
    REQUIRE(in.pushImu(restingSample(0.020)));

    ArmState arm = fuseStep(in, tracker, last, used, nullptr, firstArrival);
    CHECK(arm.t == Approx(0.010));     // the first only
    CHECK(in.imuWaiting() == 2);
    REQUIRE(in.peekImu(front));
    CHECK(front.t == Approx(0.015));
    CHECK(front.arrival > firstArrival);   // the next one is due later: the plugin steps there

    // A cutoff before everything fuses nothing and keeps the state.
    arm = fuseStep(in, tracker, last, used, nullptr, firstArrival - 1.0);
    CHECK(arm.t == Approx(0.010));
    CHECK(in.imuWaiting() == 2);
    // No cutoff: everything waiting.
    arm = fuseStep(in, tracker, last, used);
    CHECK(arm.t == Approx(0.020));
    CHECK(in.imuWaiting() == 0);
}

TEST_CASE("more than kMaxImuPerStep samples due: the newest are fused, the oldest dropped and counted", "[live][arrival]")
{
    LiveInput in;
    ArmTracker tracker;
    LiveOrientation last;
    std::uint64_t used = 0;
    std::atomic<std::uint64_t> dropped {0};
    const int n = ControlLoop::kMaxImuPerStep + 5;
    for (int i = 0; i < n; ++i) REQUIRE(in.pushImu(restingSample(0.005 * (i + 1))));
    const ArmState arm = fuseStep(in, tracker, last, used, &dropped, after(monotonicSeconds()));
    CHECK(dropped.load() == 5);
    CHECK(arm.t == Approx(0.005 * n));
    CHECK(in.imuWaiting() == 0);
}

TEST_CASE("ControlLoop::nextArrival: the oldest unfused sample of the chosen source; none for host automation", "[live][arrival]")
{
    ControlLoop loop;
    const double inf = std::numeric_limits<double>::infinity();
    CHECK(loop.nextArrival(SourceKind::Osc) == inf);
    CHECK(loop.nextArrival(SourceKind::HostAutomation) == inf);
    loop.input(SourceKind::Osc).storeOrientation(0.5, Eigen::Quaterniond::Identity());
    const double a = loop.nextArrival(SourceKind::Osc);
    CHECK(std::isfinite(a));
    CHECK(a == loop.input(SourceKind::Osc).latest().arrival);
    CHECK(loop.nextArrival(SourceKind::HostAutomation) == inf);
    CHECK(loop.nextArrival(SourceKind::Simulator) == inf);   // another source's mailbox is empty
    REQUIRE(loop.input(SourceKind::Osc).pushImu(restingSample(0.6)));
    LiveImu front;
    REQUIRE(loop.input(SourceKind::Osc).peekImu(front));
    CHECK(loop.nextArrival(SourceKind::Osc) == front.arrival);   // the IMU sample comes first
}

TEST_CASE("fusing by arrival allocates, frees, locks and throws nothing", "[live][arrival][realtime]")
{
    ARMADILLO_REQUIRE_GUARD_SEES_ALLOCATION();
    ControlLoop loop;
    LiveInput& in = loop.input(SourceKind::Osc);
    ArmTracker tracker;
    LiveOrientation last;
    std::uint64_t used = 0;
    std::atomic<std::uint64_t> dropped {0};
    std::uint64_t violations = 0;
    for (int k = 0; k < 200; ++k) {
        for (int i = 0; i < 3; ++i) REQUIRE(in.pushImu(restingSample(0.001 * (3 * k + i + 1))));
        RealtimeGuard guard;
        const double cutoff = loop.nextArrival(SourceKind::Osc) + (k % 2 ? 0.0 : 1.0);
        (void) fuseStep(in, tracker, last, used, &dropped, cutoff);
        violations += guard.allocations() + guard.deallocations() + guard.locks() + guard.throws();
    }
    CHECK(violations == 0);
}
