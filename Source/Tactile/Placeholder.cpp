// Placeholder factory until the score player lands (nullptr = "not built yet").
#include "Tactile/ScoreScene.h"
namespace armadillo {
std::unique_ptr<Scene> makeScoreScene() { return nullptr; }
} // namespace armadillo
