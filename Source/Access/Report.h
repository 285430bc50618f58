#pragma once
// The progress report of a reader profile (`armadillo braille --report PROFILE.json`): accuracy
// per stage and per session, letters per minute, the confusion matrix of the letters, accuracy
// per display method, and where the reader stands against the published figures (docs/BRAILLE.md
// "Adaptive training"): a forearm study's 93 % with dots one at a time against 26 % together,
// UbiBraille's 82 % after 10 minutes, the thesis's letters above 95 % after about 25 minutes.
#include "Access/ReaderProfile.h"
#include <string>

namespace armadillo::access {

std::string progressReport(const ReaderProfile& profile);

} // namespace armadillo::access
