#include "Live/Session/Instrument.h"
#include "Live/Stage/SetList.h"

namespace armadillo::live {

Instrument::Begun Instrument::beginStage() noexcept
{
    Begun b;
    b.change = runner_.beginStage();
    if (b.change == StepRunner::StageChange::PanicStarted) {
        // A panic that a step's gesture started was already heard by the mapping at that step.
        b.silenceMapping = !mappingSilenced_;
        mappingSilenced_ = true;
    } else if (b.change == StepRunner::StageChange::Resumed) {
        mappingSilenced_ = false;
    }
    return b;
}

Instrument::Stepped Instrument::step(ControlStep s, double t, bool levelsOut) noexcept
{
    s.leftArm = leftArm_.fuse(s.recordedLeft);   // null while the left arm is off (one arm)
    // The stage's cues and panic; the panic gesture (docs/STAGE.md) panics the stage too, held
    // until resume as a command's panic is (StepRunner.h). The result is built in place: a
    // default ArmState costs a rest orientation (sines and cosines) that would be thrown away.
    Stepped out {runner_.step(s), s.leftArm};
    out.panicked = runner_.panicked() || out.result.gesturePanic;
    if (out.panicked && !mappingSilenced_) out.silenceMapping = true;
    mappingSilenced_ = out.panicked;
    if (!out.result.ran) return out;
    out.engine = runner_.running();
    if (out.engine != nullptr)
        published_.publish(StepPublisher::frameOf(t, out.result.arm, levelsOut ? &out.result.levels : nullptr, out.engine->config().motorCount),
                           *out.engine);
    return out;
}

void Instrument::processMidi(const core::MidiNoteEvent* events, int count) noexcept
{
    if (CuePlayer* cues = runner_.cues(); cues != nullptr) cues->processMidi(events, count);
    else loop_.processMidi(events, count);
}

void Instrument::processInput(const float* const* in, int channels, int numSamples) noexcept
{
    if (CuePlayer* cues = runner_.cues(); cues != nullptr) cues->processInput(in, channels, numSamples);
    else loop_.processInput(in, channels, numSamples);
}

void Instrument::render(float* left, float* right, int numSamples) noexcept
{
    if (CuePlayer* cues = runner_.cues(); cues != nullptr) cues->renderAudio(left, right, numSamples);
    else loop_.render(left, right, numSamples);
}

const core::MotorLevels* Instrument::leftLevels() noexcept
{
    if (!leftArm_.on()) return nullptr;
    if (CuePlayer* cues = runner_.cues(); cues != nullptr) return &cues->leftLevels();
    engine::Engine* engine = runner_.running();
    return engine != nullptr ? &engine->leftLevels() : nullptr;
}

mapping::MappingInput Instrument::mappingInput(const Stepped& stepped, double t) const noexcept
{
    mapping::MappingInput in;
    in.t = t;
    in.arm[0] = &stepped.result.arm;
    in.arm[1] = stepped.leftArm;
    if (stepped.engine != nullptr) in.scene = stepped.engine->sceneValues();
    in.gestures = published_.stepGestures();
    in.gestureCount = published_.stepGestureCount();
    in.stageOnly = stepped.panicked;   // in panic no note is sent until resume; a mapped resume still runs
    return in;
}

} // namespace armadillo::live
