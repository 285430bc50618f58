// The audio paths allocate nothing and take no locks (STYLE.md convention 5), proved with the
// counting guard while the scenes are driven through busy scripts (strikes, damping, sweeps,
// parameter changes from the "UI" between blocks).
#define ARMADILLO_REALTIME_GUARD_IMPLEMENTATION
#include "Common/RealtimeGuard.h"
#include "Instruments/Dsp.h"
#include "Instruments/Scenes.h"
#include "SceneHarness.h"
#include <catch2/catch.hpp>
#include <csignal>
#include <memory>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <thread>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::instruments;
using namespace armadillo::test;

namespace {
#ifdef ARMADILLO_GUARD_UNDER_SANITIZER
// Sanitizer builds own malloc/operator new: the guard is left out and these tests stop early.
#define REQUIRE_GUARD() do { WARN("sanitizer build: no real-time guard"); SUCCEED("skipped under the sanitizer"); return; } while (false)
#else
#define REQUIRE_GUARD() REQUIRE(RealtimeGuard::installed())
#endif
struct GuardTotals {
    std::uint64_t allocations = 0, deallocations = 0, locks = 0, calls = 0;
};

/// Wraps every renderAudio call of the harness in its own guard and adds up what they saw.
void guardRendering(SceneHarness& h, GuardTotals& totals)
{
    h.renderWrapper = [&totals](const std::function<void()>& render) {
        RealtimeGuard guard;
        render();
        totals.allocations += guard.allocations();
        totals.deallocations += guard.deallocations();
        totals.locks += guard.locks();
        ++totals.calls;
    };
}
} // namespace

TEST_CASE("the realtime guard sees allocations and locks (so it can fail)", "[realtime]")
{
    REQUIRE_GUARD();
    {
        RealtimeGuard guard;
        auto p = std::make_unique<int>(3);
        CHECK(*p == 3);
        p.reset();
        CHECK(guard.allocations() == 1);
        CHECK(guard.deallocations() == 1);
        CHECK_FALSE(guard.clean());
    }
    {
        std::mutex m;
        RealtimeGuard guard;
        { const std::lock_guard<std::mutex> lock(m); }
        CHECK(guard.locks() >= 1);
        CHECK(guard.allocations() == 0);
    }
    {
        RealtimeGuard guard;
        volatile double x = 1.0;
        for (int i = 0; i < 100; ++i) x = x * 1.0001;
        CHECK(guard.clean());
    }
}

namespace {
volatile std::sig_atomic_t trapped = 0;
extern "C" void onTrap(int) { trapped = 1; }
} // namespace

TEST_CASE("a Trap-mode guard stops at the first allocation (for the debugger), a counting one does not", "[realtime]")
{
    REQUIRE_GUARD();
    const auto previous = std::signal(SIGTRAP, onTrap);
    trapped = 0;
    {
        RealtimeGuard guard;   // counting only
        auto p = std::make_unique<int>(1);
        CHECK(*p == 1);
    }
    CHECK(trapped == 0);
    {
        RealtimeGuard guard(RealtimeGuard::Mode::Trap);
        auto p = std::make_unique<int>(2);
        CHECK(trapped == 1);
        CHECK(*p == 2);
    }
    std::signal(SIGTRAP, previous);
}

TEST_CASE("theremin renderAudio allocates nothing and takes no locks", "[realtime][theremin]")
{
    REQUIRE_GUARD();
    SceneHarness h(makeThereminScene());
    GuardTotals totals;
    guardRendering(h, totals);
    for (int block : {64, 240, 1, 513}) {
        h.blockSize = block;
        h.move({-50.0, 0.0, 0.0}, {50.0, 70.0, 0.0}, 0.5);
        h.set("theremin.glide", 100.0f);
        h.set("theremin.snap", 60.0f);
        h.move({50.0, 70.0, 0.0}, {-50.0, -70.0, 0.0}, 0.5);
        h.set("theremin.glide", 0.0f);
        h.set("theremin.scale", 3.0f);
    }
    REQUIRE(totals.calls > 100);
    REQUIRE(rms(h.audio.left, 0, h.audio.left.size()) > 0.05);   // it did make sound
    CHECK(totals.allocations == 0);
    CHECK(totals.deallocations == 0);
    CHECK(totals.locks == 0);
}

TEST_CASE("cymbal renderAudio allocates nothing and takes no locks through strikes and damping", "[realtime][cymbal]")
{
    REQUIRE_GUARD();
    SceneHarness h(makeCymbalScene());
    GuardTotals totals;
    guardRendering(h, totals);
    for (int block : {64, 240, 1, 513}) {
        h.blockSize = block;
        h.move(h.lastPose, {30.0, 0.0, 0.0}, 0.3);
        h.move({30.0, 0.0, 0.0}, {-20.0, 0.0, 0.0}, 0.1);        // strike
        h.move({-20.0, 0.0, 0.0}, {-20.0, 60.0, 0.0}, 0.3);      // brush: tail modulation
        h.move({-20.0, 60.0, 0.0}, {8.0, 60.0, 0.0}, 0.4);
        h.move({8.0, 60.0, 0.0}, {-5.0, 60.0, 0.0}, 0.8);        // gentle touch: damp
        h.set("cymbal.level", 0.5f);
        h.hold({-5.0, 60.0, 0.0}, 0.3);
    }
    REQUIRE(h.events.count("strike") == 4);
    REQUIRE(h.events.count("damp") == 4);
    CHECK(totals.allocations == 0);
    CHECK(totals.deallocations == 0);
    CHECK(totals.locks == 0);
}

TEST_CASE("panel and sound-design renderAudio allocate nothing and take no locks", "[realtime][panel][sound-design]")
{
    REQUIRE_GUARD();
    for (auto make : {&makePanelScene, &makeSoundDesignScene}) {
        SceneHarness h(make());
        GuardTotals totals;
        guardRendering(h, totals);
        for (int block : {64, 1, 513}) {
            h.blockSize = block;
            h.move(h.lastPose, {40.0, 30.0, 0.0}, 0.3);
            h.move({40.0, 30.0, 0.0}, {40.0, 30.0, 60.0}, 0.1);   // quick roll: select
            h.move({40.0, 30.0, 60.0}, {-40.0, -30.0, 0.0}, 0.5);
            h.move({-40.0, -30.0, 0.0}, {-40.0, -30.0, 60.0}, 0.1);
        }
        REQUIRE(h.events.count("select") >= 3);
        REQUIRE(rms(h.audio.left, 0, h.audio.left.size()) > 0.001);
        INFO(h.scene().name());
        CHECK(totals.allocations == 0);
        CHECK(totals.deallocations == 0);
        CHECK(totals.locks == 0);
    }
}

TEST_CASE("with a real control thread and a real audio thread the audio side stays clean", "[realtime][cymbal][theremin]")
{
    // The control thread plays a scripted performance (strikes, brushing, damping, parameter
    // changes) while this thread renders 64-sample blocks; they share only the scene. Iteration
    // counts, not sleeps: the interleaving varies from run to run, the invariants must not.
    REQUIRE_GUARD();
    for (auto make : {&makeCymbalScene, &makeThereminScene}) {
        auto scene = make();
        SceneConfig config;
        scene->prepare(config);
        std::vector<ArmState> script;
        Eigen::Quaterniond previous = poseToQuaternion({});
        for (int i = 0; i < 2000; ++i) {
            const double t = i * 0.005, phase = std::fmod(t, 1.0);
            const double el = phase < 0.5 ? -30.0 + 120.0 * phase : phase < 0.6 ? 30.0 - 600.0 * (phase - 0.5) : -30.0;
            const ArmState s = armStateFromPose({el, 30.0 * std::sin(t), 0.0}, &previous, 0.005, t);
            previous = s.q;
            script.push_back(s);
        }
        std::atomic<bool> done {false};
        std::thread control([&] {
            RecordingCanvas canvas;
            RecordingEvents events;
            SceneOutput out {canvas, events};
            const auto specs = scene->parameters();
            for (std::size_t i = 0; i < script.size(); ++i) {
                ControlInput in;
                in.arm = script[i];
                scene->control(in, out);
                scene->setParameter(static_cast<int>(i % specs.size()),
                                    specs[i % specs.size()].defaultValue);   // "UI" writes from this thread
            }
            done.store(true);
        });
        std::vector<float> l(64), r(64);
        GuardTotals totals;
        bool finite = true;
        double energy = 0.0;
        // Render while the control thread plays, then 100 blocks more: how much overlapped
        // depends on the scheduler, what is rendered after it finished does not.
        int after = 0;
        for (int b = 0; b < 20000 || after < 100; ++b) {
            if (done.load()) ++after;
            std::fill(l.begin(), l.end(), 0.0f);
            std::fill(r.begin(), r.end(), 0.0f);
            RealtimeGuard guard;
            scene->renderAudio(l.data(), r.data(), 64);
            totals.allocations += guard.allocations();
            totals.deallocations += guard.deallocations();
            totals.locks += guard.locks();
            for (int i = 0; i < 64; ++i) {
                finite = finite && std::isfinite(l[static_cast<std::size_t>(i)]) && std::isfinite(r[static_cast<std::size_t>(i)]);
                energy += static_cast<double>(l[static_cast<std::size_t>(i)]) * static_cast<double>(l[static_cast<std::size_t>(i)]);
            }
        }
        control.join();
        INFO(scene->name());
        CHECK(finite);
        CHECK(energy > 0.0);
        CHECK(totals.allocations == 0);
        CHECK(totals.deallocations == 0);
        CHECK(totals.locks == 0);
    }
}

TEST_CASE("property: any parameter values and any arm input give finite, bounded audio", "[realtime][property]")
{
    // Random parameter settings (including the range ends) and random, partly broken arm
    // states: the sound stays finite and within ±1 for every scene that makes sound.
    dsp::Random rng(2024);
    for (auto make : {&makeThereminScene, &makeCymbalScene, &makePanelScene, &makeSoundDesignScene}) {
        auto scene = make();
        SceneConfig config;
        scene->prepare(config);
        const auto specs = scene->parameters();
        RecordingCanvas canvas;
        RecordingEvents events;
        SceneOutput out {canvas, events};
        std::vector<float> l(240), r(240);
        float peak = 0.0f;
        bool finite = true;
        Eigen::Quaterniond previous = poseToQuaternion({});
        for (int step = 0; step < 3000; ++step) {
            if (step % 50 == 0)
                for (std::size_t p = 0; p < specs.size(); ++p) {
                    const double u = rng.uniform();
                    const float v = u < 0.1 ? specs[p].min : u < 0.2 ? specs[p].max
                                                                     : static_cast<float>(rng.uniform(specs[p].min, specs[p].max));
                    scene->setParameter(static_cast<int>(p), v);
                }
            Pose pose {rng.uniform(-90.0, 90.0), rng.uniform(0.0, 360.0), rng.uniform(-180.0, 180.0)};
            ControlInput in;
            in.arm = armStateFromPose(pose, &previous, 0.005, step * 0.005);
            previous = in.arm.q;
            const double u = rng.uniform();
            if (u < 0.03) in.arm.features.axis.setConstant(kNaN);   // a broken feature vector
            else if (u < 0.06) in.arm.gyro.setConstant(kNaN);
            else if (u < 0.08) in.arm.valid = false;
            else if (u < 0.09) in.dt = 0.0;
            scene->setParameter(-1, 1.0f);                            // out of range index: ignored
            scene->setParameter(0, std::numeric_limits<float>::quiet_NaN());
            scene->control(in, out);
            std::fill(l.begin(), l.end(), 0.0f);
            std::fill(r.begin(), r.end(), 0.0f);
            scene->renderAudio(l.data(), r.data(), 240);
            for (std::size_t i = 0; i < l.size(); ++i) {
                finite = finite && std::isfinite(l[i]) && std::isfinite(r[i]);
                peak = std::max({peak, std::fabs(l[i]), std::fabs(r[i])});
            }
        }
        INFO(scene->name() << " peak " << peak);
        CHECK(finite);
        CHECK(peak <= 1.0f);
    }
}
