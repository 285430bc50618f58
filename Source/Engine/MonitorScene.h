#pragma once
#include "Core/Scene.h"
#include <memory>

namespace armadillo::engine {
/// "monitor": no sound, motors off — for recording sessions and testing the link.
std::unique_ptr<core::Scene> makeMonitorScene();
} // namespace armadillo::engine
