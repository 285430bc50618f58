#pragma once
// `armadillo braille --train --adaptive`: training that adapts and remembers, for a reader alone
// (issue 26). See GuidedTraining.cpp and docs/BRAILLE.md "Adaptive training".
#include "Cli/CommandLine.h"
#include <vector>

namespace armadillo::cli {

/// Options `braille` accepts for the adaptive training and the report.
std::vector<OptionSpec> guidedTrainingOptionSpecs();
int runGuidedTraining(const CommandLine& cl);
int printProgressReport(const CommandLine& cl);

} // namespace armadillo::cli
