#pragma once
#include "Core/Scene.h"
#include <memory>

namespace armadillo {
/// "monitor": no sound, motors off — for recording sessions and testing the link.
std::unique_ptr<Scene> makeMonitorScene();
} // namespace armadillo
