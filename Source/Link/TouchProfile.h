#pragma once
// A reader's touch profile (issue 26): the detection threshold of each of the nine motors,
// measured by `armadillo touch-profile` with the staircase of Tactile/Staircase.h, and a
// comfortable level. Scenes take it as per-motor gains (TactileConfig::motorGain) so that the
// reader feels every motor alike. File format (JSON, docs/INTERFACES.md "Touch profile"):
//   {"format": "armadillo-touch-profile", "version": 1,
//    "threshold": [t1, …, t9],      levels 1..15 of motors m1…m9 (the motor packet's order)
//    "felt": [true, …],             optional: false = not felt even at 15
//    "comfort": L, "comfort_motor": 5,   optional: the comfortable level measured on that motor
//    "arm": "right", "stimuli": N, "stimulus_seconds": S, "date": "…"}   optional, informative
// Only "threshold" is required; other keys are allowed (and ignored).
#include "Core/Types.h"
#include <array>
#include <string>
#include <string_view>

namespace armadillo::link {

inline constexpr int kProfileMotors = 9;

struct TouchProfile {
    std::array<int, kProfileMotors> threshold {};   ///< levels 1..15, m1…m9
    std::array<bool, kProfileMotors> felt {true, true, true, true, true, true, true, true, true};
    int comfort = 0;          ///< level; 0 = not measured
    int comfortMotor = 5;     ///< 1..9
    std::string arm;          ///< "right" / "left" / "" (informative)
    std::string date;         ///< ISO 8601, informative
    int stimuli = 0;          ///< how many stimuli the measurement took
    double stimulusSeconds = 0.0;   ///< s of stimulus time (stimuli and the pauses after them)
};

/// Parses the JSON above; InputError naming source, line and key.
TouchProfile parseTouchProfile(std::string_view json, const std::string& source);
/// Reads a file: IoError when unreadable, InputError when invalid.
TouchProfile loadTouchProfile(const std::string& path);
std::string touchProfileToJson(const TouchProfile& profile);
void saveTouchProfile(const std::string& path, const TouchProfile& profile);   ///< atomic

/// Gains per physical motor: gain_m = threshold_m / median threshold, clamped to 0.25..4, so a
/// level L is felt at about L / median above threshold on every motor (a motor twice as
/// insensitive is driven twice as hard). Motors 10… keep gain 1.
std::array<float, core::kMaxMotors> touchProfileGains(const TouchProfile& profile);

} // namespace armadillo::link
