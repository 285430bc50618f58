#pragma once
// The answer's feedback felt on the arm (issue 26), shared by the CLI's guided training
// (Cli/GuidedTraining.cpp) and the app's Training panel (a deafblind reader's only channel):
//   "right": all nine motors hum softly together (0.4 s, level 4, soft start);
//   "wrong": the two outer columns buzz three times (0.1 s on, 0.1 s off) at the reading level.
// Distinct in place (all nine vs the outer columns), rhythm (one hum vs three buzzes) and level.
#include "Access/TactilePlayer.h"
#include "Braille/Sensations.h"
#include <vector>

namespace armadillo::access {

inline constexpr braille::MotorSet kUndersideMotors = braille::motorBit(0, 1) | braille::motorBit(1, 1) | braille::motorBit(2, 1);
inline constexpr braille::MotorSet kAllNineMotors = 0x1FF;
inline constexpr braille::MotorSet kOuterMotors = kAllNineMotors & ~kUndersideMotors;

/// The segments of the sensation; `level` is the reading level (the "wrong" buzz's level).
std::vector<TactileSegment> feedbackSensation(bool right, float level);
/// Seconds of stillness after it before the next cue.
inline double feedbackPause(bool right) noexcept { return right ? 0.3 : 0.6; }

} // namespace armadillo::access
