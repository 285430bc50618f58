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

TEST_CASE("step runner: a guided procedure's stimulus has the motors instead of the scene, and a panic silences it too",
          "[live][stage][panic]")
{
    ControlLoop loop;
    loop.replace(test::loopSlot("monitor"));   // a scene that leaves the grid alone
    Stage stage;
    StepRunner runner(loop, &stage);
    access::TactilePlayer player(tactile::TactileConfig {}, 0.0);
    // Motor m5 at level 10 for 2 s.
    player.play({access::TactileSegment {0.0, 2.0, static_cast<std::uint16_t>(1u << 4), 10.0f}});
    auto levelsOfStep = [&] {
        runner.beginStage();
        ControlStep step;
        step.automation = Pose {20.0, 0.0, 0.0};
        step.dt = 0.005;
        return runner.step(step).levels;
    };
    int quiet = 0;
    for (int i = 0; i < 40; ++i) quiet += levelsOfStep()[4];
    CHECK(quiet == 0);   // no stimulus set: the scene's levels
    runner.setStimulus(&player);
    CHECK(runner.hasStimulus());
    int strongest = 0;
    for (int i = 0; i < 40; ++i) strongest = std::max(strongest, static_cast<int>(levelsOfStep()[4]));
    CHECK(strongest >= 8);   // the stimulus's motor, through its own engine and safety stage

    stage.apply({StageCommand::Kind::Panic, 0});
    for (int i = 0; i < 40; ++i) {
        const MotorLevels levels = levelsOfStep();
        for (int m = 0; m < kMaxMotors; ++m) REQUIRE(levels[static_cast<std::size_t>(m)] == 0);
    }
    runner.setStimulus(nullptr);
    CHECK_FALSE(runner.hasStimulus());
}
