#pragma once
// The engine every front end shares (plugin, standalone app, `armadillo play`, `armadillo render`):
// arm state → scene → tactile engine (shaping, then the safety stage, last) → motor levels;
// scene → audio. Threads (docs/ARCHITECTURE.md): control() runs on the control thread (the device
// thread in `play`, the audio thread in the plugin), renderAudio() on the audio thread; both are
// real-time (no allocation, lock, I/O or exception) and share nothing but the scene's own
// lock-free parameters. Construction, scene changes and setSceneParameter() are not real-time.
#include "Core/Scene.h"
#include "Core/SpscQueue.h"
#include "Core/Types.h"
#include "Tactile/TactileEngine.h"
#include <array>
#include <atomic>
#include <memory>
#include <string>
#include <vector>

namespace armadillo::tactile {
class TactileEngine;
}

namespace armadillo::engine {

/// Scene names of INTERFACES.md, in the order of the plugin's `scene` choice.
const std::vector<std::string>& sceneNames();
/// Scenes a front end plays by writing into them, made by createScene() too but not in the
/// plugin's choice or `play`'s list: "patch" (issue 46; the grid's targets from a patch,
/// SceneConfig::motorTargets), for Pure Data's [armadillo] and [armadillo~].
const std::vector<std::string>& hostedSceneNames();
/// A new scene by name (sceneNames() or hostedSceneNames()); throws InputError for an unknown name.
std::unique_ptr<core::Scene> createScene(const std::string& name);
/// What is wrong with one "id=value" setting for `scene` (the check Engine::setSceneParameter
/// makes, without preparing the scene): empty when it would be accepted. For front ends that
/// refuse a bad setting as bad usage before any work starts (`--param`).
std::string sceneParameterProblem(const std::string& scene, const std::string& assignment);

struct EngineConfig {
    std::string scene = "monitor";
    core::SceneConfig sceneConfig {};
    int motorCount = core::kGridMotors; ///< 9, or 12 with the back motors
    std::vector<std::string> parameters;   ///< "id=value" scene settings applied after prepare()
    /// The reader's touch profile as per-motor gains (TactileConfig::motorGain; physical motor
    /// order m1…). All 1 = none. Device/TouchProfile.h makes them from a profile file.
    std::array<float, core::kMaxMotors> motorGain = tactile::TactileConfig::unitMotorGains();
    /// Two arms (docs/STAGE.md): a second tactile engine (its own shaping and safety stage,
    /// left-arm mirroring) for the left arm's motors; control() then takes the left arm's state.
    bool twoArms = false;
};

/// A gesture a scene emitted (for OSC /armadillo/gesture and MIDI). `name` is a string literal.
struct GestureEvent {
    const char* name = "";
    float value = 0.0f;
    double t = 0.0;
};

class Engine {
public:
    explicit Engine(const EngineConfig& config);
    /// The same with a scene made elsewhere (tests, a front end's own scene); config.scene is
    /// only its name for messages.
    Engine(const EngineConfig& config, std::unique_ptr<core::Scene> scene);
    ~Engine();
    Engine(const Engine&) = delete;
    Engine& operator=(const Engine&) = delete;

    /// Control thread (real-time): one update per sensor packet. Returns the levels of the next
    /// motor packet, after shaping and the safety stage. dt in s (clamped to a sane range). Never
    /// throws: a scene that throws is stopped for good (failed()), its motors off, and every later
    /// call returns all-off levels. `motorOnTime` ≥ 0: how long the previous levels really stayed
    /// on the motor, when a link that sends levels on the wall clock says it differs from dt
    /// (TactileEngine::tick); negative: dt.
    core::MotorLevels control(const core::ArmState& arm, const core::Transport& transport, double dt, double motorOnTime = -1.0) noexcept;
    /// Two arms: as control(), with the left arm's state (scenes see it as ControlInput::leftArm);
    /// returns the right arm's levels, leftLevels() the left arm's (all-off without twoArms).
    core::MotorLevels control(const core::ArmState& arm, const core::ArmState& leftArm, const core::Transport& transport, double dt) noexcept;
    /// The left arm's motor levels of the last control() (control thread).
    const core::MotorLevels& leftLevels() const noexcept { return leftLevels_; }
    bool twoArms() const noexcept { return leftTactile_ != nullptr; }
    /// Audio thread: adds nothing but the scene's sound; no locks, allocation or I/O.
    void renderAudio(float* left, float* right, int numSamples) noexcept;
    /// Audio thread: the audio input (planar channels, n samples at the scene's sample rate),
    /// handed to the scene before renderAudio() of the same block. Real-time; ignored by scenes
    /// that do not listen and once the scene failed. numSamples may be 0: "this input is the
    /// recording itself" (render/play --audio-in say so before the first block; Core/Scene.h).
    void processInput(const float* const* in, int channels, int numSamples) noexcept;
    bool listensToAudio() const { return scene_->listensToAudio(); }
    /// Audio thread: the instrument's MIDI notes for the coming block (Core/Scene.h,
    /// Scene::processMidi), handed to the scene before processInput() of the same block.
    /// Real-time; ignored by scenes without MIDI input and once the scene failed.
    void processMidi(const core::MidiNoteEvent* events, int count) noexcept;
    bool listensToMidi() const { return scene_->listensToMidi(); }
    /// Stop, disconnect or error: every motor off now; patterns and targets forgotten.
    void allOff() noexcept;
    /// Control thread, real-time: another arm from now on (a switch of source). Every motor off
    /// now, and the next control() resets the scene first (Scene::reset()), so nothing it took
    /// from the old arm (the theremin's reference heading, a gesture in progress) carries over.
    void restart() noexcept;

    /// Panic (docs/STAGE.md): any thread, real-time, idempotent. From the next control()
    /// every motor is off through the tactile engine's all-off path (and stays off, the safety
    /// stage still accounting the time), the scene no longer runs; the next renderAudio() block
    /// fades to silence within kPanicFadeSeconds and stays silent (the scene keeps rendering
    /// underneath, so its timeline does not jump). Latches until resume().
    void panic() noexcept;
    /// Back to the current scene after a panic: any thread, real-time. The next control() resets
    /// the scene (Scene::reset: gestures in progress forgotten) and runs it; audio fades back in
    /// over kResumeFadeSeconds.
    void resume() noexcept;
    bool panicked() const noexcept { return panic_.load(std::memory_order_acquire); }
    /// Panics so far (each panic() while not panicked counts once).
    std::uint32_t panicCount() const noexcept { return panicCount_.load(std::memory_order_relaxed); }
    static constexpr double kPanicFadeSeconds = 0.001;
    static constexpr double kResumeFadeSeconds = 0.020;

    /// Sets one of the scene's own parameters by its stable id (ParamSpec::id). `value` is a
    /// number in the parameter's unit, or one of its choice names. Throws InputError naming the
    /// id and the allowed values when either is unknown or out of range. Not real-time.
    void setSceneParameter(const std::string& id, const std::string& value);
    /// Applies "id=value" settings in order (e.g. from --param options).
    void setSceneParameters(const std::vector<std::string>& assignments);

    core::Scene& scene() noexcept { return *scene_; }
    const EngineConfig& config() const noexcept { return config_; }
    bool producesAudio() const { return scene_->producesAudio(); }
    /// The scene threw during control(): it no longer runs (silence, motors off). Any thread.
    bool failed() const noexcept { return failed_.load(std::memory_order_acquire); }
    /// What it threw (the exception's what(), cut to fit), "" while not failed(). Any thread.
    const char* failure() const noexcept { return failed() ? failure_.data() : ""; }
    /// Gestures since the last call (control thread; at most 64 are kept between calls).
    bool popGesture(GestureEvent& out) noexcept { return gestures_.pop(out); }
    /// The scene's own outputs after the latest control() (Core/Scene.h SceneValues; control thread).
    core::SceneValues sceneValues() const noexcept { return failed() ? core::SceneValues {} : scene_->values(); }

private:
    class Events;
    void fail(const char* what) noexcept;
    EngineConfig config_;
    std::unique_ptr<core::Scene> scene_;
    std::unique_ptr<tactile::TactileEngine> tactile_;
    std::unique_ptr<tactile::TactileEngine> leftTactile_; // two arms only
    core::MotorLevels leftLevels_ {};
    core::MotorLevels run(const core::ArmState& arm, const core::ArmState* leftArm, const core::Transport& transport, double dt, double motorOnTime) noexcept;
    std::unique_ptr<Events> events_;
    core::SpscQueue<GestureEvent, 64> gestures_;
    double time_ = 0.0;
    std::array<char, 256> failure_ {};   // written once, before failed_ is set
    std::atomic<bool> failed_ {false};
    std::atomic<bool> panic_ {false};
    std::atomic<std::uint32_t> panicCount_ {0};
    bool controlPanicked_ = false;       // control thread: the state of the previous control()
    bool restartPending_ = false;        // control thread: restart() asked, the scene not yet reset
    double audioGain_ = 1.0;             // audio thread: the panic/resume fade
};

} // namespace armadillo::engine
