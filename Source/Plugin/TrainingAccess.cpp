#include "Plugin/TrainingAccess.h"
#include "Braille/BrailleScene.h"
#include "Engine/Engine.h"

namespace armadillo::plugin {

namespace {
braille::BrailleSceneControls* controlsOf(live::EngineSlot& slot) noexcept
{
    return dynamic_cast<braille::BrailleSceneControls*>(&slot.engine->scene());
}
} // namespace

bool TrainingAccess::with(const std::function<void(braille::BrailleSceneControls&, std::uint64_t)>& use)
{
    bool called = false;
    engines_.withNewest([&](live::EngineSlot& slot) {
        if (auto* controls = controlsOf(slot)) {
            use(*controls, slot.generation);
            called = true;
        }
    });
    return called;
}

bool TrainingAccess::copyLog(std::uint64_t generation, std::string& csv, juce::String& why)
{
    why = "The braille scene was restarted since (scene, text or audio settings changed); its training log is gone.";
    bool copied = false;
    engines_.withNewest([&](live::EngineSlot& slot) {
        if (slot.generation != generation) return;
        auto* controls = controlsOf(slot);
        if (controls == nullptr) {
            why = "The braille scene is not running.";
            return;
        }
        try {
            csv = controls->trainingLogCsv();
            why.clear();
            copied = true;
        } catch (const std::exception& e) {
            why = "Cannot copy the training log: " + juce::String(e.what());
        }
    });
    return copied;
}

void TrainingAccess::collect()
{
    engines_.withNewest([](live::EngineSlot& slot) {
        if (auto* controls = controlsOf(slot)) controls->collectTrainingLog();
    });
}

} // namespace armadillo::plugin
