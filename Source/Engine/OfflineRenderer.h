#pragma once
// `armadillo render`: the same engine the app uses, driven by a motion file instead of a device,
// deterministic for a given seed. Control updates happen at the motion file's rows; audio between
// two rows is rendered after the first row's control update (as the live app's audio thread would
// hear it). Sample 0 is the time of the first row.
#include "Core/Csv.h"
#include "Core/Wav.h"
#include "Engine/Engine.h"
#include <vector>

namespace armadillo {

struct RenderSettings {
    EngineConfig engine {};
    double tailSeconds = 0.0;      ///< audio rendered after the last row (e.g. to hear a crash ring out)
    int blockSize = 64;            ///< audio is rendered in blocks of at most this many samples
    double bpm = 120.0;            ///< tempo of the audio-clock transport the scenes see
    /// The recording the listener hears (`--audio-in`): fed block by block to the engine's audio
    /// input before each block is rendered, from sample 0 = the first motion row. Its sample
    /// rate must be the engine's (engine.sceneConfig.sampleRate); the scene must listen.
    const AudioBuffer* audioIn = nullptr;
    /// Two arms (`--motion-left`): the left arm's motion file, on the same clock as the main one
    /// (its rows up to each main row's time are applied before that row's control update).
    /// Needs engine.twoArms. Null: one arm.
    const CsvTable* leftMotion = nullptr;
};

struct RenderResult {
    AudioBuffer audio;                       ///< stereo, engine.sceneConfig.sampleRate
    std::vector<TactileRow> tactile;         ///< one row per control update (motor packet)
    std::vector<GestureEvent> gestures;      ///< every gesture the scene emitted
    std::size_t controlUpdates = 0;
    std::size_t invalidRows = 0;             ///< rows before fusion had an orientation (motors stay off)
    std::vector<TactileRow> leftTactile;     ///< two arms: the left arm's motor packets, one per control update
    /// Two arms: each control update's orientations (right, left; identity while not tracked).
    std::vector<TimedQuaternion> rightOrientation, leftOrientation;
};

/// Runs the scene over the motion table (IMU, quaternion or pose file); throws InputError for
/// a file that is not a motion file.
RenderResult renderOffline(const CsvTable& motion, const RenderSettings& settings);

} // namespace armadillo
