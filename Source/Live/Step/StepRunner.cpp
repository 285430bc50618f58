#include "Live/Step/StepRunner.h"
#include "Live/Stage/SetList.h"
#include <cmath>

namespace armadillo::live {

engine::Engine* StepRunner::running() noexcept
{
    if (cues_ != nullptr) return &cues_->engine(cues_->current());
    EngineSlot* slot = loop_.active();
    return slot != nullptr ? slot->engine.get() : nullptr;
}

StepRunner::StageChange StepRunner::beginStage() noexcept
{
    if (stage_ == nullptr) return StageChange::None;
    cues_ = stage_->beginStep();
    const bool panic = stage_->panicked();
    engine::Engine* engine = nullptr;
    if (EngineSlot* slot = loop_.active(); slot != nullptr) engine = slot->engine.get();
    if (panic) {   // every step while in panic: before anything of it is rendered
        if (engine != nullptr) engine->panic();
        if (cues_ != nullptr) cues_->panic();
    }
    if (panic == panicApplied_) return StageChange::None;
    panicApplied_ = panic;
    if (panic) return StageChange::PanicStarted;
    // Resume: the current scene (or cue) from its start, sound fading back in.
    if (engine != nullptr) engine->resume();
    if (cues_ != nullptr) cues_->resume();
    return StageChange::Resumed;
}

ControlResult StepRunner::step(ControlStep s) noexcept
{
    s.cues = cues_;   // a set list's cues run in place of the loop's engine
    s.panic = panicApplied_;
    s.panicGesture = s.panicGesture || (stage_ != nullptr && stage_->panicGesture());
    ControlResult result = loop_.tick(s);   // swap-in, parameters, fusion, Engine::control
    if (result.gesturePanic && stage_ != nullptr) stage_->panic();
    if (!result.ran) return result;
    stimulusClock_ += s.dt;
    if (access::TactilePlayer* stimulus = stimulus_.load(std::memory_order_acquire); stimulus != nullptr && !panicApplied_ && !result.gesturePanic)
        // A guided procedure has the motors; the roll rate feeds its arm gestures.
        result.levels = stimulus->onPacket(stimulusClock_, result.arm.valid ? result.arm.gyro.x() : std::nan(""));
    return result;
}

} // namespace armadillo::live
