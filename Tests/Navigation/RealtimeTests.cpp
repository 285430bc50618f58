// The navigation scene's control step allocates, frees, locks and throws nothing in any of its
// states (compass, arrival and name, off route, fix lost, end), the heading learner and the
// guidance included (STYLE.md convention 5).
#define ARMADILLO_REALTIME_GUARD_IMPLEMENTATION
#include "Common/RealtimeGuard.h"
#include "Core/Pose.h"
#include "Navigation/NavigationScene.h"
#include <catch2/catch.hpp>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::navigation;

namespace {
class NullCanvas final : public MotorCanvas {
public:
    void setLevel(int, float) override { ++calls; }
    void clearLevels() override { ++calls; }
    void trigger(const PatternRequest&) override { ++calls; }
    void stopVoice(int) override { ++calls; }
    int calls = 0;
};
class NullEvents final : public EventSink {
public:
    void emit(const char*, float) override {}
};
} // namespace

TEST_CASE("navigation control step is real-time in every state", "[realtime]")
{
#ifdef ARMADILLO_GUARD_UNDER_SANITIZER
    SUCCEED("the guard is off under a sanitizer");
    return;
#endif
    REQUIRE(test::RealtimeGuard::installed());
    {   // the probe: the guard sees an allocation on this thread
        test::RealtimeGuard probe;
        auto* p = new int(3);
        delete p;
        REQUIRE(probe.allocations() > 0);
    }
    Route r;
    r.source = "rt";
    r.points.push_back({{48.0, 11.0}, "Start", 0});
    r.points.push_back({destination({48.0, 11.0}, 0.0, 100.0), "Entrance", 0});
    r.points.push_back({destination(r.points[1].pos, 90.0, 100.0), "Exit", 0});
    auto link = std::make_shared<NavigationLink>();
    link->logEnabled = true;
    auto scene = makeNavigationScene(r, link);
    SceneConfig config;
    scene->prepare(config);
    NullCanvas canvas;
    NullEvents events;
    SceneOutput out {canvas, events, nullptr};
    ControlInput in;
    in.arm.valid = true;
    in.dt = 0.01;
    NavigationLogRecord drained;
    const LatLon positions[] = {r.points[0].pos, destination(destination(r.points[0].pos, 0.0, 50.0), 90.0, 30.0),
                                destination(r.points[1].pos, 180.0, 3.0), destination(r.points[2].pos, 0.0, 1.0)};
    test::RealtimeGuard guard;
    double t = 0.0;
    for (const LatLon& p : positions) {
        for (int i = 0; i < 2500; ++i, t += 0.01) {   // 25 s each, a fix each second except a 5 s gap
            if (i % 100 == 0 && (i < 1000 || i > 1500)) {
                PositionFix f;
                f.pos = p;
                f.quality = FixQuality::Fix2D;
                f.speedMps = 1.2;
                f.courseDeg = 10.0;
                link->position.store(f);
            }
            Pose pose;
            pose.azimuthDeg = std::fmod(37.0 * t, 360.0);
            pose.elevationDeg = -10.0 + 12.0 * std::cos(5.6 * t);
            in.arm.q = poseToQuaternion(pose);   // Eigen fixed-size: no allocation
            scene->control(in, out);
            while (link->log.pop(drained)) {}
        }
    }
    CHECK(guard.allocations() == 0);
    CHECK(guard.deallocations() == 0);
    CHECK(guard.locks() == 0);
    CHECK(guard.throws() == 0);
    CHECK(canvas.calls > 100);
    CHECK(link->status.load().finished);
}
