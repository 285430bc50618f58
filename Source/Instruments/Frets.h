#pragma once
// The fretted theremin's pitch map and frets (thesis §3.5.1–3.5.3), as plain functions and a
// small state machine that the scene and the tests share.
#include "Core/Types.h"
#include "Tactile/Hysteresis.h"
#include <array>
#include <string>
#include <vector>

namespace armadillo::instruments {

/// Scales the frets can follow: semitone steps from the root within one octave (root = 0).
enum class FretScale : int { Major, NaturalMinor, HarmonicMinor, Dorian, Mixolydian, MajorPentatonic, MinorPentatonic };
const std::vector<std::string>& fretScaleNames();     ///< choice labels, in enum order
const std::vector<int>& fretScaleSteps(FretScale scale);   ///< e.g. major {0,2,4,5,7,9,11}
const std::vector<std::string>& pitchClassNames();    ///< "A", "A#", "B", … "G#" (root choice, A = 0)

/// Pitch map of thesis §3.5.1: e semitones, linear in y = sin(elevation), the Y component of
/// the forearm axis; f = base·2^(e/12).
struct PitchMapParams {
    double baseHz = 220.0;             ///< Hz at the bottom elevation
    double rangeSemitones = 12.0;      ///< semitones from the bottom to the top elevation
    double bottomElevationDeg = -45.0; ///< deg: elevation that plays baseHz
    double topElevationDeg = 45.0;     ///< deg: elevation that plays base·2^(range/12)
};
inline constexpr PitchMapParams kDefaultPitchMap {};

/// Semitones above base for an axis Y component (sin elevation), any value in −1..1.
double semitonesForAxisY(const PitchMapParams& p, double axisY) noexcept;
double frequencyForSemitones(const PitchMapParams& p, double semitones) noexcept;

/// Fret positions: the scale notes (root given as a pitch class, A = 0) that lie inside
/// [0, range] semitones above base, lowest first, at most kMaxFrets (the theremin's eight motors).
inline constexpr int kMaxFrets = 8;
/// Up to kMaxFrets values, lowest first: fret positions without a heap (the scene recomputes
/// them in control(), on the audio thread in the plugin, whenever a parameter is automated).
struct FretList {
    std::array<double, kMaxFrets> values {};
    int count = 0;
};
FretList fretSemitonesFixed(const PitchMapParams& p, FretScale scale, int rootPitchClass) noexcept;
std::vector<double> fretSemitones(const PitchMapParams& p, FretScale scale, int rootPitchClass);

/// Pitch snapping: moves `semitones` toward the nearest note of the scale by `amount` (0..1).
double snapToScale(double semitones, const PitchMapParams& p, FretScale scale, int rootPitchClass, double amount) noexcept;

/// The motor of fret i (thesis §3.5.2, ARMADILLO.md §7): elbow row A B C#, middle D E F#,
/// wrist row G# A; rising pitch moves toward the wrist; the wrist-row right motor is unused.
int fretMotor(int fretIndex) noexcept;

/// Which fret is felt (thesis §3.5.2–3.5.3). One Hysteresis per boundary between neighbouring
/// frets j−1 and j: it turns on at f_j·(1 − a) on the way up (the fret sits a% lower when
/// approached from below) and off at f_{j−1}·(1 + a) on the way down (a% higher from above).
/// The felt fret is the number of boundaries that are on. Between two frets nothing changes:
/// the last fret reached holds.
class FretTracker {
public:
    /// frequencies in Hz, ascending; adjust = a (0.01 = the thesis's 1%).
    void configure(const std::vector<double>& fretHz, double adjust);
    /// The same from a fixed list (real-time).
    void configure(const FretList& fretHz, double adjust) noexcept;
    /// Feeds the controller's frequency (Hz); returns the felt fret (0..count−1), −1 if no frets.
    int update(double frequencyHz) noexcept;
    int current() const noexcept { return current_; }
    int count() const noexcept { return count_; }
    /// Forgets the history: the next update picks the fret at or below the frequency.
    void reset() noexcept { primed_ = false; }

private:
    std::array<tactile::Hysteresis, kMaxFrets> boundaries_ {
        tactile::Hysteresis(0, 0), tactile::Hysteresis(0, 0), tactile::Hysteresis(0, 0), tactile::Hysteresis(0, 0),
        tactile::Hysteresis(0, 0), tactile::Hysteresis(0, 0), tactile::Hysteresis(0, 0), tactile::Hysteresis(0, 0)};
    std::array<double, kMaxFrets> hz_ {};
    int count_ = 0;
    int current_ = -1;
    bool primed_ = false;
};

} // namespace armadillo::instruments
