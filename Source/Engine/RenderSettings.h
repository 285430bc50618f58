#pragma once
// What an offline render (`armadillo render`) is given and gives back, below the live instrument
// that runs it (Live/Session/RowClock.h: a file's rows are its clock, one control step per row;
// audio between two rows is rendered after the first row's step, as the live app's audio thread
// would hear it; sample 0 is the time of the first row): the settings, the result, a motion
// file as rows, and the checks every render makes before it starts.
#include "Core/Csv.h"
#include "Core/Wav.h"
#include "Engine/Engine.h"
#include <functional>
#include <vector>

namespace armadillo::fusion {
class ArmTracker;
}
namespace armadillo::mapping {
struct MappingInput;
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
    /// Called after every control update (one per motion row) with the mapping's view of it
    /// (Mapping/Mapper.h MappingInput: the row's time on the motion file's clock, both arms — the
    /// left null with one arm — the scene's values and the gestures of that update) and the engine
    /// that sounds: what a front end's mapping (`render --map`, Source/Mapping) reads and drives.
    /// Empty: not called.
    std::function<void(const mapping::MappingInput& in, Engine& engine)> onStep;
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

/// Refuses (InputError naming the row and the time column) a motion file whose rows, plus the
/// tail, span more than `maxSeconds` from the first row — before anything is allocated for them.
/// `timeOf(i)` is row i's time in seconds. Every offline render checks its span with it.
void checkRenderSpan(const core::CsvTable& motion, std::size_t rows, const std::function<double(std::size_t)>& timeOf, double tailSeconds,
                     double maxSeconds);

} // namespace armadillo::engine
