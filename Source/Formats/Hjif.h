#pragma once
// MPEG haptics, ISO/IEC 23090-31, in its JSON form `.hjif` (media type haptics/hjif, RFC 9695):
// read, evaluated as the MPEG reference software synthesises it, and written (docs/FORMATS.md,
// "MPEG haptics .hjif"). The semantics come from MPEGGroup/HapticReferenceSoftware:
// source/Types/src/Effect.cpp (EvaluateVectorial, EvaluateTransient, EvaluateKeyframes),
// source/Types/src/Band.cpp (effects summed per band, the 22 ms transient), Channel.cpp (bands
// summed and clamped to ±1), Perception.cpp (linearizeLibrary: a Reference is a copy of the
// library effect at the reference's position), source/Synthesizer/src/Helper.cpp (gain and
// 10^perception_unit_exponent) and source/IOHaptics/src/IOJson.cpp (the keys, what is required,
// the conformance limits). No JUCE.
#include "Core/Csv.h"
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace armadillo::formats::hjif {

enum class BandType { Transient, Curve, VectorialWave, WaveletWave };
enum class CurveType { Unknown, Cubic, Linear, Akima, Bezier, Bspline };

/// A keyframe, its time in seconds from its effect's start (relative_position / timescale).
struct Keyframe {
    double time = 0.0;
    bool hasAmplitude = false;
    double amplitude = 0.0;      ///< amplitude_modulation
    bool hasFrequency = false;
    double frequency = 0.0;      ///< frequency_modulation, Hz
};

/// A basis effect after References and Composites are resolved: start in seconds from the file's 0.
struct Effect {
    double start = 0.0;
    std::string baseSignal = "Sine";
    std::vector<Keyframe> keyframes;
};

struct Band {
    BandType type = BandType::VectorialWave;
    CurveType curve = CurveType::Unknown;
    double lowerHz = 0.0, upperHz = 0.0;
    std::vector<Effect> effects;
};

/// A vibrotactile channel (channels of other perceptions are not kept).
struct Channel {
    int perceptionId = 0;
    int id = 0;
    std::string description;
    double gain = 1.0;
    double scale = 1.0;                    ///< 10^perception_unit_exponent of its perception
    std::uint32_t bodyPartMask = 0;
    int resolutionX = 0, resolutionY = 0;  ///< actuator_resolution (0: none)
    std::vector<std::pair<int, int>> targets;   ///< actuator_target X, Y
    std::vector<Band> bands;
};

struct File {
    unsigned timescale = 1000;
    std::vector<Channel> channels;         ///< the vibrotactile ones, in file order
    int otherPerceptions = 0;              ///< perceptions of other modalities (not felt here)
    int otherFelt = 0;                     ///< perceptions of modality Other felt (the file has no Vibrotactile one)
    double seconds = 0.0;                  ///< the end of the last effect
};

/// One thing wrong with a file, at a line (0: the whole file).
struct Problem {
    long line = 0;
    std::string where;
    std::string what;
};

/// The structure check: every key the reference loader requires, with its type, the
/// conformance limits of source/IOHaptics/src/IOJson.cpp (profile, level, timescale, channels
/// and bands per level, actuator targets inside the resolution, curve_type on Curve bands only,
/// unique library ids, references that resolve) and keyframes in time order. Empty = valid.
/// JSON syntax errors throw InputError.
std::vector<Problem> checkStructure(std::string_view json, const std::string& source);

/// Parses and resolves a file; the first structure problem, an effect this importer cannot
/// evaluate (WaveletWave: docs/FORMATS.md) or an absurd size throws
/// InputError naming `source`.
File parse(std::string_view json, const std::string& source);

/// A channel's envelope on frames of `step` seconds: value k is at time (k + 0.5)·step.
struct Envelope {
    std::vector<float> amplitude;   ///< 0..1: what a motor should feel (gain and unit applied, clamped)
    double minHz = 0.0, maxHz = 0.0;   ///< the carrier's range where the channel sounds (0: none)
};
/// Every channel's envelope (see docs/FORMATS.md for each band type). Throws InputError when the
/// evaluation would exceed the work or memory budget (effects piled on each other).
std::vector<Envelope> evaluate(const File& file, double step, const std::string& source);

/// `--tactile-hjif`: one Vibrotactile perception, one channel per motor (actuator_resolution
/// 3 × rows, actuator_target the motor's column and row, row 0 = the wrist), one VectorialWave
/// band with one effect whose amplitude keyframes step through level/15 (each change a 1 ms
/// ramp), timescale 1000, a `carrierHz` carrier.
std::string write(const std::vector<core::TactileRow>& rows, int motors, const std::string& project, double carrierHz = 150.0);

} // namespace armadillo::formats::hjif
