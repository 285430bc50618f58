// The panic gesture in the one control step (live::ControlLoop, docs/STAGE.md "Panic"): the right
// forearm hanging straight down (elevation ≤ −75°) for 2 s panics the engine and every cue of a
// set list, once per hang, for `armadillo play --panic-gesture` and the app's setting alike.
// Before 0.5.0 the engine ran the gesture itself, so a set list in `play` never heard it (its
// cues' engines were not told) and the app ran a copy of its own.
#include "Core/Pose.h"
#include "Live/Step/ControlLoop.h"
#include "Live/Stage/SetList.h"
#include "LoopSlots.h"
#include <catch2/catch.hpp>
#include <memory>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::live;

namespace {

constexpr double kDt = 0.005;   // the 200 Hz control step

/// Steps the loop with host automation at `elevationDeg` for `seconds`; how often the gesture fired.
int hold(ControlLoop& loop, double seconds, double elevationDeg, bool gesture = true, CuePlayer* cues = nullptr)
{
    int fired = 0;
    for (int i = 0; i < static_cast<int>(seconds / kDt + 0.5); ++i) {
        ControlStep step;
        step.automation = Pose {elevationDeg, 0.0, 0.0};
        step.dt = kDt;
        step.panicGesture = gesture;
        step.cues = cues;
        fired += loop.tick(step).gesturePanic ? 1 : 0;
    }
    return fired;
}

} // namespace

TEST_CASE("control loop: the panic gesture panics once per 2 s hang; off, nothing", "[live][panic]")
{
    {   // off: hanging for 10 s does nothing
        ControlLoop loop;
        loop.replace(test::loopSlot("theremin"));
        CHECK(hold(loop, 10.0, -85.0, false) == 0);
        CHECK_FALSE(loop.active()->engine->panicked());
    }
    ControlLoop loop;
    loop.replace(test::loopSlot("theremin"));
    engine::Engine& engine = *loop.active()->engine;
    CHECK(hold(loop, 1.0, 0.0) == 0);
    CHECK(hold(loop, 1.9, -80.0) == 0);   // not long enough
    CHECK(hold(loop, 0.2, -60.0) == 0);   // up again: the count starts over
    CHECK(hold(loop, 1.9, -80.0) == 0);
    CHECK_FALSE(engine.panicked());
    CHECK(hold(loop, 0.2, -80.0) == 1);   // 2.1 s hanging: panic
    CHECK(engine.panicked());
    CHECK(engine.panicCount() == 1u);
    engine.resume();
    CHECK(hold(loop, 3.0, -80.0) == 0);   // resumed while still hanging: no second panic
    CHECK_FALSE(engine.panicked());
    CHECK(hold(loop, 0.5, 0.0) == 0);
    CHECK(hold(loop, 2.1, -80.0) == 1);   // a new hang: a new panic
    CHECK(engine.panicked());
    CHECK(engine.panicCount() == 2u);
    // Turned off while hanging, then on again: the hang starts over.
    engine.resume();
    CHECK(hold(loop, 0.5, 0.0) == 0);
    CHECK(hold(loop, 1.5, -80.0) == 0);
    CHECK(hold(loop, 1.0, -80.0, false) == 0);
    CHECK(hold(loop, 1.9, -80.0) == 0);
    CHECK(hold(loop, 0.2, -80.0) == 1);
}

TEST_CASE("control loop: the panic gesture with a set list panics every cue, so a cue change stays silent", "[live][panic][setlist]")
{
    SetList list;
    list.source = "show.json";
    for (const char* scene : {"theremin", "panel", "sound-design"}) {
        Cue c;
        c.name = scene;
        c.scene = scene;
        list.cues.push_back(c);
    }
    SceneConfig base;
    base.sampleRate = 48000.0;
    base.controlRateHz = 200.0;
    CuePlayer cues(list, base);
    ControlLoop loop;
    loop.replace(test::loopSlot("monitor"));
    CHECK(hold(loop, 1.0, 0.0, true, &cues) == 0);
    for (int c = 0; c < cues.cueCount(); ++c) CHECK_FALSE(cues.engine(c).panicked());
    CHECK(hold(loop, 2.1, -80.0, true, &cues) == 1);
    for (int c = 0; c < cues.cueCount(); ++c) CHECK(cues.engine(c).panicked());
    cues.next();
    const ControlResult after = [&] {
        ControlStep step;
        step.dt = kDt;
        step.cues = &cues;
        return loop.tick(step);
    }();
    CHECK(cues.current() == 1);
    CHECK(after.levels == MotorLevels {});   // the next cue starts in panic: every motor off
}
