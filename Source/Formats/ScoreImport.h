#pragma once
// Tactile scores from other formats (docs/FORMATS.md): a Standard MIDI File (notes → motors by a
// documented, editable rule), a multichannel WAV (the Syntacts convention: channel k drives motor
// k), Apple's AHAP and Meta's `.haptic`. Each importer writes the text of a version-2 score — a
// file a person can read and edit — and the result is parsed back by the score parser, so what
// is imported is exactly what `--score FILE.score` plays. No JUCE.
#include "Core/Csv.h"
#include "Formats/Hjif.h"
#include "Formats/MidiFile.h"
#include "Tactile/Score.h"
#include "Tactile/TactileEngine.h"
#include "Tactors/TactorRenderer.h"
#include <cstdint>
#include <string>
#include <vector>

namespace armadillo::formats {

/// A track's motors instead of the pitch rule (`--track N=SET`), or the track left out (`--track N=off`).
struct MidiTrackRule {
    int track = 1;               ///< 1-based: the MTrk chunk's position in the file
    std::uint16_t motors = 0;    ///< bit i = motor index i; 0 with `off`
    bool off = false;
};

/// The MIDI rule (docs/FORMATS.md, "MIDI files"); every default is what the docs describe.
struct MidiImportOptions {
    int maxMotors = 4;                 ///< the budget: at most this many notes sound at once
    std::vector<MidiTrackRule> tracks; ///< per-track overrides
    tactile::SafetyParams safety {};   ///< the level curve's limits: rating and the run above it
    float quietLevel = 1.5f;           ///< level of velocity 1
    float shortTop = 10.0f;            ///< level of velocity 127 for a note that may run above the rating
    int softBelowVelocity = 49;        ///< notes quieter than this (p and softer) ...
    double softLongerThan = 0.5;       ///< ... and at least this long (s) start soft
    bool follow = true;                ///< pitch= on every pitched note, parts follow=notes
};

/// What an import did, besides the score text.
struct ImportReport {
    std::string format;          ///< "midi", "wav", "ahap", "haptic", "tact"
    int notes = 0;               ///< notes written
    int dropped = 0;             ///< notes left out (over the budget, or every motor busy)
    int shortened = 0;           ///< held notes ended early to make room for a new onset
    int cues = 0;
    std::vector<std::string> warnings;
};

struct ImportedScore {
    std::string text;            ///< the score file's text (armadillo-score 2)
    tactile::Score score;        ///< the same text parsed
    ImportReport report;
};

/// The level curve of the MIDI rule: velocity 1..127 → quietLevel..top, linear, where top is the
/// rated level for a note longer than the safety's run above the rating (it could not run above
/// the rating anyway) and shortTop for a shorter one.
float midiVelocityLevel(int velocity, double seconds, const MidiImportOptions& options) noexcept;

/// The motor (index, right-arm layout) a pitch rule bin 0..8 names: 0 = elbow left (motor 7) …
/// 8 = wrist right (motor 3); bin = 3·(2 − row) + column.
int binMotor(int bin) noexcept;

ImportedScore importMidi(const MidiFile& midi, const MidiImportOptions& options, const std::string& source);

/// Options of the haptic formats.
struct HapticImportOptions {
    double frameSeconds = 0.005;          ///< WAV: the analysis frame (the peak of each frame is a level)
    std::uint16_t motors = 0x01FF;        ///< AHAP / .haptic: the motors the one actuator drives (default all nine)
    double transientSeconds = 0.030;      ///< AHAP: how long a transient event is held
    double emphasisSeconds = 0.030;       ///< .haptic: how long an emphasis is held (Lofelt's emphasis length)
    std::string tactDevice;               ///< .tact: "ForearmR" or "ForearmL"; empty: the forearm that plays (ForearmR when both)
    double tactPathStep = 0.020;          ///< .tact: a path is followed in steps of this (s; the Designer's 20 ms frame)
    /// .hjif: channel (1-based, the file's Vibrotactile channels in order) -> motors
    /// (`--actuator-motors C=SET`); empty: the default rule (hjifDefaultMotors). With any given,
    /// the channels not named are left out.
    std::vector<std::pair<int, std::uint16_t>> hjifChannels;
    int hjifGridMotors = 9;               ///< .hjif: the grid the default rule spreads over (12 with the back row)
};

/// A multichannel WAV (9 or 12 channels, or up to 16): channel k → motor k; each frame's level is
/// 15 × the peak |sample| of the channel in the frame.
ImportedScore importTactileWav(const std::string& path, const HapticImportOptions& options);
/// Apple AHAP (JSON text).
ImportedScore importAhap(std::string_view json, const std::string& source, const HapticImportOptions& options);
/// Meta Haptics Studio `.haptic` (Lofelt data model v1, JSON text).
ImportedScore importMetaHaptic(std::string_view json, const std::string& source, const HapticImportOptions& options);

/// bHaptics `.tact` (Designer JSON), the forearm device (docs/FORMATS.md, "bHaptics .tact"):
/// Tactosy index i (x = (i mod 3)/2, y = ⌊i/3⌋) → our column (mirrored for ForearmL), y = 0 →
/// the wrist row, y = 1 → the elbow row; level = 15 × intensity; fades linear; path points
/// spread bilinearly over the 3 × 3 (column 2x, row 2y); overlaps: the louder.
ImportedScore importTact(std::string_view json, const std::string& source, const HapticImportOptions& options);

/// MPEG haptics `.hjif` (ISO/IEC 23090-31, docs/FORMATS.md "MPEG haptics .hjif"): every
/// Vibrotactile channel's amplitude envelope as the reference software synthesises it, per
/// `frameSeconds` frame, level = 15 x envelope on the channel's motors (the loudest channel on a
/// shared motor).
ImportedScore importHjif(std::string_view json, const std::string& source, const HapticImportOptions& options);
/// The default motors of a channel: with actuator_resolution and actuator_target, the targets on
/// the 3 x 3 grid (X = column from the left, Y = row from the wrist; a 3 x 3 or 3 x 4 resolution
/// as is, another spread in proportion); otherwise every motor of the grid (`gridMotors`).
std::uint16_t hjifDefaultMotors(const hjif::Channel& channel, int gridMotors) noexcept;
/// `--tactile-hjif`: the motors as an .hjif file (hjif::write; docs/FORMATS.md).
std::string exportHjif(const std::vector<core::TactileRow>& rows, int motors, const std::string& project);

/// By extension: .score (parsed as is), .mid/.midi, .wav, .ahap, .haptic, .tact, .hjif. InputError for an
/// unknown extension, naming the ones known.
ImportedScore importScoreFile(const std::string& path, const MidiImportOptions& midi = {}, const HapticImportOptions& haptic = {});
/// importScoreFile(path).score: what `--score FILE` plays for a file of any of those formats.
tactile::Score loadAnyScore(const std::string& path);
/// Whether `path` ends with an extension importScoreFile() knows (case-insensitive).
bool isImportableScorePath(const std::string& path) noexcept;

/// Writes the motors as a multichannel WAV (docs/FORMATS.md): rows of 0..15 levels, each held
/// until the next row's time; channel k = motor k at amplitude level/15 of a `carrierHz` sine.
/// Rendered by the tactor renderer (Tactors/TactorRenderer.h) as the voice-coil model.
void writeTactileWav(const std::string& path, const std::vector<core::TactileRow>& rows, int motors, double sampleRate,
                     double carrierHz = 150.0, bool float32 = false);
/// The same with any actuator model, channel map and calibration gains (`render --tactile-wav`
/// with `--tactor-model`, `--tactor-map`, `--tactor-gain`): exactly what the live output plays.
/// `sound`: the scene's own sound (mono, sample 0 = the first row's time) for a voice-coil model
/// that is handed it (TactorParams::voiceCoilSound, `--tactor-sound`).
void writeTactileWav(const std::string& path, const std::vector<core::TactileRow>& rows, const tactors::TactorParams& params,
                     const tactors::ChannelMap& map, const tactors::TactorGains& gains, double sampleRate, bool float32 = false,
                     const std::vector<float>* sound = nullptr);

/// The one actuator an AHAP or `.haptic` file describes, from motor rows (docs/FORMATS.md,
/// "Out: AHAP and .haptic"): at each row, the largest level among `motors` (bit i = motor index
/// i), held until the next row's time; the last row is held 5 ms when it is not all-off. Times
/// start at the first row. A file for one motor set; several sets → several files.
struct ActuatorRun {
    double start = 0.0;      ///< s from the first row
    double duration = 0.0;   ///< s
    int level = 0;           ///< 1..15 (runs of level 0 are gaps)
};
std::vector<ActuatorRun> actuatorRuns(const std::vector<core::TactileRow>& rows, std::uint16_t motors);

/// Apple AHAP text: one HapticContinuous event per run of equal level (split at Core Haptics'
/// 30 s limit of a continuous event), HapticIntensity = level/15, no sharpness (an ERM motor has
/// none), Version 1.0 and Metadata {Project, Description}.
std::string exportAhap(const std::vector<core::TactileRow>& rows, std::uint16_t motors, const std::string& project);
/// Meta Haptics Studio `.haptic` text (Lofelt data model 1.0.0): the amplitude envelope as steps
/// (two breakpoints at each change: the old and the new amplitude, level/15), no frequency
/// envelope, no emphasis.
std::string exportMetaHaptic(const std::vector<core::TactileRow>& rows, std::uint16_t motors, const std::string& project);
/// bHaptics `.tact` text for ForearmR (docs/FORMATS.md): one effect per run of equal packets;
/// the wrist and elbow rows in dot mode (Tactosy indices 0-2 and 3-5, intensity level/15), a
/// middle-row motor as a still path point at (column/2, 0.5); times in whole ms from the first row.
std::string exportTact(const std::vector<core::TactileRow>& rows, const std::string& project);

} // namespace armadillo::formats
