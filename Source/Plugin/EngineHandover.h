#pragma once
// Engines for the plugin: built on the message thread (a scene, text, score, arm side or sample
// rate change) and handed to the control side lock-free through live::ControlLoop. The engine
// the control side gives up is deleted here, never on the audio thread.
//
// Threads: every method runs on the message thread or in prepareToPlay, under this class's
// builder lock. The audio thread never takes that lock: it only swaps the offered engine in at the
// start of a control step (ControlLoop::tick). install() replaces the engine outright and needs
// the control token (the caller proves the control side is not running).
#include "Live/Step/ControlLoop.h"
#include "Navigation/NavigationScene.h"
#include "Live/Session/BlockInstrument.h"
#include "Plugin/Parameters.h"
#include <juce_audio_processors/juce_audio_processors.h>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace armadillo::plugin {

/// What an engine is built for; a different request means a new engine.
struct EngineRequest {
    int scene = 0;
    double sampleRate = 48000.0;
    bool left = false;
    bool backMotors = false;
    bool twoArms = false;       ///< the left arm is on (EngineConfig::twoArms)
    std::string text, score;
    std::string touchProfile;   ///< the reader's touch profile JSON ("" = none): EngineConfig::motorGain
    /// audio-touch's stems (SceneConfig::stems: the enabled sidechain buses' presets, in bus
    /// order); empty for every other scene and when no sidechain bus is enabled.
    std::vector<std::string> stems;
    /// Counts the states loaded (setStateInformation): a session reopened starts from a fresh
    /// engine and arm, not from what the instance played before its state came (issue 32).
    std::uint64_t session = 0;
    /// A walk in the app (NavigationRig.h, issue 34): while both are set, the engine runs the
    /// navigation scene for this route and link instead of `scene` (compared by identity).
    std::shared_ptr<const navigation::Route> route;
    std::shared_ptr<navigation::NavigationLink> navigation;
    bool operator==(const EngineRequest&) const = default;
};

class EngineHandover {
public:
    static constexpr double kControlRateHz = 200.0;   ///< thesis: the 2005 system ran at ~200 updates/s

    /// `status` receives messages for the user (a scene that cannot start and its fallback), and
    /// "" when a requested scene started, so the owner can take down a message that no longer holds.
    EngineHandover(live::ControlLoop& loop, const SceneParameterTable& table, juce::AudioProcessorValueTreeState& parameters,
                   std::function<void(const juce::String&)> status);

    /// Builds an engine for `request` and installs it at once (constructor, prepareToPlay) through
    /// the instrument (BlockInstrument::install: the control token held while it swaps).
    void install(const EngineRequest& request, live::BlockInstrument& instrument);
    /// Timer: deletes the engine the control side gave up, and offers a new one when `request`
    /// differs from what the newest engine was built for (one hand-over in flight at a time).
    void update(const EngineRequest& request);
    /// Runs `use` with the newest engine (pending, else active) under the builder lock, so it
    /// cannot be deleted meanwhile. False (not called) when there is none. Never keep the
    /// reference: `slot.generation` changes with every new engine.
    bool withNewest(const std::function<void(live::EngineSlot& slot)>& use);
    /// A failure of the newest engine's scene not reported before: its text, else "".
    juce::String takeNewFailure();

private:
    std::unique_ptr<live::EngineSlot> build(const EngineRequest& request);

    live::ControlLoop& loop_;
    const SceneParameterTable& table_;
    juce::AudioProcessorValueTreeState& parameters_;
    std::function<void(const juce::String&)> status_;
    std::mutex mutex_;                  // the builder lock: message thread vs prepareToPlay
    EngineRequest built_ {};            // under mutex_: what the newest engine was built for
    std::uint64_t generation_ = 0;      // under mutex_: engines built
    std::uint64_t reportedFailure_ = 0; // under mutex_: generation whose failure was reported
};

} // namespace armadillo::plugin
