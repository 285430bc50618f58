// Placeholder factories until the instruments land (nullptr = "not built yet").
#include "Instruments/Scenes.h"
namespace armadillo {
std::unique_ptr<Scene> makeThereminScene() { return nullptr; }
std::unique_ptr<Scene> makeCymbalScene() { return nullptr; }
std::unique_ptr<Scene> makePanelScene() { return nullptr; }
std::unique_ptr<Scene> makeSoundDesignScene() { return nullptr; }
std::unique_ptr<Scene> makeCompassScene() { return nullptr; }
} // namespace armadillo
