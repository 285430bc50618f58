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
#include <array>
#include <atomic>
#include <memory>
#include <string>
#include <vector>

namespace armadillo {

class TactileEngine;

/// Scene names of INTERFACES.md, in the order of the plugin's `scene` choice.
const std::vector<std::string>& sceneNames();
/// A new scene by name; throws InputError for an unknown name.
std::unique_ptr<Scene> createScene(const std::string& name);

struct EngineConfig {
    std::string scene = "monitor";
    SceneConfig sceneConfig {};
    int motorCount = kGridMotors;   ///< 9, or 12 with the back motors
    std::vector<std::string> parameters;   ///< "id=value" scene settings applied after prepare()
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
    Engine(const EngineConfig& config, std::unique_ptr<Scene> scene);
    ~Engine();
    Engine(const Engine&) = delete;
    Engine& operator=(const Engine&) = delete;

    /// Control thread (real-time): one update per sensor packet. Returns the levels of the next
    /// motor packet, after shaping and the safety stage. dt in s (clamped to a sane range). Never
    /// throws: a scene that throws is stopped for good (failed()), its motors off, and every later
    /// call returns all-off levels. `motorOnTime` ≥ 0: how long the previous levels really stayed
    /// on the motor, when a link that sends levels on the wall clock says it differs from dt
    /// (TactileEngine::tick); negative: dt.
    MotorLevels control(const ArmState& arm, const Transport& transport, double dt, double motorOnTime = -1.0) noexcept;
    /// Audio thread: adds nothing but the scene's sound; no locks, allocation or I/O.
    void renderAudio(float* left, float* right, int numSamples) noexcept;
    /// Audio thread: the audio input (planar channels, n samples at the scene's sample rate),
    /// handed to the scene before renderAudio() of the same block. Real-time; ignored by scenes
    /// that do not listen and once the scene failed. numSamples may be 0: "this input is the
    /// recording itself" (render/play --audio-in say so before the first block; Core/Scene.h).
    void processInput(const float* const* in, int channels, int numSamples) noexcept;
    bool listensToAudio() const { return scene_->listensToAudio(); }
    /// Stop, disconnect or error: every motor off now; patterns and targets forgotten.
    void allOff() noexcept;

    /// Sets one of the scene's own parameters by its stable id (ParamSpec::id). `value` is a
    /// number in the parameter's unit, or one of its choice names. Throws InputError naming the
    /// id and the allowed values when either is unknown or out of range. Not real-time.
    void setSceneParameter(const std::string& id, const std::string& value);
    /// Applies "id=value" settings in order (e.g. from --param options).
    void setSceneParameters(const std::vector<std::string>& assignments);

    Scene& scene() noexcept { return *scene_; }
    const EngineConfig& config() const noexcept { return config_; }
    bool producesAudio() const { return scene_->producesAudio(); }
    /// The scene threw during control(): it no longer runs (silence, motors off). Any thread.
    bool failed() const noexcept { return failed_.load(std::memory_order_acquire); }
    /// What it threw (the exception's what(), cut to fit), "" while not failed(). Any thread.
    const char* failure() const noexcept { return failed() ? failure_.data() : ""; }
    /// Gestures since the last call (control thread; at most 64 are kept between calls).
    bool popGesture(GestureEvent& out) noexcept { return gestures_.pop(out); }
    /// The scene's own outputs after the latest control() (Core/Scene.h SceneValues; control thread).
    SceneValues sceneValues() const noexcept { return failed() ? SceneValues {} : scene_->values(); }

private:
    class Events;
    void fail(const char* what) noexcept;
    EngineConfig config_;
    std::unique_ptr<Scene> scene_;
    std::unique_ptr<TactileEngine> tactile_;
    std::unique_ptr<Events> events_;
    SpscQueue<GestureEvent, 64> gestures_;
    double time_ = 0.0;
    std::array<char, 256> failure_ {};   // written once, before failed_ is set
    std::atomic<bool> failed_ {false};
};

} // namespace armadillo
