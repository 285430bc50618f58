#pragma once
// Braille training for the Training panel: answers, progress and the training log of the braille
// scene the newest engine runs (thesis §4.4).
//
// Threads: message thread only. Everything runs under the engine hand-over's builder lock (the
// engine cannot be deleted meanwhile; the audio thread never takes that lock). The scene's
// control step only queues fixed-size log records; their text is built here, never while the
// control token is held, so the audio thread never waits for a copy of the log.
#include "Plugin/EngineHandover.h"
#include <cstdint>
#include <functional>
#include <string>

namespace armadillo::braille {
class BrailleSceneControls;
}

namespace armadillo::plugin {

class TrainingAccess {
public:
    explicit TrainingAccess(EngineHandover& engines) : engines_(engines) {}

    /// Runs `use` with the training controls of the newest engine; false (not called) when that
    /// engine does not run the braille scene. Never keep the reference: `generation` changes with
    /// every new engine (scene, text, sample rate or arm change), and a new engine's training
    /// starts from its first trial.
    bool with(const std::function<void(braille::BrailleSceneControls&, std::uint64_t generation)>& use);
    /// A copy of the training log of engine `generation`. False with the reason when that engine
    /// is gone or runs another scene.
    bool copyLog(std::uint64_t generation, std::string& csv, juce::String& why);
    /// Timer: moves the newest braille scene's queued log records into its text log, so the
    /// queue never fills while no panel asks for the log.
    void collect();

private:
    EngineHandover& engines_;
};

} // namespace armadillo::plugin
