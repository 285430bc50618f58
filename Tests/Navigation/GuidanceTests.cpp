// The guidance state machine with scripted position reports (no motors): arrival within the
// radius, the next waypoint, off route, fix lost (timeout, "no fix", poor accuracy), garbage and
// jumps refused, the end of the route; and the heading learner on synthetic data.
#include "Navigation/Guidance.h"
#include "Navigation/HeadingLearner.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

using namespace armadillo::navigation;

namespace {

/// Start, then 100 m north ("A"), then 100 m east of that ("B").
Route lRoute()
{
    Route r;
    r.source = "test";
    const LatLon s {48.0, 11.0};
    r.points.push_back({s, "Start", 0});
    r.points.push_back({destination(s, 0.0, 100.0), "A", 0});
    r.points.push_back({destination(r.points[1].pos, 90.0, 100.0), "B", 0});
    return r;
}

struct Feed {
    PositionFix fix {};
    std::uint64_t serial = 0;
    void at(const LatLon& p, double accuracy = 4.0)
    {
        fix = {};
        fix.pos = p;
        fix.quality = FixQuality::Fix2D;
        fix.accuracyM = accuracy;
        fix.serial = ++serial;
    }
    void none()
    {
        fix = {};
        fix.serial = ++serial;
    }
};

} // namespace

TEST_CASE("guidance: distance and bearing to point 2 first; arrival inside the radius, not outside", "[guidance]")
{
    const Route r = lRoute();
    GuidanceParams p;
    p.maxSpeedMps = 1e6;   // the test puts the walker anywhere at once
    Guidance g(r, p);
    Feed f;
    f.at(r.points[0].pos);
    GuidanceStep s = g.step(0.01, f.fix);
    CHECK(s.fix == FixState::Ok);
    CHECK(s.newFix);
    CHECK(s.waypoint == 2);
    CHECK(s.distanceM == Approx(100.0).margin(0.01));
    CHECK(s.bearingDeg == Approx(0.0).margin(0.01));
    f.at(destination(r.points[1].pos, 180.0, 8.5));   // 8.5 m short: not yet
    s = g.step(0.5, f.fix);
    CHECK(s.arrivedAt == 0);
    CHECK(s.waypoint == 2);
    f.at(destination(r.points[1].pos, 180.0, 7.5));   // inside 8 m
    s = g.step(0.5, f.fix);
    CHECK(s.arrivedAt == 2);
    CHECK(s.waypoint == 3);
    CHECK(s.bearingDeg == Approx(initialBearingDeg(destination(r.points[1].pos, 180.0, 7.5), r.points[2].pos)).margin(1e-9));
    s = g.step(0.5, f.fix);   // the same report again: no second arrival
    CHECK(s.arrivedAt == 0);
    f.at(destination(r.points[2].pos, 270.0, 3.0));
    s = g.step(0.5, f.fix);
    CHECK(s.arrivedAt == 3);
    CHECK(s.finished);
    CHECK(s.waypoint == 4);
    CHECK(g.step(0.5, f.fix).finished);
}

TEST_CASE("guidance: the arrival radius is the user's", "[guidance]")
{
    const Route r = lRoute();
    GuidanceParams p;
    p.arrivalRadiusM = 20.0;
    Guidance g(r, p);
    Feed f;
    f.at(destination(r.points[1].pos, 180.0, 19.0));
    CHECK(g.step(0.1, f.fix).arrivedAt == 2);
}

TEST_CASE("guidance: off route beyond the set distance from the leg, a reminder every 10 s, back on route with hysteresis", "[guidance]")
{
    const Route r = lRoute();
    Guidance g(r);
    Feed f;
    f.at(destination(destination(r.points[0].pos, 0.0, 50.0), 90.0, 19.0));
    GuidanceStep s = g.step(0.1, f.fix);
    CHECK_FALSE(s.offRoute);
    CHECK(s.legDistanceM == Approx(19.0).margin(0.05));
    f.at(destination(destination(r.points[0].pos, 0.0, 50.0), 90.0, 21.0));
    s = g.step(0.9, f.fix);
    CHECK(s.offRoute);
    CHECK(s.offRouteCue);
    int cues = 0;
    for (int i = 0; i < 1500; ++i) {   // 15 s still off (fresh fixes each second): one reminder after 10 s
        if (i % 100 == 0) f.at(destination(destination(r.points[0].pos, 0.0, 50.0), 90.0, 21.0));
        cues += g.step(0.01, f.fix).offRouteCue ? 1 : 0;
    }
    CHECK(cues == 1);
    f.at(destination(destination(r.points[0].pos, 0.0, 50.0), 90.0, 17.0));   // between 15 and 20: still off
    CHECK(g.step(0.1, f.fix).offRoute);
    f.at(destination(destination(r.points[0].pos, 0.0, 50.0), 90.0, 14.0));
    CHECK_FALSE(g.step(0.1, f.fix).offRoute);
}

TEST_CASE("guidance: fix lost after the timeout, at once on 'no fix', and for a poor accuracy; waiting before any report", "[guidance]")
{
    const Route r = lRoute();
    Guidance g(r);
    Feed f;
    CHECK(g.step(0.1, f.fix).fix == FixState::Waiting);
    f.at(r.points[0].pos);
    CHECK(g.step(0.1, f.fix).fix == FixState::Ok);
    GuidanceStep s;
    for (int i = 0; i < 290; ++i) s = g.step(0.01, f.fix);   // 2.9 s without a new report
    CHECK(s.fix == FixState::Ok);
    s = g.step(0.2, f.fix);
    CHECK(s.fix == FixState::Lost);
    CHECK(s.fixLostNow);
    CHECK_FALSE(g.step(0.01, f.fix).fixLostNow);   // said once
    f.at(r.points[0].pos);
    CHECK(g.step(0.1, f.fix).fix == FixState::Ok);
    f.none();
    CHECK(g.step(0.1, f.fix).fix == FixState::Lost);
    f.at(r.points[0].pos, 80.0);   // 80 m accuracy: not usable
    CHECK(g.step(0.1, f.fix).fix == FixState::Lost);
    // With nothing at all for longer than the timeout, the walker is told too.
    Guidance g2(r);
    PositionFix nothing;
    GuidanceStep s2;
    for (int i = 0; i < 400; ++i) s2 = g2.step(0.01, nothing);
    CHECK(s2.fix == FixState::Lost);
}

TEST_CASE("guidance: garbage and jumps are refused; a jump repeated three times is the receiver re-acquiring", "[guidance]")
{
    const Route r = lRoute();
    Guidance g(r);
    Feed f;
    f.at(r.points[0].pos);
    g.step(1.0, f.fix);
    f.at({std::nan(""), 11.0});
    GuidanceStep s = g.step(1.0, f.fix);
    CHECK(s.rejectedFix);
    f.at({95.0, 11.0});
    CHECK(g.step(1.0, f.fix).rejectedFix);
    const LatLon far = destination(r.points[0].pos, 90.0, 2000.0);   // 2 km in a second
    f.at(far);
    s = g.step(1.0, f.fix);
    CHECK(s.rejectedFix);
    CHECK(s.bearingDeg == Approx(0.0).margin(0.01));   // still guided from the last good fix
    f.at(far);
    CHECK(g.step(1.0, f.fix).rejectedFix);
    f.at(far);
    s = g.step(1.0, f.fix);
    CHECK_FALSE(s.rejectedFix);
    CHECK(s.newFix);
    CHECK(g.lastFix().pos.lon == Approx(far.lon));
}

TEST_CASE("heading learner: the strap offset from the course over ground, swing cancelled; turning samples refused", "[heading]")
{
    std::mt19937_64 rng(3);
    std::normal_distribution<double> n(0.0, 1.0);
    HeadingLearner learner;
    const double offset = 20.0, course = 75.0;
    double t = 0.0;
    for (int fix = 0; fix < 30; ++fix) {
        for (int k = 0; k < 100; ++k, t += 0.01) {
            const double swing = std::sin(2.0 * 3.14159265358979 * 0.9 * t);
            learner.arm(t, course + offset + 5.0 * swing + 1.5 * n(rng), -10.0 + 12.0 * std::cos(2.0 * 3.14159265358979 * 0.9 * t));
        }
        learner.fix(t, 0.0, 0.0, course + 5.0 * n(rng), 1.3);
    }
    CHECK(learner.learned());
    CHECK(learner.offsetDeg() == Approx(offset).margin(3.0));
    CHECK(learner.swingPeriodS() == Approx(1.0 / 0.9).margin(0.1));
    // Standing still: nothing learned.
    HeadingLearner still;
    for (int fix = 0; fix < 30; ++fix) {
        for (int k = 0; k < 100; ++k, t += 0.01) still.arm(t, 95.0, -10.0);
        still.fix(t, 0.0, 0.0, 75.0, 0.1);
    }
    CHECK(still.samples() == 0);
    // Turning fast (90°/s): the arm is not steady over a fix, nothing learned.
    HeadingLearner turning;
    for (int fix = 0; fix < 30; ++fix) {
        for (int k = 0; k < 100; ++k, t += 0.01) turning.arm(t, wrap360(90.0 * t), -10.0);
        turning.fix(t, 0.0, 0.0, 75.0, 1.3);
    }
    CHECK(turning.samples() == 0);
}

TEST_CASE("heading learner: without a course from the source, a line fitted through the fixes", "[heading]")
{
    HeadingLearner learner;
    const double course = 200.0, offset = -15.0;
    double t = 0.0;
    std::mt19937_64 rng(9);
    std::normal_distribution<double> n(0.0, 1.0);
    double x = 0.0, y = 0.0;
    const double c = course * 3.14159265358979 / 180.0;
    for (int fix = 0; fix < 60; ++fix) {
        for (int k = 0; k < 100; ++k, t += 0.01) learner.arm(t, wrap360(course + offset + n(rng)), -10.0);
        x += 1.3 * std::sin(c);
        y += 1.3 * std::cos(c);
        learner.fix(t, x + 0.8 * n(rng), y + 0.8 * n(rng), std::nan(""), std::nan(""));
    }
    CHECK(learner.learned());
    CHECK(learner.offsetDeg() == Approx(offset).margin(4.0));
}
