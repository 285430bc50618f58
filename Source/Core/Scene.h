#pragma once
// The scene API: what every application of thesis §3–4 implements, and the only ways it may
// touch the outside world. A scene never writes a motor level directly: it states intents on a
// MotorCanvas, and the tactile engine shapes them and passes them through the safety stage
// (STYLE.md convention 6). Audio crosses to the audio thread inside the scene, lock-free.
#include "Core/ArmState.h"
#include "Core/Types.h"
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace armadillo::core {

class MotorTargets;

/// Musical transport: the host's (plugin) or the audio clock's (standalone/CLI).
struct Transport {
    bool valid = false;          ///< false: no transport, scenes use their own clock
    bool playing = false;
    double seconds = 0.0;        ///< s since the song start
    double ppq = 0.0;            ///< quarter notes since the song start
    double bpm = 120.0;
    bool looping = false;
};

/// The thesis's sensations (§3.2.6) plus the pulse shapes the applications need.
enum class PatternKind : std::uint8_t {
    Point,        ///< one or more motors at `level` for `duration` (jump-started)
    Pulse,        ///< a single shaped pulse: fast attack, decay over `duration`
    FadeInPulse,  ///< rising ramp then cut (upper-level knobs, thesis §3.4)
    FadeOutPulse, ///< cut in then falling ramp (lower-level knobs)
    Breathing,    ///< all `motors` rise and fall at `rate`
    Jolt,         ///< every motor in `motors` spikes together: a shove
    Tickle,       ///< fast random light touches among `motors`
    Massage,      ///< slow overlapping swells moving around `motors`
    Twist,        ///< configurations fading into each other around the arm
    BrokenGlass,  ///< ~250 ms events travelling elbow → wrist, then mirrored; wrist longer/stronger
    Accent,       ///< short strong hit on `motors`
    GearPull,     ///< "pulling against a gear train": alternating rows at `rate`
    Geiger,       ///< clicks on `motors` at `rate` (compass)
};

/// A request for a pattern. A request replaces whatever runs in the same voice slot.
struct PatternRequest {
    PatternKind kind = PatternKind::Point;
    std::uint16_t motors = 0x01FF;   ///< bit i = motor index i (right-arm layout); default the 3×3 grid
    float level = 15.0f;             ///< peak level 0..15 (the safety stage still has the last word)
    double duration = 0.0;           ///< s; 0 = the pattern's default; < 0 = until stopped
    double rate = 0.0;               ///< Hz for periodic patterns; 0 = default
    int voice = 0;                   ///< 0..kPatternVoices-1
    /// A soft intent (a fade, a swell, a gentle touch): its motors never get the jump-start
    /// spike. false = a fast start (the engine kicks a starting motor, unless the pattern is a
    /// fade by nature or its on-time is shorter than the spike). See docs/TACTILE.md.
    bool soft = false;
};
inline constexpr int kPatternVoices = 8;

/// Scene → tactile engine. Indices use the right-arm layout; the engine mirrors for the left arm.
/// Real-time: every method is called from Scene::control and must not allocate, lock or throw.
class MotorCanvas {
public:
    virtual ~MotorCanvas() = default;
    /// Sustained target for one motor, 0..15 (fractional levels are dithered), until changed.
    virtual void setLevel(int motorIndex, float level) = 0;
    /// The same as a soft intent: the motor's rises toward this target never get the jump-start
    /// spike (swells, crescendos, followed envelopes, gentle backgrounds). setLevel() asks for a
    /// fast start. The default forwards to setLevel() (canvases that do not shape).
    virtual void setSoftLevel(int motorIndex, float level) { setLevel(motorIndex, level); }
    /// All sustained targets to 0 (running patterns keep running).
    virtual void clearLevels() = 0;
    virtual void trigger(const PatternRequest& request) = 0;
    virtual void stopVoice(int voice) = 0;
};

/// Scene → the outside (OSC `/armadillo/gesture`, MIDI notes/CCs). Names are string literals.
/// Real-time: implementations queue into fixed capacity and drop (never grow) when full.
class EventSink {
public:
    virtual ~EventSink() = default;
    virtual void emit(const char* gesture, float value) = 0;
};

/// A MIDI note from the instrument a scene listens to (the layered keyboard's MIDI input:
/// docs/STAGE.md, docs/INTERFACES.md "MIDI input"). Plain data, copied by value.
struct MidiNoteEvent {
    int offset = 0;              ///< sample offset inside the audio block it belongs to (0..numSamples-1)
    std::uint8_t note = 60;      ///< 0..127, 60 = C4
    std::uint8_t velocity = 0;   ///< 1..127 = note-on; 0 = note-off
    std::uint8_t channel = 0;    ///< 0..15
};

struct ControlInput {
    ArmState arm {};             ///< the arm (with two arms: the right one)
    Transport transport {};
    double dt = 0.005;           ///< s since the previous control update
    /// Two arms (docs/STAGE.md): the left arm's state; invalid (valid = false) when only one arm
    /// is worn. Every scene must keep working with one arm.
    ArmState leftArm {};
};

/// A scene's own continuous outputs that a mapping may read (Mapping/, docs/MAPPING.md "Scene
/// outputs"). NaN = this scene has no such output. Written by the scene in control() and read on
/// the same thread right after it (Engine::sceneValues()).
struct SceneValues {
    float pitch = std::numeric_limits<float>::quiet_NaN();    ///< sounding pitch as a MIDI note number, fractional (theremin)
    float fret = std::numeric_limits<float>::quiet_NaN();     ///< fret index, 0 = lowest (theremin)
    float strike = std::numeric_limits<float>::quiet_NaN();   ///< the last strike's speed, deg/s; 0 before any (cymbal)
    // The virtual control panel (thesis §3.4, docs/INSTRUMENTS.md "panel"): its knobs as a remote.
    float panelKnob = std::numeric_limits<float>::quiet_NaN();      ///< the knob under the arm, 0..8 upper level, 9..17 lower (panel)
    float panelLevel = std::numeric_limits<float>::quiet_NaN();     ///< the level the arm is on: 1 upper, 0 lower (panel)
    float panelSelected = std::numeric_limits<float>::quiet_NaN();  ///< the knob last selected by a quick roll, 0..17; NaN before any (panel)
};

struct SceneOutput {
    MotorCanvas& motors;                 ///< the arm's motors (with two arms: the right arm's)
    EventSink& events;
    /// Two arms: the left arm's motors (its own tactile engine and safety stage); null with one.
    MotorCanvas* leftMotors = nullptr;
};

struct SceneConfig {
    double sampleRate = 48000.0;     ///< Hz of renderAudio
    double controlRateHz = 200.0;    ///< expected control updates per second (a hint; dt is exact)
    std::uint64_t seed = 1;          ///< every random choice derives from this (renders repeat)
    ArmSide side = ArmSide::Right;
    std::string text;                ///< braille scene: what to read
    /// braille scene: nothing of its own to read (text ignored), only the messages handed to it
    /// (BrailleSceneControls::showMessage; `armadillo read`, docs/MQTT.md): the arm is still
    /// between messages.
    bool messagesOnly = false;
    std::string score;               ///< score scene: a score name (Core/Resources.h) or a .score file path
    std::string resourceDir;         ///< a folder searched first for resource files (empty: the usual search, Core/Resources.h)
    std::string audioFile;           ///< cymbal: a WAV recording to cut crash fragments from (optional)
    /// audio-touch: the audio input is stems, one mono channel each, in this order, each named by
    /// its preset (drums, bass, other, vocals: docs/INSTRUMENTS.md); empty: one mixed input.
    std::vector<std::string> stems;
    /// patch scene (issue 46): the cell a front end writes the grid's targets into
    /// (Core/MotorTargets.h; Pure Data's `motors L1 … L9`). Null: the scene keeps its own, all 0.
    std::shared_ptr<MotorTargets> motorTargets;
};

/// A scene's own parameter; id is stable ("theremin.range"), value in the given unit.
struct ParamSpec {
    std::string id;
    std::string name;
    float min = 0.0f, max = 1.0f, defaultValue = 0.0f;
    std::string unit;                      ///< "semitones", "deg", "%", "" ...
    std::vector<std::string> choices;      ///< non-empty: a choice parameter (value = index)
};

class Scene {
public:
    virtual ~Scene() = default;
    virtual std::string_view name() const = 0;
    virtual std::vector<ParamSpec> parameters() const { return {}; }
    /// Not real-time: allocate and build tables here. Called before any control/render.
    virtual void prepare(const SceneConfig& config) = 0;
    /// Any thread; implementations store into atomics. Index into parameters().
    virtual void setParameter(int index, float value) noexcept { (void) index; (void) value; }
    /// Once per control update (thesis: ~200/s). REAL-TIME: in the plugin this runs on the audio
    /// thread (inside processBlock), so it must not allocate or free, lock, do I/O or throw, and
    /// its work must be bounded per call (no scan whose length grows with the session; logs and
    /// gestures leave through fixed-capacity SPSC queues or atomics). Everything that allocates
    /// belongs in prepare(). Held to this by Tests/Engine/RealtimeEngineTests.cpp for every scene.
    /// Should a scene throw anyway, the Engine catches it, switches the motors off and reports a
    /// failed state (Engine::failed()); the exception never reaches the host.
    virtual void control(const ControlInput& in, SceneOutput& out) = 0;
    /// Audio thread: no locks, allocation, I/O or exceptions. Adds nothing when silent.
    virtual void renderAudio(float* left, float* right, int numSamples) noexcept
    {
        (void) left; (void) right; (void) numSamples;
    }
    virtual bool producesAudio() const { return false; }
    /// Audio input (the recording the listener hears: the plugin's input bus, `--audio-in`):
    /// `channels` planar channels of n samples at SceneConfig::sampleRate, called on the audio
    /// thread before renderAudio() of the same block. REAL-TIME like renderAudio(): no locks,
    /// allocation, I/O or exceptions, bounded work. What the scene learns crosses to control()
    /// through atomics (in the plugin both run on the audio thread; in `play` they do not).
    /// numSamples may be 0: the front end declares that this input is the recording itself
    /// (`render/play --audio-in`), to be followed from its first sample, silence included; a
    /// plugin input is not declared (an unrouted one delivers silence). A scene that does not
    /// listen ignores it.
    virtual void processInput(const float* const* in, int channels, int numSamples) noexcept
    {
        (void) in; (void) channels; (void) numSamples;
    }
    /// True for scenes that use processInput() (score, audio-touch, layered-keyboard).
    virtual bool listensToAudio() const { return false; }
    /// MIDI notes from the instrument (a keyboard's MIDI out): the `count` note events of the
    /// coming audio block, in time order, their offsets relative to its first sample. Called on
    /// the audio thread BEFORE processInput() of the same block (so an offset names a sample of
    /// the audio that follows). REAL-TIME like processInput(): the caller owns the events (a
    /// fixed buffer); the scene copies what it keeps into fixed capacity, never allocates, locks
    /// or throws. A scene without MIDI input ignores it (the default).
    virtual void processMidi(const MidiNoteEvent* events, int count) noexcept
    {
        (void) events; (void) count;
    }
    /// True for scenes that use processMidi() (layered-keyboard).
    virtual bool listensToMidi() const { return false; }
    /// Entering the scene, or a transport jump: forget gestures in progress. Real-time, like
    /// control() (the plugin calls it on the audio thread).
    virtual void reset() {}
    /// The scene's own outputs after the latest control() (SceneValues). Real-time, control
    /// thread. The default: none.
    virtual SceneValues values() const noexcept { return {}; }
};

} // namespace armadillo::core
