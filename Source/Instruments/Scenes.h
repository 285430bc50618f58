#pragma once
// Factories of the instrument scenes (thesis §3.4–3.7, §4.1).
#include "Core/Scene.h"
#include <memory>

namespace armadillo::instruments {
std::unique_ptr<core::Scene> makeThereminScene(); ///< "theremin"     — fretted theremin, thesis §3.5
std::unique_ptr<core::Scene> makeCymbalScene(); ///< "cymbal"       — virtual crash cymbal, thesis §3.6
std::unique_ptr<core::Scene> makePanelScene();  ///< "panel"        — virtual control panel, thesis §3.4
std::unique_ptr<core::Scene> makeSoundDesignScene(); ///< "sound-design" — gesture sound design, thesis §3.7
std::unique_ptr<core::Scene> makeCompassScene(); ///< "compass"      — tactile compass, thesis §4.1
std::unique_ptr<core::Scene> makeAudioTouchScene(); ///< "audio-touch"  — any audio in, felt on the arm (bands → rows)
std::unique_ptr<core::Scene> makeThereminDuoScene(); ///< "theremin-duo" — a theremin for two arms (docs/STAGE.md)
std::unique_ptr<core::Scene> makePatchScene(); ///< "patch" — the grid's targets set by a front end's patch (Core/MotorTargets.h), issue 46
std::unique_ptr<core::Scene> makeLayeredKeyboardScene(); ///< "layered-keyboard" — the arm plays over a real instrument, thesis §5.2
} // namespace armadillo::instruments
