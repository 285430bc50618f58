#pragma once
// The one place the live control step runs (issue 45): the stage's commands applied (a set list's
// cue requests, panic, resume) and then live::ControlLoop::tick — engine hand-over, source
// choice, bounded fusion of both arms, the scene's parameters, Engine::control or a set list's
// cues, the panic gesture; and a stimulus that has the motors instead of the scene (a guided
// procedure: the sensitivity test, the adaptive training), silenced by a panic as the scene is.
// The instrument's core (Live/Session/Instrument.h) holds the one runner, and every clock drives
// it through that core: `play`, `read` and `navigate` once per sensor packet (LiveSession), the
// app and the plugin at their audio blocks' 200 Hz grid or the idle clock (BlockControl). The
// step itself, and how panic and resume reach the engine and the cues, is here once; what
// follows it for every clock (the frame, the mapping's view, its panic) is the core's.
//
// Threads: one control thread at a time (the source's thread, or the control-token holder):
// beginStage() and step() are real-time (no allocation, lock, I/O or throw). The stage's commands
// come from any thread through live::Stage (atomics).
#include "Access/TactilePlayer.h"
#include "Live/Step/ControlLoop.h"
#include "Live/Stage/Stage.h"
#include <atomic>

namespace armadillo::live {

class StepRunner {
public:
    /// `stage` may be null (no stage commands: a bare loop in a test).
    StepRunner(ControlLoop& loop, Stage* stage) noexcept : loop_(loop), stage_(stage) {}
    /// Control side, with nothing running: the set list's player is taken again at the next
    /// beginStage() (the stage may have replaced it while the audio was stopped).
    void forgetCues() noexcept { cues_ = nullptr; }
    StepRunner(const StepRunner&) = delete;
    StepRunner& operator=(const StepRunner&) = delete;

    /// What beginStage() changed.
    enum class StageChange { None, PanicStarted, Resumed };
    /// The start of a block or step: the stage's offered set list taken and its cue requests
    /// applied; while in panic the engine and the cues are panicked (idempotent: it reaches an
    /// engine or a cue that took over since); the moment panic starts or ends is returned, so
    /// the caller silences or restarts what it sends beside the engine (the mapping's notes).
    StageChange beginStage() noexcept;

    /// One control step. `step.cues` and `step.panic` are the stage's (set here); the panic
    /// gesture is on when the step or the stage asks for it. A gesture panic panics the stage
    /// too, so it holds until resume as a command's does.
    ControlResult step(ControlStep step) noexcept;

    /// A guided procedure's player (Procedures/TouchTest.h, AdaptiveTraining.h): while set, each
    /// step's levels come from it (its own TactileEngine and SafetyStage) instead of the scene's,
    /// on the steps' clock, with the arm's roll rate for its gestures; never during a panic (the
    /// motors stay off until resume). nullptr gives the motors back to the scene. Any thread; the
    /// player must outlive its use (until the next step after it is unset).
    void setStimulus(access::TactilePlayer* player) noexcept { stimulus_.store(player, std::memory_order_release); }
    bool hasStimulus() const noexcept { return stimulus_.load(std::memory_order_acquire) != nullptr; }

    /// The set list's player this step (null: none), as the last beginStage() took it.
    CuePlayer* cues() const noexcept { return cues_; }
    /// The stage's panic as last applied.
    bool panicked() const noexcept { return panicApplied_; }
    /// The engine that sounds: the current cue's with a set list, else the loop's (null: none).
    engine::Engine* running() noexcept;

private:
    ControlLoop& loop_;
    Stage* stage_ = nullptr;
    CuePlayer* cues_ = nullptr;
    bool panicApplied_ = false;
    std::atomic<access::TactilePlayer*> stimulus_ {nullptr};
    double stimulusClock_ = 0.0;   // s: the steps' clock (the sum of their dt)
};

} // namespace armadillo::live
