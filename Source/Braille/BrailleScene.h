#pragma once
// The Arm Braille scene (thesis §4.2–4.4): SceneConfig::text is read by rolling the arm.
// nullptr = not built in this version.
#include "Core/Scene.h"
#include <memory>

namespace armadillo {
std::unique_ptr<Scene> makeBrailleScene();   ///< "braille"
} // namespace armadillo
