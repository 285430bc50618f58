#include "Engine/Engine.h"
#include "Tactile/TactileEngine.h"
#include "Core/Errors.h"
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>


namespace armadillo::engine {

/// Gestures go into a bounded queue; when the consumer falls behind, new ones are dropped.
class Engine::Events final : public core::EventSink {
public:
    Events(core::SpscQueue<GestureEvent, 64>& queue, const double& time) : queue_(queue), time_(time) {}
    void emit(const char* gesture, float value) override { queue_.push({gesture, value, time_}); }

private:
    core::SpscQueue<GestureEvent, 64>& queue_;
    const double& time_;
};

Engine::Engine(const EngineConfig& config) : Engine(config, createScene(config.scene)) {}

Engine::Engine(const EngineConfig& config, std::unique_ptr<core::Scene> scene) : config_(config), scene_(std::move(scene))
{
    if (!scene_) throw core::InputError("", 0, "", "no scene given for '" + config_.scene + "'");
    config_.motorCount = std::clamp(config_.motorCount, core::kGridMotors, core::kMaxMotors);
    scene_->prepare(config_.sceneConfig);
    tactile_ = std::make_unique<tactile::TactileEngine>();
    tactile::TactileConfig tactileConfig;
    tactileConfig.motorCount = config_.motorCount;
    tactileConfig.side = config_.sceneConfig.side;
    tactileConfig.motorGain = config_.motorGain;
    tactile_->prepare(tactileConfig);
    if (config_.twoArms) {   // the left arm: its own shaping and safety stage, mirrored columns
        leftTactile_ = std::make_unique<tactile::TactileEngine>();
        tactile::TactileConfig left = tactileConfig;
        left.side = core::ArmSide::Left;
        leftTactile_->prepare(left);
    }
    events_ = std::make_unique<Events>(gestures_, time_);
    setSceneParameters(config_.parameters);
}

namespace {
/// The parameter `id` of a scene with these specs set to `value`: its index and value, or an
/// empty `problem` saying what is wrong (unknown id, not a number or a choice, out of range).
struct ParameterSetting {
    int index = -1;
    float value = 0.0f;
    std::string problem;
};

ParameterSetting resolveParameter(const std::vector<core::ParamSpec>& specs, const std::string& scene, const std::string& id,
                                  const std::string& value)
{
    ParameterSetting out;
    for (std::size_t i = 0; i < specs.size(); ++i) {
        const core::ParamSpec& p = specs[i];
        if (p.id != id) continue;
        out.index = static_cast<int>(i);
        for (std::size_t c = 0; c < p.choices.size(); ++c)
            if (p.choices[c] == value) {
                out.value = static_cast<float>(c);
                return out;
            }
        double v = 0.0;
        const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
        if (ec != std::errc() || end != value.data() + value.size() || !std::isfinite(v) || v < double(p.min) || v > double(p.max)) {
            std::string allowed = std::to_string(p.min) + ".." + std::to_string(p.max);
            for (std::size_t c = 0; c < p.choices.size(); ++c) allowed += (c ? ", " : " or ") + p.choices[c];
            out.problem = "'" + value + "' is not a valid value (" + allowed + (p.unit.empty() ? "" : " " + p.unit) + ")";
            return out;
        }
        out.value = static_cast<float>(v);
        return out;
    }
    std::string ids;
    for (const auto& p : specs) ids += (ids.empty() ? "" : ", ") + p.id;
    out.problem = "scene '" + scene + "' has no such parameter (it has: " + (ids.empty() ? "none" : ids) + ")";
    return out;
}
} // namespace

std::string sceneParameterProblem(const std::string& scene, const std::string& assignment)
{
    const auto eq = assignment.find('=');
    if (eq == std::string::npos || eq == 0) return "scene parameter '" + assignment + "' must be written id=value";
    return resolveParameter(createScene(scene)->parameters(), scene, assignment.substr(0, eq), assignment.substr(eq + 1)).problem;
}

void Engine::setSceneParameter(const std::string& id, const std::string& value)
{
    const ParameterSetting s = resolveParameter(scene_->parameters(), config_.scene, id, value);
    if (!s.problem.empty()) throw core::InputError("", 0, id, s.problem);
    scene_->setParameter(s.index, s.value);
}

void Engine::setSceneParameters(const std::vector<std::string>& assignments)
{
    for (const auto& a : assignments) {
        const auto eq = a.find('=');
        if (eq == std::string::npos || eq == 0) throw core::InputError("", 0, "", "scene parameter '" + a + "' must be written id=value");
        setSceneParameter(a.substr(0, eq), a.substr(eq + 1));
    }
}

Engine::~Engine() = default;

core::MotorLevels Engine::control(const core::ArmState& arm, const core::Transport& transport, double dt, double motorOnTime) noexcept
{
    return run(arm, nullptr, transport, dt, motorOnTime);
}

core::MotorLevels Engine::control(const core::ArmState& arm, const core::ArmState& leftArm, const core::Transport& transport, double dt) noexcept
{
    return run(arm, &leftArm, transport, dt, -1.0);
}

core::MotorLevels Engine::run(const core::ArmState& arm, const core::ArmState* leftArm, const core::Transport& transport, double dt, double motorOnTime) noexcept
{
    leftLevels_ = core::MotorLevels {};
    if (failed_.load(std::memory_order_relaxed)) return core::MotorLevels {};
    // A stalled or restarted source must not make shaping jump: dt is kept to 0..0.1 s.
    if (!(dt >= 0.0)) dt = 0.0;
    dt = std::min(dt, 0.1);
    time_ = arm.t;
    if (panic_.load(std::memory_order_acquire)) {
        // Every motor off through the tactile engine's all-off path; the safety stage keeps
        // accounting the time (its heat history stays true for the resume).
        controlPanicked_ = true;
        tactile_->allOff();
        if (leftTactile_) {
            leftTactile_->allOff();
            leftLevels_ = leftTactile_->tick(dt);
        }
        return tactile_->tick(dt, std::isfinite(motorOnTime) ? motorOnTime : -1.0);
    }
    core::ControlInput in {arm, transport, dt};
    if (leftArm) in.leftArm = *leftArm;
    core::SceneOutput out {*tactile_, *events_, leftTactile_.get()};
    try {
        if (controlPanicked_ || restartPending_) {   // back from a panic, or another arm: the scene starts afresh
            controlPanicked_ = false;
            restartPending_ = false;
            scene_->reset();
        }
        scene_->control(in, out);
    } catch (const std::exception& e) {
        fail(e.what());
        return core::MotorLevels {};
    } catch (...) {
        fail("unknown exception");
        return core::MotorLevels {};
    }
    if (leftTactile_) leftLevels_ = leftTactile_->tick(dt);
    return tactile_->tick(dt, std::isfinite(motorOnTime) ? motorOnTime : -1.0);
}

void Engine::fail(const char* what) noexcept
{
    // A scene broke its contract (Core/Scene.h): motors off first, then a state the front ends
    // report (the plugin's status line, `armadillo play` and `render` with exit code 4). Nothing
    // is rethrown: on the audio thread an exception would reach the host.
    tactile_->allOff();
    if (leftTactile_) leftTactile_->allOff();
    std::strncpy(failure_.data(), what ? what : "", failure_.size() - 1);
    failed_.store(true, std::memory_order_release);
}

void Engine::renderAudio(float* left, float* right, int numSamples) noexcept
{
    if (numSamples <= 0) return;
    std::memset(left, 0, sizeof(float) * static_cast<std::size_t>(numSamples));
    std::memset(right, 0, sizeof(float) * static_cast<std::size_t>(numSamples));
    if (failed_.load(std::memory_order_acquire)) return;   // a failed scene stays silent
    scene_->renderAudio(left, right, numSamples);
    // Last line of defence for ears and speakers: nothing non-finite, nothing beyond full scale.
    for (int i = 0; i < numSamples; ++i) {
        left[i] = std::isfinite(left[i]) ? std::clamp(left[i], -1.0f, 1.0f) : 0.0f;
        right[i] = std::isfinite(right[i]) ? std::clamp(right[i], -1.0f, 1.0f) : 0.0f;
    }
    // Panic: a 1 ms fade to silence (no click), then zeros; resume fades back in over 20 ms.
    const bool silent = panic_.load(std::memory_order_acquire);
    if (!silent && audioGain_ >= 1.0) return;
    const double fs = config_.sceneConfig.sampleRate > 0.0 ? config_.sceneConfig.sampleRate : 48000.0;
    const double step = silent ? -1.0 / std::max(1.0, kPanicFadeSeconds * fs) : 1.0 / std::max(1.0, kResumeFadeSeconds * fs);
    for (int i = 0; i < numSamples; ++i) {
        audioGain_ = std::clamp(audioGain_ + step, 0.0, 1.0);
        const auto g = static_cast<float>(audioGain_);
        left[i] *= g;
        right[i] *= g;
    }
}

void Engine::panic() noexcept
{
    if (!panic_.exchange(true, std::memory_order_acq_rel)) panicCount_.fetch_add(1, std::memory_order_relaxed);
}

void Engine::resume() noexcept { panic_.store(false, std::memory_order_release); }

void Engine::processInput(const float* const* in, int channels, int numSamples) noexcept
{
    if (!in || channels <= 0 || numSamples < 0 || failed_.load(std::memory_order_acquire)) return;
    scene_->processInput(in, channels, numSamples);
}

void Engine::processMidi(const core::MidiNoteEvent* events, int count) noexcept
{
    if (!events || count <= 0 || failed_.load(std::memory_order_acquire)) return;
    scene_->processMidi(events, count);
}

void Engine::allOff() noexcept
{
    tactile_->allOff();
    if (leftTactile_) leftTactile_->allOff();
    leftLevels_ = core::MotorLevels {};
}

void Engine::restart() noexcept
{
    allOff();
    restartPending_ = true;
}

} // namespace armadillo::engine
