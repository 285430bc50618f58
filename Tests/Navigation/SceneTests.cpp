// The navigation scene through the real Engine (tactile shaping and safety stage): the compass
// side, the arrival sensation, the waypoint's name read back by the rows method (sign shorthand),
// off route, fix lost, the end of the route, and the status snapshot.
#include "Core/Pose.h"
#include "Engine/Engine.h"
#include "Navigation/NavigationScene.h"
#include "RowsDecoder.h"
#include <catch2/catch.hpp>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;
using namespace armadillo::navigation;

namespace {

Route testRoute()
{
    Route r;
    r.source = "test";
    const LatLon s {48.0, 11.0};
    r.points.push_back({s, "Start", 0});
    r.points.push_back({destination(s, 0.0, 100.0), "Entrance", 0});
    r.points.push_back({destination(r.points[1].pos, 90.0, 100.0), "Exit", 0});
    return r;
}

ArmState thumbToward(double headingDeg)
{
    ArmState a;
    a.valid = true;
    Pose p;
    p.azimuthDeg = wrap360(headingDeg + 90.0);   // palm down: the right thumb lies 90° counter-clockwise of the forearm
    a.q = poseToQuaternion(p);
    return a;
}

struct Rig {
    std::shared_ptr<NavigationLink> link = std::make_shared<NavigationLink>();
    std::unique_ptr<Engine> engine;
    std::vector<test::MotorFrame> frames;
    double t = 0.0;
    explicit Rig(const Route& r, NavigationOptions o = {})
    {
        o.learnHeading = false;
        o.guidance.maxSpeedMps = 1e6;   // the tests put the walker anywhere at once
        EngineConfig c;
        c.scene = "navigate";
        engine = std::make_unique<Engine>(c, makeNavigationScene(r, link, o));
    }
    void fix(const LatLon& p)
    {
        PositionFix f;
        f.pos = p;
        f.quality = FixQuality::Fix3D;
        f.accuracyM = 3.0;
        link->position.store(f);
    }
    MotorLevels run(double seconds, const ArmState& arm, const LatLon* refresh = nullptr)
    {
        MotorLevels last {};
        for (double end = t + seconds; t < end; t += 0.01) {
            if (refresh && std::fmod(t, 1.0) < 0.01) fix(*refresh);
            last = engine->control(arm, Transport {}, 0.01);
            std::uint16_t mask = 0;
            for (int m = 0; m < kGridMotors; ++m)
                if (last[static_cast<std::size_t>(m)] > 0) mask |= static_cast<std::uint16_t>(1u << m);
            frames.push_back({t, mask});
        }
        return last;
    }
    int onsets(int motor, std::size_t from) const
    {
        int n = 0;
        for (std::size_t i = std::max<std::size_t>(from, 1); i < frames.size(); ++i)
            if ((frames[i].mask & (1u << motor)) && !(frames[i - 1].mask & (1u << motor))) ++n;
        return n;
    }
};

} // namespace

TEST_CASE("thumb heading: the compass's definition; palm down the right thumb is 90° counter-clockwise of the forearm", "[scene]")
{
    ArmState rest;
    rest.valid = true;   // forearm north, level, palm down
    CHECK(thumbHeadingDeg(rest, ArmSide::Right) == Approx(270.0).margin(1e-6));
    CHECK(thumbHeadingDeg(thumbToward(37.0), ArmSide::Right) == Approx(37.0).margin(1e-6));
    CHECK(std::isnan(thumbHeadingDeg(ArmState {}, ArmSide::Right)));   // invalid
    Pose up;
    up.elevationDeg = 0.0;
    up.rollDeg = 90.0;   // thumb straight up: no heading
    ArmState a;
    a.valid = true;
    a.q = poseToQuaternion(up);
    CHECK(std::isnan(thumbHeadingDeg(a, ArmSide::Right)));
}

TEST_CASE("scene: the compass clicks on the side to turn toward, faster nearer, steady on both sides on course", "[scene]")
{
    const Route r = testRoute();
    Rig rig(r);
    rig.fix(r.points[0].pos);
    // Waypoint due north, thumb toward 90° (east): turn counter-clockwise = motor index 3 on the right arm.
    std::size_t from = rig.frames.size();
    rig.run(4.0, thumbToward(90.0), &r.points[0].pos);
    const int farLeft = rig.onsets(3, from);
    CHECK(farLeft >= 8);
    CHECK(rig.onsets(5, from) == 0);
    // Thumb toward 340°: turn clockwise (motor index 5), and clicks faster when nearer.
    from = rig.frames.size();
    rig.run(4.0, thumbToward(340.0), &r.points[0].pos);
    CHECK(rig.onsets(3, from + 20) == 0);
    const int nearRight = rig.onsets(5, from);
    CHECK(nearRight > farLeft);
    // On course: both side motors on together.
    const MotorLevels on = rig.run(1.0, thumbToward(1.0), &r.points[0].pos);
    CHECK(on[3] > 0);
    CHECK(on[5] > 0);
    const NavigationStatus st = rig.link->status.load();
    CHECK(st.waypoint == 2);
    CHECK(std::string(st.name) == "Entrance");
    CHECK(std::string(st.shown) == "en");
    CHECK(st.distanceM == Approx(100.0).margin(0.1));
    CHECK(st.bearingDeg == Approx(0.0).margin(0.01));
    CHECK(st.headingDeg == Approx(1.0).margin(0.01));
    CHECK(st.sensation == Sensation::Compass);
}

TEST_CASE("scene: arrival → all nine motors, then the name's shorthand by the rows method between the cues, then the next waypoint", "[scene]")
{
    const Route r = testRoute();
    Rig rig(r);
    rig.fix(r.points[0].pos);
    rig.run(1.0, thumbToward(0.0));
    const LatLon near = destination(r.points[1].pos, 180.0, 5.0);
    rig.fix(near);
    const std::size_t from = rig.frames.size();
    rig.run(0.1, thumbToward(0.0), &near);
    CHECK(rig.frames.back().mask == 0x1FF);   // arrival: the whole grid
    rig.run(12.0, thumbToward(0.0), &near);
    const std::vector<test::MotorFrame> shown(rig.frames.begin() + static_cast<long>(from), rig.frames.end());
    const auto names = test::decodeNames(shown);
    REQUIRE(names.size() == 1);
    CHECK(names[0] == "en");
    const NavigationStatus st = rig.link->status.load();
    CHECK(st.waypoint == 3);
    CHECK(std::string(st.shown) == "ex");
    CHECK(st.arrivals == 1);
    CHECK(st.sensation == Sensation::Compass);   // back to the compass, toward "Exit"
}

TEST_CASE("scene: full names when asked; a name liblouis cannot spell falls back to its letters", "[scene]")
{
    Route r = testRoute();
    r.points[1].name = "Bäckerei 7";
    NavigationOptions o;
    o.names = NameDisplay::Full;
    Rig rig(r, o);
    rig.fix(destination(r.points[1].pos, 0.0, 2.0));
    rig.run(40.0, thumbToward(0.0));   // 11 cells of about 2 s
    const auto names = test::decodeNames(rig.frames);
    REQUIRE(names.size() == 1);
    CHECK(names[0].find("ckerei") != std::string::npos);
}

TEST_CASE("scene: off route → the four corners; fix lost → the centre swelling, no side cue; the end → silence after the swells", "[scene]")
{
    const Route r = testRoute();
    Rig rig(r);
    const LatLon off = destination(destination(r.points[0].pos, 0.0, 50.0), 90.0, 30.0);
    rig.fix(off);
    rig.run(0.15, thumbToward(0.0), &off);
    constexpr std::uint16_t corners = (1u << 0) | (1u << 2) | (1u << 6) | (1u << 8);
    bool sawCorners = false;
    for (const auto& f : rig.frames) sawCorners |= (f.mask & corners) == corners;
    CHECK(sawCorners);
    CHECK(rig.link->status.load().offRoute);
    // No more reports: after the 3 s timeout the centre motor swells and the sides stay still.
    rig.run(4.0, thumbToward(90.0));
    const std::size_t from = rig.frames.size();
    rig.run(6.0, thumbToward(90.0));
    CHECK(rig.onsets(3, from) == 0);
    CHECK(rig.onsets(5, from) == 0);
    bool centre = false;
    for (std::size_t i = from; i < rig.frames.size(); ++i) centre |= (rig.frames[i].mask & (1u << 4)) != 0;
    CHECK(centre);
    CHECK(rig.link->status.load().fix == FixState::Lost);
    CHECK(rig.link->status.load().sensation == Sensation::FixLost);
    // Walk to the end.
    rig.fix(r.points[1].pos);
    rig.run(12.0, thumbToward(90.0), &r.points[1].pos);
    rig.fix(r.points[2].pos);
    rig.run(20.0, thumbToward(90.0), &r.points[2].pos);
    const NavigationStatus st = rig.link->status.load();
    CHECK(st.finished);
    CHECK(st.arrivals == 2);
    CHECK(st.sensation == Sensation::None);
    CHECK(rig.frames.back().mask == 0);
    const auto names = test::decodeNames(rig.frames);
    REQUIRE(names.size() == 2);
    CHECK(names[1] == "ex");
}

TEST_CASE("scene: a panic stops every motor; resuming keeps the walk (the waypoint reached)", "[scene]")
{
    const Route r = testRoute();
    Rig rig(r);
    const LatLon near = destination(r.points[1].pos, 180.0, 5.0);
    rig.fix(near);
    rig.run(12.0, thumbToward(90.0), &near);
    REQUIRE(rig.link->status.load().waypoint == 3);
    rig.engine->panic();
    const MotorLevels off = rig.run(2.0, thumbToward(90.0), &near);
    for (int m = 0; m < kGridMotors; ++m) CHECK(off[static_cast<std::size_t>(m)] == 0);
    rig.engine->resume();
    const std::size_t from = rig.frames.size();
    rig.run(3.0, thumbToward(0.0), &near);   // "Exit" lies east: the clockwise side clicks again
    CHECK(rig.link->status.load().waypoint == 3);
    CHECK(rig.link->status.load().arrivals == 1);
    CHECK(rig.onsets(5, from) > 3);
}
