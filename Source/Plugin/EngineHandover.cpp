#include "Plugin/EngineHandover.h"
#include "Engine/Engine.h"
#include "Link/TouchProfile.h"
#include <limits>

namespace armadillo::plugin {

EngineHandover::EngineHandover(live::ControlLoop& loop, const SceneParameterTable& table,
                               juce::AudioProcessorValueTreeState& parameters, std::function<void(const juce::String&)> status)
    : loop_(loop), table_(table), parameters_(parameters), status_(std::move(status))
{
}

std::unique_ptr<live::EngineSlot> EngineHandover::build(const EngineRequest& request)
{
    auto slot = std::make_unique<live::EngineSlot>();
    slot->generation = ++generation_;
    engine::EngineConfig config;
    const auto& names = engine::sceneNames();
    config.scene = names.empty() ? std::string("monitor") : names[static_cast<std::size_t>(request.scene) % names.size()];
    config.motorCount = request.backMotors ? core::kGridMotors + core::kBackMotors : core::kGridMotors;
    config.sceneConfig.sampleRate = request.sampleRate;
    config.sceneConfig.controlRateHz = kControlRateHz;
    config.sceneConfig.seed = 1;
    config.sceneConfig.side = request.left ? core::ArmSide::Left : core::ArmSide::Right;
    config.twoArms = request.twoArms;   // issue 28: the left arm's own tactile engine and safety stage
    config.sceneConfig.text = request.text;
    config.sceneConfig.score = request.score;
    config.sceneConfig.stems = request.stems;   // audio-touch: the sidechain buses, one stem each
    // The reader's touch profile scales each motor (TactileEngine, before the SafetyStage), so
    // every scene gets it; the settings only keep a profile that parses (PluginState.cpp).
    if (! request.touchProfile.empty()) {
        try {
            config.motorGain = link::touchProfileGains(link::parseTouchProfile(request.touchProfile, "the touch profile setting"));
        } catch (const std::exception& e) {
            status_("The touch profile is not used: " + juce::String(e.what()));
        }
    }
    // resourceDir stays empty: scores and word lists come from the user's folders or the copy
    // built into the core (Core/Resources.h), never from a path of the build machine.
    try {
        if (request.route != nullptr && request.navigation != nullptr) {   // a walk: the navigation scene
            config.scene = "navigation";
            slot->engine = std::make_unique<engine::Engine>(config, navigation::makeNavigationScene(*request.route, request.navigation));
        } else {
            slot->engine = std::make_unique<engine::Engine>(config);
        }
        status_({});   // the scene starts: an earlier "cannot start" no longer holds
    } catch (const std::exception& e) {
        status_("Scene \"" + juce::String(config.scene) + "\" cannot start (" + juce::String(e.what())
                + "); running \"monitor\" instead.");
        config.scene = "monitor";
        try {
            slot->engine = std::make_unique<engine::Engine>(config);
        } catch (const std::exception& e2) {
            status_("The engine cannot start: " + juce::String(e2.what()));
            return slot;
        }
    }
    slot->sceneName = config.scene;
    for (const auto& entry : table_.scenes) {
        if (entry.scene != config.scene) continue;
        for (std::size_t i = 0; i < entry.specs.size(); ++i)
            slot->params.push_back(entry.exposed[i] ? parameters_.getRawParameterValue(juce::String(entry.specs[i].id)) : nullptr);
    }
    slot->sent.assign(slot->params.size(), std::numeric_limits<float>::quiet_NaN());
    return slot;
}

void EngineHandover::install(const EngineRequest& request, live::BlockInstrument& instrument)
{
    std::lock_guard<std::mutex> lock(mutex_);
    instrument.install(build(request));   // between two idle steps; audio is stopped here
    built_ = request;
}

void EngineHandover::update(const EngineRequest& request)
{
    std::lock_guard<std::mutex> lock(mutex_);
    loop_.collect();   // the engine the control side gave up is deleted here, never on the audio thread
    if (request == built_) return;
    // Only one hand-over in flight, and the retired engine must be gone before the next one.
    if (! loop_.canOffer()) return;
    auto slot = build(request);
    if (loop_.offer(slot)) built_ = request;
}

bool EngineHandover::withNewest(const std::function<void(live::EngineSlot&)>& use)
{
    // Engines are deleted only under mutex_ (update, install), and the loop's newest engine is
    // either the active one or the pending one, never the retired one.
    std::lock_guard<std::mutex> lock(mutex_);
    auto* newest = loop_.newest();
    if (newest == nullptr || newest->engine == nullptr) return false;
    use(*newest);
    return true;
}

juce::String EngineHandover::takeNewFailure()
{
    std::lock_guard<std::mutex> lock(mutex_);
    auto* newest = loop_.newest();
    if (newest == nullptr || newest->engine == nullptr || ! newest->engine->failed() || reportedFailure_ == newest->generation)
        return {};
    reportedFailure_ = newest->generation;
    return "The scene \"" + juce::String(newest->sceneName) + "\" failed during a control update and was stopped (motors off): "
           + juce::String(newest->engine->failure()) + ". Choose the scene again to restart it.";
}

} // namespace armadillo::plugin
