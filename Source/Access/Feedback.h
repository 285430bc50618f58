#pragma once
// The answer's feedback felt on the arm (issue 26), shared by the CLI's guided training
// (Cli/GuidedTraining.cpp) and the app's Training panel (a deafblind reader's only channel):
//   "right": all nine motors hum softly together (0.4 s, level 4, soft start);
//   "wrong": the two outer columns buzz three times (0.1 s on, 0.1 s off) at the reading level.
// Distinct in place (all nine vs the outer columns), rhythm (one hum vs three buzzes) and level.
#include "Access/TactilePlayer.h"
#include "Braille/Sensations.h"
#include <string>
#include <vector>

namespace armadillo::access {

inline constexpr braille::MotorSet kUndersideMotors = braille::motorBit(0, 1) | braille::motorBit(1, 1) | braille::motorBit(2, 1);
inline constexpr braille::MotorSet kAllNineMotors = 0x1FF;
inline constexpr braille::MotorSet kOuterMotors = kAllNineMotors & ~kUndersideMotors;

/// The segments of the sensation; `level` is the reading level (the "wrong" buzz's level).
std::vector<TactileSegment> feedbackSensation(bool right, float level);
/// Seconds of stillness after it before the next cue.
inline double feedbackPause(bool right) noexcept { return right ? 0.3 : 0.6; }

/// Passive drawing (docs/BRAILLE.md: 0.4 s on, 0.2 s between rows, 0.5 s between letters, a
/// word gap as the underside line, 1.2 s) of `text` from `at` s on: the segments, and the
/// drawing's end (s, the last gap included) in `end`. At most `maxSegments` (a TactilePlayer
/// sequence holds 127): whole units only, the rest left out.
std::vector<TactileSegment> drawnText(const std::string& text, int grade, braille::DisplayMethod method, float level, double at,
                                      double& end, std::size_t maxSegments = 120);
/// The whole answer feedback of a deafblind reader's training, as one sequence: the sensation,
/// its pause, then (when wrong and `again` is not empty) `again` drawn (Grade 1, rows) and half a
/// second of stillness, then the "next" cue: the reader feels when the next trial may begin.
/// `again` must be letters and spaces (anything else is not drawn). The app's §4.4.1 Training
/// panel plays it (Plugin/PluginProcessor.cpp armFeedback), as the CLI's --arm-only does in steps.
std::vector<TactileSegment> feedbackSequence(bool right, const std::string& again, float level);
/// "A trial begins": the underside line swept wrist → elbow (0.3 s).
std::vector<TactileSegment> nextCue(float level, double at = 0.0);
/// "Your turn": the underside line tapped twice (0.34 s).
std::vector<TactileSegment> yourTurnCue(float level, double at = 0.0);

} // namespace armadillo::access
