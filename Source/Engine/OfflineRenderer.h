#pragma once
// `armadillo render`: the same engine the app uses, driven by a motion file instead of a device,
// deterministic for a given seed. Control updates happen at the motion file's rows; audio between
// two rows is rendered after the first row's control update (as the live app's audio thread would
// hear it). Sample 0 is the time of the first row.
#include "Core/Csv.h"
#include "Core/Wav.h"
#include "Engine/Engine.h"
#include <functional>
#include <vector>

namespace armadillo::fusion {
class ArmTracker;
}

namespace armadillo::engine {

/// Longest render whose audio is collected in RenderResult::audio (no audioSink): one hour.
inline constexpr double kMaxCollectedRenderSeconds = 3600.0;

/// A MIDI note of the instrument on the render's clock (`render --midi-in`, docs/STAGE.md).
struct TimedMidiNote {
    double t = 0.0;        ///< s from the first motion row (= sample 0 of the audio input)
    int note = 60;         ///< 0..127
    int velocity = 0;      ///< 1..127 note-on, 0 note-off
    int channel = 0;       ///< 0..15
};

struct RenderSettings {
    EngineConfig engine {};
    double tailSeconds = 0.0;      ///< audio rendered after the last row (e.g. to hear a crash ring out)
    int blockSize = 64;            ///< audio is rendered in blocks of at most this many samples
    double bpm = 120.0;            ///< tempo of the audio-clock transport the scenes see
    /// The recording the listener hears (`--audio-in`): fed block by block to the engine's audio
    /// input before each block is rendered, from sample 0 = the first motion row. Its sample
    /// rate must be the engine's (engine.sceneConfig.sampleRate); the scene must listen.
    const core::AudioBuffer* audioIn = nullptr;
    /// Called after every control update (one per motion row) with the row's time (s, the motion
    /// file's clock), the arm, the gestures the scene emitted in that update and the engine (its
    /// scene's outputs, Engine::sceneValues, and parameters): what a front end's mapping
    /// (`render --map`, Source/Mapping) reads and drives; with two arms (leftMotion) also the left
    /// arm's state as of that update (null with one arm). Empty: not called.
    std::function<void(double t, const core::ArmState& arm, const core::ArmState* leftArm, const GestureEvent* gestures, std::size_t count, Engine& engine)>
        onControl;
    std::string audioInName;       ///< the file audioIn came from, named in messages
    /// The instrument's MIDI notes (`--midi-in`), sorted by t: each note goes to the engine's
    /// MIDI input (Engine::processMidi) with the block that holds its sample, before that
    /// block's audio input. The scene must listen to MIDI (layered-keyboard). Null: none.
    const std::vector<TimedMidiNote>* midiIn = nullptr;
    std::string midiInName;        ///< the file midiIn came from, named in messages
    /// Mix the recording (audioIn) into the rendered audio, as the listener hears it (the scene's
    /// sound over the recording, clipped to ±1). False: the scene's sound alone.
    bool mixAudioIn = true;
    /// Longest span a render may cover (first row to last row + tail); a motion file spanning
    /// more is refused with an InputError naming the row, before anything is rendered. Without
    /// an audioSink, at most kMaxCollectedRenderSeconds.
    double maxSeconds = 24.0 * 3600.0;
    /// Where the audio goes, block by block (stereo, at most blockSize frames). Set: the audio is
    /// streamed there and RenderResult::audio stays empty (memory does not grow with the span).
    /// Empty: the audio is collected in RenderResult::audio.
    std::function<void(const float* left, const float* right, int frames)> audioSink;
    /// Two arms (`--motion-left`): the left arm's motion file, on the same clock as the main one
    /// (its rows up to each main row's time are applied before that row's control update).
    /// Needs engine.twoArms. Null: one arm.
    const core::CsvTable* leftMotion = nullptr;
    /// How the sensor that recorded the motion file was strapped on (`render --mount`): the rotation
    /// sensor → device frame (Link/Mount.h's Mount::rotation). IMU samples are turned into the
    /// device frame, orientations become q · mount⁻¹; a pose file is refused (it is the forearm's
    /// own pose). Identity: the file is in the device frame already.
    Eigen::Quaterniond mount = Eigen::Quaterniond::Identity();
    Eigen::Quaterniond leftMount = Eigen::Quaterniond::Identity();   ///< the same for leftMotion (`--mount-left`)
};

struct RenderResult {
    core::AudioBuffer audio;                 ///< stereo, engine.sceneConfig.sampleRate
    std::vector<core::TactileRow> tactile;   ///< one row per control update (motor packet), then the
                                             ///< all-off packet sent at the end (at the render's end time)
    std::vector<GestureEvent> gestures;      ///< every gesture the scene emitted
    std::size_t controlUpdates = 0;
    std::size_t invalidRows = 0;             ///< rows before fusion had an orientation (motors stay off)
    std::uint64_t frames = 0;                ///< audio frames rendered (streamed or collected)
    float peak = 0.0f;                       ///< largest |sample| of the output (0: it is silent)
    float scenePeak = 0.0f;                  ///< largest |sample| of the scene's own sound (without the recording)
    double minElevation = 0.0, maxElevation = 0.0;   ///< degrees, over rows with an orientation
    double minAzimuth = 0.0, maxAzimuth = 0.0;       ///< degrees
    std::vector<core::TactileRow> leftTactile; ///< two arms: the left arm's motor packets, one per control update
    /// Two arms: each control update's orientations (right, left; identity while not tracked).
    std::vector<core::TimedQuaternion> rightOrientation, leftOrientation;
};

/// A motion file as per-row arm updates, whatever its kind: IMU rows (fused by the tracker) or
/// orientations (quaternion and pose files). `load` turns a sensor's recording into the forearm's
/// axes with `mount` (RenderSettings::mount; InputError naming `mountOption` for a pose file).
struct MotionRows {
    core::MotionKind kind = core::MotionKind::Unknown;
    std::vector<core::ImuSample> imu;
    std::vector<core::TimedQuaternion> orientations;
    std::size_t size() const;
    double time(std::size_t i) const;
    core::ArmState apply(fusion::ArmTracker& tracker, std::size_t i) const;
    static MotionRows load(const core::CsvTable& table, const Eigen::Quaterniond& mount = Eigen::Quaterniond::Identity(),
                           const char* mountOption = "--mount");
};

/// Why a render came out silent, in words for a user (empty when `r.peak` > 0): the scene makes
/// no sound, a listening scene without a recording, no row with an orientation, or the arm's
/// range over the file.
std::string silenceReason(const RenderResult& r, const RenderSettings& settings);

/// What an offline render plays: one engine (renderOffline's own, from RenderSettings::engine),
/// or a set list's cues (Live/Stage/SetList.h renderSetList). The renderer owns the clock, the motion,
/// the recording, the MIDI notes and the audio; the performer answers for the sound and the
/// motors. One renderer for both, so a set list renders exactly as a scene does.
class OfflinePerformer {
public:
    virtual ~OfflinePerformer() = default;
    /// Before the control update of the row at `t` s from the first row (a cue change due).
    virtual void beforeRow(double /*t*/) {}
    /// One control update: both arms when `left` is not null.
    virtual core::MotorLevels control(const core::ArmState& right, const core::ArmState* left, const core::Transport& transport, double dt) = 0;
    virtual core::MotorLevels leftLevels() = 0;
    virtual void allOff() = 0;
    /// The engine sounding now (its failure stops the render; a front end's mapping reads it).
    virtual Engine& sounding() = 0;
    virtual void processMidi(const core::MidiNoteEvent* events, int count) = 0;
    virtual void processInput(const float* const* in, int channels, int numSamples) = 0;
    virtual void renderAudio(float* left, float* right, int numSamples) = 0;
    /// Moves the gestures emitted since the last call to `out`.
    virtual void popGestures(std::vector<GestureEvent>& out) = 0;
    /// Whether a recording or MIDI notes can be heard, and if not, why in words ("scene 'x' does
    /// not listen to audio").
    virtual bool listensToAudio(std::string& whyNot) const = 0;
    virtual bool listensToMidi(std::string& whyNot) const = 0;
};

/// Runs the scene over the motion table (IMU, quaternion or pose file); throws InputError for
/// a file that is not a motion file.
RenderResult renderOffline(const core::CsvTable& motion, const RenderSettings& settings);
/// The same with `performer` playing (its engines built by the caller for settings.engine's
/// sample rate): a set list's cues.
RenderResult renderOffline(const core::CsvTable& motion, const RenderSettings& settings, OfflinePerformer& performer);

/// Refuses (InputError naming the row and the time column) a motion file whose rows, plus the
/// tail, span more than `maxSeconds` from the first row — before anything is allocated for them.
/// `timeOf(i)` is row i's time in seconds. Every offline render checks its span with it.
void checkRenderSpan(const core::CsvTable& motion, std::size_t rows, const std::function<double(std::size_t)>& timeOf, double tailSeconds,
                     double maxSeconds);

} // namespace armadillo::engine
