#include "Plugin/FactoryPresets.h"
#include "Plugin/Parameters.h"
#include "Engine/Engine.h"
#include <cstring>

namespace armadillo::plugin {

const std::vector<FactoryPreset>& factoryPresets()
{
    static const std::vector<FactoryPreset> presets {
        {"Theremin: fretted major (thesis)", "theremin", {}},
        {"Theremin: minor pentatonic, snapped", "theremin",
         {{"theremin.scale", 6.0f}, {"theremin.snap", 80.0f}, {"theremin.glide", 60.0f}}},
        {"Theremin: two octaves, slow glide", "theremin", {{"theremin.range", 24.0f}, {"theremin.glide", 250.0f}}},
        {"Cymbal (thesis)", "cymbal", {}},
        {"Control panel", "panel", {}},
        {"Sound design", "sound-design", {}},
        {"Compass: north, fine", "compass", {{"compass.target", 0.0f}, {"compass.tolerance", 3.0f}}},
        {"Braille: active reading", "braille", {{"braille.mode", 0.0f}}},
        {"Braille: passive reading", "braille", {{"braille.mode", 1.0f}}},
        {"Braille: training", "braille", {{"braille.mode", 2.0f}}},
        {"Tactile score", "score", {}},
        {"Audio to touch", "audio-touch", {}},
        {"Monitor (no sound, no motors)", "monitor", {}},
    };
    return presets;
}

bool applyFactoryPreset(int index, juce::AudioProcessorValueTreeState& parameters)
{
    const auto& presets = factoryPresets();
    if (index < 0 || index >= static_cast<int>(presets.size())) return false;
    const FactoryPreset& preset = presets[static_cast<std::size_t>(index)];
    const auto& names = engine::sceneNames();
    int sceneIndex = -1;
    for (std::size_t i = 0; i < names.size(); ++i)
        if (names[i] == preset.scene) sceneIndex = static_cast<int>(i);
    auto* scene = parameters.getParameter(ParamIds::scene);
    if (sceneIndex < 0 || scene == nullptr) return false;
    for (const auto& [id, value] : preset.values)
        if (parameters.getParameter(id) == nullptr) return false;

    auto set = [](juce::RangedAudioParameter& p, float normalised) {
        p.beginChangeGesture();
        p.setValueNotifyingHost(normalised);
        p.endChangeGesture();
    };
    const std::string prefix = std::string(preset.scene) + ".";
    for (auto* p : parameters.processor.getParameters()) {
        auto* ranged = dynamic_cast<juce::RangedAudioParameter*>(p);
        if (ranged != nullptr && ranged->getParameterID().startsWith(juce::String(prefix)))
            set(*ranged, ranged->getDefaultValue());
    }
    for (const auto& [id, value] : preset.values) {
        auto* p = parameters.getParameter(id);
        set(*p, p->convertTo0to1(value));
    }
    set(*scene, scene->convertTo0to1(static_cast<float>(sceneIndex)));
    return true;
}

} // namespace armadillo::plugin
