// The one control step (live::StepRunner, issue 45): every clock runs it, so a stage command acts
// the same way for `play` (one step per sensor packet) and the app (its block grid): at the next
// beginStage(), on the engine and on every cue; and a gesture panic is held by the stage until a
// resume, as a command's is.
#include "Core/Pose.h"
#include "Core/StageCommand.h"
#include "Live/Stage/SetList.h"
#include "Live/Step/StepRunner.h"
#include "LoopSlots.h"
#include <catch2/catch.hpp>
#include <memory>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::live;

namespace {

/// beginStage() and one 5 ms step with host automation at `elevationDeg`.
StepRunner::StageChange stepOnce(StepRunner& runner, double elevationDeg = 20.0, bool gesture = false)
{
    const StepRunner::StageChange change = runner.beginStage();
    ControlStep step;
    step.automation = Pose {elevationDeg, 0.0, 0.0};
    step.dt = 0.005;
    step.panicGesture = gesture;
    runner.step(step);
    return change;
}

} // namespace

TEST_CASE("step runner: a stage command acts at the next step, on the engine, and resume brings it back", "[live][stage]")
{
    ControlLoop loop;
    loop.replace(test::loopSlot("theremin"));
    Stage stage;
    StepRunner runner(loop, &stage);
    engine::Engine& engine = *loop.active()->engine;
    CHECK(stepOnce(runner) == StepRunner::StageChange::None);
    CHECK_FALSE(engine.panicked());

    stage.apply({StageCommand::Kind::Panic, 0});   // from any thread: only the stage's atomics
    CHECK_FALSE(engine.panicked());                 // nothing reached the engine yet
    CHECK(stepOnce(runner) == StepRunner::StageChange::PanicStarted);
    CHECK(engine.panicked());
    CHECK(runner.panicked());
    CHECK(stepOnce(runner) == StepRunner::StageChange::None);   // said once
    CHECK(stage.panics() == 1u);

    stage.apply({StageCommand::Kind::Resume, 0});
    CHECK(stepOnce(runner) == StepRunner::StageChange::Resumed);
    CHECK_FALSE(engine.panicked());
    CHECK_FALSE(runner.panicked());
}

TEST_CASE("step runner: the stage's panic gesture is held by the stage until resume", "[live][stage][panic]")
{
    ControlLoop loop;
    loop.replace(test::loopSlot("theremin"));
    Stage stage;
    stage.setPanicGesture(true);   // the app's setting; `play --panic-gesture` sets the same
    StepRunner runner(loop, &stage);
    for (int i = 0; i < 200; ++i) stepOnce(runner, 0.0);
    CHECK_FALSE(stage.panicked());
    for (int i = 0; i < 450; ++i) stepOnce(runner, -85.0);   // 2.25 s hanging straight down
    CHECK(stage.panicked());
    CHECK(stage.panics() == 1u);
    CHECK(loop.active()->engine->panicked());
    for (int i = 0; i < 100; ++i) stepOnce(runner, 0.0);    // the arm up again: still in panic
    CHECK(stage.panicked());
    CHECK(loop.active()->engine->panicked());
    stage.apply({StageCommand::Kind::Resume, 0});
    stepOnce(runner, 0.0);
    CHECK_FALSE(loop.active()->engine->panicked());
}

TEST_CASE("step runner: cue commands reach a set list's player at the next step; a panic reaches every cue", "[live][stage][setlist]")
{
    SetList list;
    for (const char* scene : {"theremin", "cymbal", "panel"}) {
        Cue c;
        c.name = scene;
        c.scene = scene;
        list.cues.push_back(c);
    }
    SceneConfig base;
    base.sampleRate = 48000.0;
    base.controlRateHz = 200.0;
    ControlLoop loop;
    loop.replace(test::loopSlot("monitor"));
    Stage stage;
    stage.replace(std::make_unique<CuePlayer>(list, base, kGridMotors, false));
    StepRunner runner(loop, &stage);
    stepOnce(runner);
    REQUIRE(runner.cues() != nullptr);
    CHECK(runner.cues()->requested() == 0);
    stage.apply({StageCommand::Kind::CueNext, 0});
    CHECK(runner.cues()->requested() == 0);   // not before the next step
    stepOnce(runner);
    CHECK(runner.cues()->requested() == 1);
    stage.apply({StageCommand::Kind::CueGoto, 2});
    stepOnce(runner);
    CHECK(runner.cues()->requested() == 2);
    stage.apply({StageCommand::Kind::CuePrev, 0});
    stepOnce(runner);
    CHECK(runner.cues()->requested() == 1);
    stage.apply({StageCommand::Kind::Panic, 0});
    stepOnce(runner);
    for (int c = 0; c < runner.cues()->cueCount(); ++c) CHECK(runner.cues()->engine(c).panicked());
    CHECK(runner.running() == &runner.cues()->engine(runner.cues()->current()));
}
