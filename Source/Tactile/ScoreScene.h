#pragma once
// The tactile-score scene (thesis §3.3): plays a score from Resources/Scores in sync with the
// host transport or its own clock.
#include "Core/Scene.h"
#include <memory>

namespace armadillo::tactile {
std::unique_ptr<core::Scene> makeScoreScene(); ///< "score" — SceneConfig::score names the score
} // namespace armadillo::tactile
