// Scenes not built yet in this version (nullptr = the CLI says "not built yet").
#include "Instruments/Scenes.h"

namespace armadillo {
std::unique_ptr<Scene> makePanelScene() { return nullptr; }
std::unique_ptr<Scene> makeSoundDesignScene() { return nullptr; }
std::unique_ptr<Scene> makeCompassScene() { return nullptr; }
} // namespace armadillo
