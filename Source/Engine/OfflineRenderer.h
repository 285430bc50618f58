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
    /// Called after every control update (one per motion row) with the row's time (s, the motion
    /// file's clock), the arm, the gestures the scene emitted in that update and the engine (its
    /// scene's outputs, Engine::sceneValues, and parameters): what a front end's mapping
    /// (`render --map`, Source/Mapping) reads and drives. Empty: not called.
    std::function<void(double t, const ArmState& arm, const GestureEvent* gestures, std::size_t count, Engine& engine)> onControl;
};

struct RenderResult {
    AudioBuffer audio;                       ///< stereo, engine.sceneConfig.sampleRate
    std::vector<TactileRow> tactile;         ///< one row per control update (motor packet)
    std::vector<GestureEvent> gestures;      ///< every gesture the scene emitted
    std::size_t controlUpdates = 0;
    std::size_t invalidRows = 0;             ///< rows before fusion had an orientation (motors stay off)
};

/// Runs the scene over the motion table (IMU, quaternion or pose file); throws InputError for
/// a file that is not a motion file.
RenderResult renderOffline(const CsvTable& motion, const RenderSettings& settings);

} // namespace armadillo
