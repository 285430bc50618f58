// The closed loop of issue 34's "Done when": a simulated walker who knows nothing but what the
// motors say (after the safety stage) — reaction 250 ms, a turn rate growing with the click
// rate, tremor, arm swing, a 20° strap offset — and a GPS with 3–5 m error at 1 Hz.
#include "Navigation/WalkerSim.h"
#include <catch2/catch.hpp>
#include <array>
#include <cstdio>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::navigation;

namespace {

/// Nine points, eight legs of 50–80 m with turns of 30–150°, named with sign words.
Route eightLegs()
{
    Route r;
    r.source = "eight-legs";
    LocalPlane plane {{48.1492, 11.5678}};
    const double xy[9][2] = {{0, 0}, {0, 60}, {50, 85}, {95, 60}, {95, 0}, {150, -30}, {120, -85}, {40, -90}, {-20, -45}};
    const char* names[9] = {"Start", "Entrance", "Lobby", "Cafeteria", "Library", "Parking", "Station", "Bus", "Exit"};
    for (int i = 0; i < 9; ++i) r.points.push_back({plane.fromXY(xy[i][0], xy[i][1]), names[i], 0});
    return r;
}

/// Long straight legs for the compass's own figure: five targets, 150 m each.
Route compassTargets()
{
    Route r;
    r.source = "compass-targets";
    LatLon p {48.0, 11.0};
    r.points.push_back({p, "", 0});
    for (double bearing : {0.0, 120.0, 230.0, 330.0, 60.0}) {
        p = destination(p, bearing, 150.0);
        r.points.push_back({p, "", 0});
    }
    return r;
}

} // namespace

TEST_CASE("compass closed loop (§4.1): the walking direction within ±5° of the target (median), the 20° strap offset learned away", "[walk]")
{
    WalkerParams w;   // reaction 0.25 s, tremor 1.5°, strap 20°, GPS 4 m wandering + 1 m white at 1 Hz
    NavigationOptions nav;
    double medians[3] = {};
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
        w.seed = seed;
        const WalkResult r = simulateWalk(compassTargets(), nav, w, {});
        std::printf("compass seed %llu: finished %d in %.0f s, median |error| %.2f°, 90th percentile %.2f°, learned offset %.1f° (strap %.0f°)\n",
                    static_cast<unsigned long long>(seed), r.finished ? 1 : 0, r.seconds, r.medianHeadingErrorDeg, r.p90HeadingErrorDeg,
                    r.learnedOffsetDeg, w.strapOffsetDeg);
        CHECK(r.finished);
        CHECK(r.learnedOffsetDeg == Approx(w.strapOffsetDeg).margin(5.0));
        medians[seed - 1] = r.medianHeadingErrorDeg;
        CHECK(r.medianHeadingErrorDeg <= 5.0);
    }
    // The probe can see a bias: without the learning the strap's 20° stays in the walking direction.
    nav.learnHeading = false;
    w.seed = 1;
    const WalkResult unlearned = simulateWalk(compassTargets(), nav, w, {});
    std::printf("compass without learning: median |error| %.2f°\n", unlearned.medianHeadingErrorDeg);
    CHECK(unlearned.medianHeadingErrorDeg > 12.0);
    CHECK(medians[0] < unlearned.medianHeadingErrorDeg);
}

TEST_CASE("a whole route of 8 legs walked by the motors alone: every waypoint in order, never more than 15 m off the route", "[walk]")
{
    const Route route = eightLegs();
    for (double gpsError : {3.0, 5.0}) {
        for (std::uint64_t seed = 1; seed <= 2; ++seed) {
            WalkerParams w;
            w.seed = seed * 11;
            w.gpsBiasM = gpsError;
            WalkOptions o;
            o.startHeadingDeg = 200.0;   // starts facing away from the first waypoint
            const WalkResult r = simulateWalk(route, {}, w, o);
            std::printf("route, GPS %.0f m, seed %llu: finished %d in %.0f s, arrivals %zu, max off route %.1f m, median |error| %.2f°, offset %.1f°\n",
                        gpsError, static_cast<unsigned long long>(seed), r.finished ? 1 : 0, r.seconds, r.arrivals.size(), r.maxOffRouteM,
                        r.medianHeadingErrorDeg, r.learnedOffsetDeg);
            CHECK(r.finished);
            std::vector<int> expected;
            for (int k = 2; k <= static_cast<int>(route.points.size()); ++k) expected.push_back(k);
            CHECK(r.arrivals == expected);
            CHECK(r.maxOffRouteM <= 15.0);
        }
    }
}

TEST_CASE("a route without a course from the receiver: the offset from lines fitted through the fixes", "[walk]")
{
    WalkerParams w;
    w.gpsCourse = false;
    w.seed = 5;
    const WalkResult r = simulateWalk(eightLegs(), {}, w, {});
    std::printf("route without course over ground: finished %d in %.0f s, max off route %.1f m, median |error| %.2f°, offset %.1f°\n",
                r.finished ? 1 : 0, r.seconds, r.maxOffRouteM, r.medianHeadingErrorDeg, r.learnedOffsetDeg);
    CHECK(r.finished);
    CHECK(r.maxOffRouteM <= 15.0);
}

TEST_CASE("a magnetic disturbance the fusion reports does not teach the strap offset; one it misses would", "[walk]")
{
    // 60 s of a field bent by 40° on the first long leg of the compass route (the walker keeps
    // walking straight on the heading it had: the compass is fooled either way, the learning not).
    WalkerParams w;
    w.seed = 4;
    w.disturbance.fromS = 40.0;
    w.disturbance.toS = 100.0;
    w.disturbance.biasDeg = 40.0;
    double offsetAtEnd[2] = {};
    for (int flagged = 0; flagged < 2; ++flagged) {
        w.disturbance.flagged = flagged == 1;
        double worst = 0.0;
        WalkOptions o;
        o.maxSeconds = 100.0;
        o.observe = [&](double t, const WalkerView&, const MotorLevels&, const NavigationStatus& st) {
            if (t > 45.0) worst = std::max(worst, std::fabs(wrap180(st.offsetDeg - w.strapOffsetDeg)));
        };
        const WalkResult r = simulateWalk(compassTargets(), {}, w, o);
        offsetAtEnd[flagged] = r.learnedOffsetDeg;
        std::printf("disturbance %s by the fusion: offset %.1f° at 100 s, worst %.1f° from the strap during it\n", flagged ? "reported" : "missed",
                    r.learnedOffsetDeg, worst);
        if (flagged) CHECK(worst < 8.0);
        else CHECK(worst > 15.0);   // the probe: a missed disturbance does pull the offset
    }
    CHECK(std::fabs(offsetAtEnd[1] - w.strapOffsetDeg) < std::fabs(offsetAtEnd[0] - w.strapOffsetDeg));
}

TEST_CASE("the whole walk's motor levels keep the safety bounds (docs/TACTILE.md)", "[walk][safety]")
{
    // Every level left the safety stage; checked here on what the walker felt: above the rating
    // (level 5) at most 300 ms at a time, and mean power (level/15)² over any 10 s ≤ (5/15)².
    WalkerParams w;
    w.seed = 7;
    const double dt = 0.01;
    std::vector<std::array<std::uint8_t, kGridMotors>> frames;
    WalkOptions o;
    o.observe = [&](double, const WalkerView&, const MotorLevels& levels, const NavigationStatus&) {
        std::array<std::uint8_t, kGridMotors> f {};
        for (int m = 0; m < kGridMotors; ++m) f[static_cast<std::size_t>(m)] = levels[static_cast<std::size_t>(m)];
        frames.push_back(f);
    };
    const WalkResult r = simulateWalk(eightLegs(), {}, w, o);
    REQUIRE(r.finished);
    const std::size_t window = static_cast<std::size_t>(10.0 / dt);
    double worstPower = 0.0, longestAbove = 0.0;
    int maxLevel = 0;
    for (int m = 0; m < kGridMotors; ++m) {
        double sum = 0.0, above = 0.0;
        for (std::size_t i = 0; i < frames.size(); ++i) {
            const int level = frames[i][static_cast<std::size_t>(m)];
            maxLevel = std::max(maxLevel, level);
            sum += (level / 15.0) * (level / 15.0);
            if (i >= window) sum -= (frames[i - window][static_cast<std::size_t>(m)] / 15.0) * (frames[i - window][static_cast<std::size_t>(m)] / 15.0);
            if (i + 1 >= window) worstPower = std::max(worstPower, sum / static_cast<double>(window));
            above = level > 5 ? above + dt : 0.0;
            longestAbove = std::max(longestAbove, above);
        }
    }
    std::printf("walk safety: highest level %d, longest above level 5 %.2f s, worst 10 s mean power %.4f (limit %.4f)\n", maxLevel, longestAbove, worstPower,
                (5.0 / 15.0) * (5.0 / 15.0));
    CHECK(maxLevel > 0);   // the probe: the motors did run
    CHECK(longestAbove <= 0.3 + 1e-9);
    CHECK(worstPower <= (5.0 / 15.0) * (5.0 / 15.0) + 1e-9);
}
