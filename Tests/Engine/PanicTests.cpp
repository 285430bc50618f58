// Panic (docs/STAGE.md): one call stops all sound within one block (a 1 ms fade, then zeros) and
// every motor at the next control update, through the tactile engine's all-off path; resume
// brings the scene back. Measured on a scene that sounds and drives every motor all the time.
// This TU is tests_engine's one RealtimeGuard implementation.
#define ARMADILLO_REALTIME_GUARD_IMPLEMENTATION
#include "Common/RealtimeGuard.h"
#include "Core/Pose.h"
#include "Engine/Engine.h"
#include "Engine/PanicGesture.h"
#include <catch2/catch.hpp>
#include <atomic>
#include <cmath>
#include <memory>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;
using namespace armadillo::test;

namespace {
constexpr double kFs = 48000.0;

/// A 440 Hz sine at 0.5 and every grid motor held at the rated level, each control update.
class DroneScene final : public Scene {
public:
    std::string_view name() const override { return "drone"; }
    void prepare(const SceneConfig&) override {}
    void control(const ControlInput&, SceneOutput& out) override
    {
        for (int m = 0; m < kGridMotors; ++m) out.motors.setSoftLevel(m, static_cast<float>(kRatedLevel));
        ++controls;
    }
    void reset() override { ++resets; }
    void renderAudio(float* l, float* r, int n) noexcept override
    {
        for (int i = 0; i < n; ++i) {
            const auto v = static_cast<float>(0.5 * std::sin(phase));
            phase += 2.0 * 3.14159265358979 * 440.0 / kFs;
            l[i] += v;
            r[i] += v;
        }
    }
    bool producesAudio() const override { return true; }
    double phase = 0.0;
    int controls = 0, resets = 0;
};

struct Rig {
    DroneScene* scene = nullptr;
    std::unique_ptr<Engine> engine;
    Rig()
    {
        auto s = std::make_unique<DroneScene>();
        scene = s.get();
        EngineConfig config;
        config.scene = "drone";
        engine = std::make_unique<Engine>(config, std::move(s));
    }
    /// One block of 64 samples after one control update at time t and elevation el.
    MotorLevels block(double t, std::vector<float>& l, std::vector<float>& r, double el = 0.0)
    {
        ArmState arm;
        arm.valid = true;
        arm.t = t;
        arm.features.pose = Pose {el, 0.0, 0.0};
        arm.q = poseToQuaternion(arm.features.pose);
        const MotorLevels levels = engine->control(arm, Transport {}, 64.0 / kFs);
        l.assign(64, 0.0f);
        r.assign(64, 0.0f);
        engine->renderAudio(l.data(), r.data(), 64);
        return levels;
    }
};

int sum(const MotorLevels& levels)
{
    int s = 0;
    for (auto v : levels) s += v;
    return s;
}
} // namespace

TEST_CASE("panic: silence within one block, every motor off at the next update, resume brings the scene back", "[engine][panic]")
{
    Rig rig;
    std::vector<float> l, r;
    double t = 0.0;
    MotorLevels levels {};
    for (int i = 0; i < 200; ++i, t += 64.0 / kFs) levels = rig.block(t, l, r);
    REQUIRE(sum(levels) > 0);                       // the scene drives the motors …
    float peak = 0.0f;
    for (float v : l) peak = std::max(peak, std::fabs(v));
    REQUIRE(peak > 0.3f);                           // … and sounds
    float lastSample = l.back();

    rig.engine->panic();
    rig.engine->panic();                            // idempotent: one panic
    CHECK(rig.engine->panicked());
    CHECK(rig.engine->panicCount() == 1u);
    const int controlsBefore = rig.scene->controls;
    levels = rig.block(t, l, r);
    t += 64.0 / kFs;
    CHECK(sum(levels) == 0);                        // the first update after the panic: all off
    CHECK(rig.scene->controls == controlsBefore);   // the scene no longer runs
    // The same block fades to zero within 1 ms (48 samples) without a click: no step larger
    // than the sine's own largest step (2π·440/48000·0.5 ≈ 0.029) plus the fade's (0.5/48).
    float maxStep = std::fabs(l[0] - lastSample);
    for (std::size_t i = 1; i < l.size(); ++i) maxStep = std::max(maxStep, std::fabs(l[i] - l[i - 1]));
    CHECK(maxStep < 0.029f + 0.0105f + 1e-3f);
    for (std::size_t i = static_cast<std::size_t>(Engine::kPanicFadeSeconds * kFs); i < l.size(); ++i) {
        REQUIRE(l[i] == 0.0f);
        REQUIRE(r[i] == 0.0f);
    }
    // Stays silent and still for 3 s, whatever the scene would do.
    for (int i = 0; i < 2250; ++i, t += 64.0 / kFs) {
        levels = rig.block(t, l, r);
        REQUIRE(sum(levels) == 0);
        for (float v : l) REQUIRE(v == 0.0f);
    }
    // Resume: the scene is reset once and runs again; sound fades back in over 20 ms.
    rig.engine->resume();
    CHECK_FALSE(rig.engine->panicked());
    const int resets = rig.scene->resets;
    levels = rig.block(t, l, r);
    t += 64.0 / kFs;
    CHECK(rig.scene->resets == resets + 1);
    CHECK(sum(levels) > 0);
    CHECK(std::fabs(l.back()) < 0.5f * 64.0f / (0.020f * 48000.0f) + 1e-3f);   // still fading in
    for (int i = 0; i < 20; ++i, t += 64.0 / kFs) levels = rig.block(t, l, r);
    peak = 0.0f;
    for (float v : l) peak = std::max(peak, std::fabs(v));
    CHECK(peak > 0.3f);
    CHECK(rig.engine->panicCount() == 1u);
}

TEST_CASE("panic and resume allocate, lock and throw nothing, from another thread too", "[engine][panic][realtime]")
{
    ARMADILLO_REQUIRE_GUARD();
    Rig rig;
    std::vector<float> l(64), r(64);
    ArmState arm;
    arm.valid = true;
    // The probe sees an allocation (so the zeros below mean something).
    {
        RealtimeGuard probe;
        auto* p = new int(1);
        delete p;
        REQUIRE(probe.allocations() == 1);
    }
    RealtimeGuard guard;
    for (int i = 0; i < 2000; ++i) {
        if (i % 300 == 100) rig.engine->panic();
        if (i % 300 == 200) rig.engine->resume();
        arm.t = i * 64.0 / kFs;
        arm.features.pose.elevationDeg = (i / 500) % 2 ? -80.0 : 10.0;
        (void) rig.engine->control(arm, Transport {}, 64.0 / kFs);
        rig.engine->renderAudio(l.data(), r.data(), 64);
    }
    CHECK(guard.allocations() == 0);
    CHECK(guard.deallocations() == 0);
    CHECK(guard.locks() == 0);
    CHECK(guard.throws() == 0);
    CHECK(rig.engine->panicCount() >= 6u);
}

TEST_CASE("PanicGesture: fires once per hang of 2 s at ≤ −75°; an invalid arm neither starts nor ends a hang", "[engine][panic]")
{
    PanicGesture g;
    ArmState arm;
    arm.valid = true;
    const auto at = [&](double t, double el) {
        arm.features.pose.elevationDeg = el;
        return g.update(t, arm);
    };
    // The threshold is inclusive (docs/STAGE.md: elevation ≤ −75°); −74.9° is not hanging.
    CHECK_FALSE(at(0.0, -74.9));
    CHECK_FALSE(g.hanging());
    CHECK_FALSE(at(0.0, -75.0));
    CHECK(g.hanging());
    CHECK_FALSE(at(1.999, -80.0));
    arm.valid = false;                 // a lost source: the hang goes on
    CHECK_FALSE(at(1.9995, 0.0));
    arm.valid = true;
    CHECK(at(2.0, -80.0));             // 2 s after it began: fires …
    int again = 0;
    for (int i = 1; i <= 1000; ++i) again += at(2.0 + i * 0.005, -89.0) ? 1 : 0;   // … once (5 s more hanging)
    CHECK(again == 0);
    CHECK_FALSE(at(8.0, -60.0));       // risen
    CHECK_FALSE(at(8.25, -80.0));
    CHECK_FALSE(at(10.0, -80.0));      // 1.75 s
    CHECK_FALSE(at(10.24, -80.0));     // 1.99 s
    CHECK(at(10.25, -80.0));           // 2 s: fires again
    g.reset();
    CHECK_FALSE(at(11.0, -80.0));      // reset: a new hang begins
    CHECK(at(13.0, -80.0));
    CHECK_FALSE(at(14.0, std::nan("")));   // an unknown elevation is not hanging
    CHECK_FALSE(g.hanging());
}
