// live::ControlLoop across a switch of source: the new source is another arm, so the scene starts
// afresh (Engine::restart()). The theremin takes its reference heading from its first frame; after
// a switch it must take it from the new source's first frame, exactly as an instance that played
// that source from the start (a DAW session reopened with host automation). Before 0.5.0 the old
// source's heading survived the switch.
#include "Core/Pose.h"
#include "Live/Step/ControlLoop.h"
#include "Live/Stage/SetList.h"
#include "LoopSlots.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::live;

namespace {

std::unique_ptr<EngineSlot> thereminSlot() { return test::loopSlot("theremin"); }

/// `steps` control steps of 240 samples from `source` (host automation at elevation 0° and
/// `azimuthDeg`); the RMS of the last half, rendered by the loop's engine or by `cues`.
double play(ControlLoop& loop, SourceKind source, double azimuthDeg, int steps, CuePlayer* cues = nullptr)
{
    std::vector<float> l(240), r(240);
    double sum = 0.0;
    for (int i = 0; i < steps; ++i) {
        ControlStep step;
        step.source = source;
        step.automation = Pose {0.0, azimuthDeg, 0.0};
        step.dt = 0.005;
        step.cues = cues;
        (void) loop.tick(step);
        if (cues != nullptr) cues->renderAudio(l.data(), r.data(), 240);
        else loop.render(l.data(), r.data(), 240);
        if (i >= steps / 2)
            for (float v : l) sum += double(v) * double(v);
    }
    return std::sqrt(sum / ((steps - steps / 2) * 240.0));
}

} // namespace

TEST_CASE("control loop: after a switch of source the theremin takes its reference heading from the new source", "[live][source-switch]")
{
    // The reference: host automation from the start, heading 120°, plays at full volume (0° off its reference).
    ControlLoop fresh;
    fresh.replace(thereminSlot());
    const double reference = play(fresh, SourceKind::HostAutomation, 120.0, 200);
    REQUIRE(reference > 0.05);

    SECTION("one scene")
    {
        ControlLoop loop;
        loop.replace(thereminSlot());
        // The probe: without a switch, the heading stays the first one's, and 120° away from 0°
        // is beyond the default 60° volume width: silence. The scene does keep a reference.
        const double kept = play(loop, SourceKind::HostAutomation, 0.0, 100);
        REQUIRE(kept == Approx(reference).epsilon(0.02));
        REQUIRE(play(loop, SourceKind::HostAutomation, 120.0, 200) < 1e-4);
        // Another source (an OSC sender that sends nothing yet), then automation again at 120°.
        (void) play(loop, SourceKind::Osc, 120.0, 20);
        const double after = play(loop, SourceKind::HostAutomation, 120.0, 200);
        INFO("fresh " << reference << ", after the switch " << after);
        CHECK(after == Approx(reference).epsilon(0.02));
    }
    SECTION("a set list's cue")
    {
        const SetList list = parseSetList(R"({"armadillo_setlist": 1, "cues": [{"name": "T", "scene": "theremin"}]})", "t.json");
        SceneConfig base;
        base.sampleRate = 48000.0;
        base.controlRateHz = 200.0;
        CuePlayer cues(list, base);
        ControlLoop loop;
        loop.replace(thereminSlot());   // the loop's own engine only tracks the arm while cues play
        const double cueFresh = play(loop, SourceKind::HostAutomation, 0.0, 200, &cues);
        REQUIRE(cueFresh > 0.05);
        REQUIRE(play(loop, SourceKind::HostAutomation, 120.0, 200, &cues) < 1e-4);
        (void) play(loop, SourceKind::Osc, 120.0, 20, &cues);
        const double after = play(loop, SourceKind::HostAutomation, 120.0, 200, &cues);
        INFO("cue fresh " << cueFresh << ", after the switch " << after);
        CHECK(after == Approx(cueFresh).epsilon(0.02));
    }
}
