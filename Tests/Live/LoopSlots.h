#pragma once
// An engine slot for live::ControlLoop tests: one scene at 48 kHz with the 200 Hz control rate,
// optionally built for two arms. Shared by the loop tests of both live executables.
#include "Live/Step/ControlLoop.h"
#include <memory>
#include <string>

namespace armadillo::test {

inline std::unique_ptr<live::EngineSlot> loopSlot(const std::string& scene, bool twoArms = false)
{
    engine::EngineConfig config;
    config.scene = scene;
    config.twoArms = twoArms;
    config.sceneConfig.sampleRate = 48000.0;
    config.sceneConfig.controlRateHz = 200.0;
    auto slot = std::make_unique<live::EngineSlot>();
    slot->engine = std::make_unique<engine::Engine>(config);
    slot->sceneName = config.scene;
    return slot;
}

} // namespace armadillo::test
