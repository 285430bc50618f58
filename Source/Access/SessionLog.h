#pragma once
// The adaptive training's session log (docs/INTERFACES.md "braille --train --adaptive --log"):
// the columns of the §4.4.1 training log (Braille/Training.h) so one analysis reads both, with
// the events trial, row, word-gap, cue, answer, feedback, gesture and end. Shared by the CLI
// (Cli/GuidedTraining.cpp) and the app's, both through Procedures/AdaptiveTraining.cpp.
// Nothing moves in passive drawing: the posture and roll columns stay empty.
#include "Access/AdaptivePlan.h"
#include "Braille/Sensations.h"
#include <string>

namespace armadillo::access {

inline constexpr const char* kSessionLogHeader = "t,event,stage,trial,expected,prompt,posture,roll_deg,unit,step,motors,answer,correct\n";

/// One row. `trial` null: no stage/trial/expected; `unit` < 0: no unit/step; `correct` < 0: empty.
void appendSessionLogRow(std::string& log, double t, const char* event, const PlannedTrial* trial, int number, const std::string& prompt,
                         int unit, int step, braille::MotorSet motors, bool hasMotors, const std::string& answer, int correct);

} // namespace armadillo::access
