// live::ControlLoop with a left arm (ControlStep::leftArm, issue 28: the plugin's left arm from
// an OSC sender): an engine built with twoArms hears both arms through the loop, one built
// without ignores the left arm, and the step stays real-time (RealtimeLoopTests.cpp is this
// executable's guard TU and proves first that the guard sees what it counts).
#include "Common/RealtimeGuard.h"
#include "Core/Pose.h"
#include "Fusion/ArmTracker.h"
#include "Live/Step/ControlLoop.h"
#include "Live/Stage/SetList.h"
#include "LoopSlots.h"
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::fusion;
using namespace armadillo::live;
using namespace armadillo::test;

namespace {

std::unique_ptr<EngineSlot> duoSlot(bool twoArms) { return loopSlot("theremin-duo", twoArms); }

/// `steps` control steps of the right arm automated at 20° elevation with the left arm at
/// `leftElevation` (NaN: no left arm given), 240 samples each; the RMS of the last half.
double duoRms(ControlLoop& loop, ArmTracker& left, double leftElevation, int steps, std::uint64_t* violations = nullptr)
{
    std::vector<float> l(240), r(240);
    double sum = 0.0;
    int counted = 0;
    static double t = 0.0;
    for (int i = 0; i < steps; ++i) {
        t += 0.005;
        ControlStep step;
        step.source = SourceKind::HostAutomation;
        step.automation = Pose {20.0, 0.0, 0.0};
        step.dt = 0.005;
        const ArmState leftArm = std::isnan(leftElevation) ? ArmState {} : left.updateOrientation(t, poseToQuaternion(Pose {leftElevation, 0.0, 0.0}));
        step.leftArm = std::isnan(leftElevation) ? nullptr : &leftArm;
        {
            RealtimeGuard guard;   // the control step and its audio only (the left arm was fused above, as the front end does)
            (void) loop.tick(step);
            loop.render(l.data(), r.data(), 240);
            if (violations != nullptr) *violations += guard.allocations() + guard.deallocations() + guard.locks() + guard.throws();
        }
        if (i >= steps / 2) {
            for (float v : l) sum += double(v) * double(v);
            counted += 240;
        }
    }
    return std::sqrt(sum / counted);
}

} // namespace

TEST_CASE("control loop: a two-arm engine hears the left arm given with the step; a one-arm engine does not", "[live][two-arms]")
{
    ArmTracker left;
    SECTION("twoArms")
    {
        ControlLoop loop;
        loop.replace(duoSlot(true));
        const double raised = duoRms(loop, left, 30.0, 200);
        const double hanging = duoRms(loop, left, -85.0, 200);   // Instruments/ThereminDuoScene.cpp: below −60° the note stops
        const double again = duoRms(loop, left, 30.0, 200);
        INFO("raised " << raised << ", hanging " << hanging << ", again " << again);
        CHECK(raised > 0.02);
        CHECK(hanging < 1e-4);
        CHECK(again > 0.02);
    }
    SECTION("one arm: the left arm given is not heard")
    {
        ControlLoop loop;
        loop.replace(duoSlot(false));
        CHECK(duoRms(loop, left, -85.0, 200) > 0.02);
    }
}

TEST_CASE("control loop: the step with a left arm allocates, frees, locks and throws nothing", "[realtime][two-arms]")
{
    ARMADILLO_REQUIRE_GUARD();
    {
        RealtimeGuard probe;   // the probe: an allocation on this thread is seen
        auto p = std::make_unique<std::vector<double>>(16);
        REQUIRE(probe.allocations() >= 2);
    }
    ArmTracker left;
    ControlLoop loop;
    loop.replace(duoSlot(true));
    (void) duoRms(loop, left, 30.0, 20);   // first steps outside the count (as every real-time test warms up)
    std::uint64_t violations = 0;
    for (double elevation : {30.0, -85.0, 10.0, -70.0}) (void) duoRms(loop, left, elevation, 250, &violations);
    CHECK(violations == 0);
}

TEST_CASE("control loop: a two-arm set list's cue hears the left arm given with the step", "[live][two-arms][setlist]")
{
    const SetList list = parseSetList(R"({"armadillo_setlist": 1, "cues": [{"name": "Duo", "scene": "theremin-duo"}]})", "duo.json");
    SceneConfig base;
    base.sampleRate = 48000.0;
    base.controlRateHz = 200.0;
    CuePlayer cues(list, base, kGridMotors, true);
    ControlLoop loop;
    loop.replace(duoSlot(false));   // the loop's own engine only tracks the arm while cues play
    ArmTracker left;
    double t = 0.0;
    auto rms = [&](double leftElevation) {
        std::vector<float> l(240), r(240);
        double sum = 0.0;
        for (int i = 0; i < 200; ++i) {
            t += 0.005;
            ControlStep step;
            step.source = SourceKind::HostAutomation;
            step.automation = Pose {20.0, 0.0, 0.0};
            step.dt = 0.005;
            step.cues = &cues;
            const ArmState leftArm = left.updateOrientation(t, poseToQuaternion(Pose {leftElevation, 0.0, 0.0}));
            step.leftArm = &leftArm;
            (void) loop.tick(step);
            std::fill(l.begin(), l.end(), 0.0f);
            std::fill(r.begin(), r.end(), 0.0f);
            cues.renderAudio(l.data(), r.data(), 240);
            if (i >= 100)
                for (float v : l) sum += double(v) * double(v);
        }
        return std::sqrt(sum / (100.0 * 240.0));
    };
    const double raised = rms(30.0), hanging = rms(-85.0);
    INFO("raised " << raised << ", hanging " << hanging);
    CHECK(raised > 0.02);
    CHECK(hanging < 1e-4);   // the duo's articulation: the left arm hanging stops the note
}
