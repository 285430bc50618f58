// Placeholder factory until Arm Braille lands (nullptr = "not built yet").
#include "Braille/BrailleScene.h"
namespace armadillo {
std::unique_ptr<Scene> makeBrailleScene() { return nullptr; }
} // namespace armadillo
