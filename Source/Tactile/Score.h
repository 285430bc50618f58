#pragma once
// Tactile scores (thesis §3.3): a human-editable text file of time-stamped events — notes
// (motors held at a level or an envelope) and patterns from the library — with a tempo map, so
// a score can be written in beats and follow a DAW, or in seconds and follow a recording.
// The format is documented in docs/TACTILE.md; Resources/Scores holds the shipped scores.
#include "Core/Scene.h"
#include "Tactile/Patterns.h"
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace armadillo {

/// One tempo segment: from `beat` (and `seconds`) on, `bpm` quarter notes per minute.
struct TempoPoint {
    double beat = 0.0;
    double seconds = 0.0;
    double bpm = 120.0;
};

/// Motors held over [start, end): the envelope's points are spread evenly over the note
/// (one point = a constant level), linearly interpolated, levels 0..15.
struct ScoreNote {
    double start = 0.0, end = 0.0;   ///< s of score time
    std::uint16_t motors = 0;        ///< bit i = motor index i (right-arm layout)
    std::vector<float> envelope;     ///< levels
    long line = 0;                   ///< where it was written
    float levelAt(double seconds) const noexcept;
};

/// A pattern running on one voice over [start, end) (end = infinity: until the score ends).
struct ScorePattern {
    double start = 0.0, end = 0.0;   ///< s of score time
    PatternRequest request {};       ///< duration here is the written one (0 = pattern default)
    long line = 0;
};

struct Score {
    std::string title;
    std::string source;              ///< the file it came from (messages)
    bool inBeats = true;             ///< the file's time unit
    std::vector<TempoPoint> tempo;   ///< at least one point, at beat 0
    double length = 0.0;             ///< s of score time: after this, silence
    std::vector<ScoreNote> notes;    ///< sorted by start
    std::vector<ScorePattern> patterns;   ///< sorted by start

    double secondsAtBeat(double beat) const noexcept;
    double beatAtSeconds(double seconds) const noexcept;
    double bpmAtSeconds(double seconds) const noexcept;
};

/// Parses score text. Throws InputError naming `sourceName`, the 1-based line and the field for
/// anything it cannot use exactly as written (unknown words, bad numbers, times going
/// backwards, out-of-range levels/motors/voices, missing fields).
Score parseScore(std::string_view text, const std::string& sourceName);
/// Reads and parses a file (IoError when it cannot be read).
Score loadScore(const std::string& path);

/// Motor set syntax of the format: "3", "1,3", "1-9", names (all, wrist, middle, elbow, left,
/// under, right, back, wrist-anchors, bones) and lists of these. Motors are numbered 1..16.
/// Returns false for anything else.
bool parseMotorSet(std::string_view text, std::uint16_t& mask) noexcept;

} // namespace armadillo
