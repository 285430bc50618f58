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

namespace armadillo::tactile {

inline constexpr int kMaxScoreParts = 8;

/// A note name (C4 = middle C = 261.63 Hz, A4 = 440 Hz; sharps 's' as in Fs4 — '#' starts a
/// comment in a score —, flats 'b' as in Bb3; octaves 0..9)
/// or a frequency in Hz written `NNNhz` → Hz. Returns 0 for anything else.
double parsePitch(std::string_view text) noexcept;

/// One tempo segment: from `beat` (and `seconds`) on, `bpm` quarter notes per minute.
struct TempoPoint {
    double beat = 0.0;
    double seconds = 0.0;
    double bpm = 120.0;
};

/// How a part of a v2 score follows the recording (docs/TACTILE.md, "Following the recording").
struct ScorePart {
    std::string name;
    bool followNotes = false;        ///< its notes start when their pitch sounds in the recording
    bool followAmplitude = false;    ///< its notes' levels follow the recording's envelope
    double attackMs = 10.0;          ///< envelope follower: rise time constant, ms
    double releaseMs = 150.0;        ///< envelope follower: fall time constant, ms
    bool curveDb = false;            ///< level curve: linear in amplitude (false) or in dB (true)
    double floorDb = -50.0;          ///< dBFS: at or below, the part's lowest written level (or off)
    double topDb = -6.0;             ///< dBFS: at or above, the part's highest written level
    long line = 0;
};

/// Motors held over [start, end): the envelope's points are spread evenly over the note
/// (one point = a constant level), linearly interpolated, levels 0..15.
struct ScoreNote {
    double start = 0.0, end = 0.0;   ///< s of score time
    std::uint16_t motors = 0;        ///< bit i = motor index i (right-arm layout)
    std::vector<float> envelope;     ///< levels
    long line = 0;                   ///< where it was written
    double pitchHz = 0.0;            ///< v2 `pitch=`: the note's fundamental (0 = none written)
    int part = -1;                   ///< index into Score::parts (-1 = no part: plays by the clock)
    bool soft = false;               ///< v2 `start=soft`: its onset never gets the jump-start spike
    float levelAt(double seconds) const noexcept;
    /// The same envelope at a fraction 0..1 of the note (clamped).
    float levelAtFraction(double fraction) const noexcept;
};

/// A named point the alignment must pass through (v2 `TIME cue NAME ...`).
struct ScoreCue {
    enum class Detect : std::uint8_t {
        None,    ///< a named mark only: passed at its score time
        Onset,   ///< a sudden rise of the recording's loudness (≥ 9 dB within 50 ms)
        Loud,    ///< the recording's envelope rising above levelDb
        Quiet,   ///< the recording's envelope falling below levelDb
    };
    double time = 0.0;               ///< s of score time
    std::string name;
    Detect detect = Detect::None;
    double window = 5.0;             ///< s either side of `time` in which it is looked for
    double levelDb = -30.0;          ///< dBFS threshold for Loud / Quiet
    long line = 0;
};

/// A pattern running on one voice over [start, end) (end = infinity: until the score ends).
struct ScorePattern {
    double start = 0.0, end = 0.0;   ///< s of score time
    core::PatternRequest request {}; ///< duration here is the written one (0 = pattern default)
    long line = 0;
};

struct Score {
    int version = 1;                 ///< the file's `armadillo-score N`
    std::string title;
    std::string source;              ///< the file it came from (messages)
    bool inBeats = true;             ///< the file's time unit
    std::vector<TempoPoint> tempo;   ///< at least one point, at beat 0
    double length = 0.0;             ///< s of score time: after this, silence
    std::vector<ScoreNote> notes;    ///< sorted by start
    std::vector<ScorePattern> patterns;   ///< sorted by start
    std::vector<ScorePart> parts;    ///< v2 parts (at most kMaxScoreParts)
    std::vector<ScoreCue> cues;      ///< v2 cues, sorted by time

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

/// Score files of other formats (MIDI files, haptic files: Formats/ScoreImport.h), read by a
/// module above this one: the engine installs the reader, and the score scene uses it for a path
/// that `accepts` (anything else is a .score file or a name).
struct ScoreFileReader {
    bool (*accepts)(const std::string& path) noexcept = nullptr;
    Score (*load)(const std::string& path) = nullptr;
};
void setScoreFileReader(ScoreFileReader reader) noexcept;
ScoreFileReader scoreFileReader() noexcept;

/// Motor set syntax of the format: "3", "1,3", "1-9", names (all, wrist, middle, elbow, left,
/// under, right, back, wrist-anchors, bones) and lists of these. Motors are numbered 1..16.
/// Returns false for anything else.
bool parseMotorSet(std::string_view text, std::uint16_t& mask) noexcept;

} // namespace armadillo::tactile
