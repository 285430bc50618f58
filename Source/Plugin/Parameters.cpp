#include "Plugin/Parameters.h"
#include "Engine/Engine.h"
#include <set>

namespace armadillo::plugin {

const juce::StringArray& sourceChoiceNames()
{
    static const juce::StringArray names {"device", "simulator", "OSC", "host automation"};
    return names;
}

SceneParameterTable querySceneParameters()
{
    SceneParameterTable table;
    std::set<std::string> taken {ParamIds::elevation, ParamIds::azimuth, ParamIds::roll, ParamIds::source,
                                 ParamIds::scene};
    for (const char* id : ParamIds::macros) taken.insert(id);
    for (const auto& name : engine::sceneNames()) {
        SceneParameterTable::Entry entry;
        entry.scene = name;
        try {
            entry.specs = engine::createScene(name)->parameters();
            entry.available = true;
        } catch (const std::exception& e) {
            entry.reason = e.what();
        }
        for (const auto& spec : entry.specs)
            entry.exposed.push_back(! spec.id.empty() && taken.insert(spec.id).second);
        table.scenes.push_back(std::move(entry));
    }
    return table;
}

namespace {

juce::String withUnit(float value, const std::string& unit, int decimals)
{
    auto text = juce::String(value, decimals);
    return unit.empty() ? text : text + " " + juce::String(unit);
}

std::unique_ptr<juce::RangedAudioParameter> makeSceneParameter(const std::string& sceneName, const core::ParamSpec& spec)
{
    const juce::ParameterID id {juce::String(spec.id), kParameterVersion};
    const auto name = juce::String(sceneName) + ": " + juce::String(spec.name.empty() ? spec.id : spec.name);
    if (! spec.choices.empty()) {
        juce::StringArray choices;
        for (const auto& c : spec.choices) choices.add(juce::String(c));
        const int def = juce::jlimit(0, choices.size() - 1, juce::roundToInt(spec.defaultValue));
        return std::make_unique<juce::AudioParameterChoice>(id, name, choices, def);
    }
    const float lo = std::min(spec.min, spec.max);
    const float hi = std::max(spec.max, lo + 1.0e-6f);
    const float def = juce::jlimit(lo, hi, spec.defaultValue);
    const auto unit = spec.unit;
    auto attributes = juce::AudioParameterFloatAttributes()
                          .withLabel(juce::String(unit))
                          .withStringFromValueFunction([unit](float v, int) { return withUnit(v, unit, 2); });
    return std::make_unique<juce::AudioParameterFloat>(id, name, juce::NormalisableRange<float>(lo, hi), def,
                                                       attributes);
}

} // namespace

juce::AudioProcessorValueTreeState::ParameterLayout createParameterLayout(const SceneParameterTable& table)
{
    using juce::AudioParameterChoice;
    using juce::AudioParameterFloat;
    using juce::AudioParameterFloatAttributes;
    using juce::NormalisableRange;
    juce::AudioProcessorValueTreeState::ParameterLayout layout;

    auto degrees = [](int decimals) {
        return AudioParameterFloatAttributes()
            .withLabel("deg")
            .withStringFromValueFunction([decimals](float v, int) { return juce::String(v, decimals) + juce::String(L"\u00b0"); })
            .withValueFromStringFunction([](const juce::String& s) { return s.retainCharacters("-0123456789.").getFloatValue(); });
    };
    // Orientation: INTERFACES.md "Pose". Fine steps so recorded movement is not quantised.
    layout.add(std::make_unique<AudioParameterFloat>(juce::ParameterID {ParamIds::elevation, kParameterVersion},
                                                     "Elevation", NormalisableRange<float>(-90.0f, 90.0f), 0.0f,
                                                     degrees(1)));
    layout.add(std::make_unique<AudioParameterFloat>(juce::ParameterID {ParamIds::azimuth, kParameterVersion},
                                                     "Azimuth", NormalisableRange<float>(0.0f, 360.0f), 0.0f,
                                                     degrees(1)));
    layout.add(std::make_unique<AudioParameterFloat>(juce::ParameterID {ParamIds::roll, kParameterVersion}, "Roll",
                                                     NormalisableRange<float>(-180.0f, 180.0f), 0.0f, degrees(1)));
    layout.add(std::make_unique<AudioParameterChoice>(juce::ParameterID {ParamIds::source, kParameterVersion},
                                                      "Source", sourceChoiceNames(),
                                                      static_cast<int>(SourceKind::Simulator)));
    juce::StringArray scenes;
    for (const auto& entry : table.scenes) scenes.add(juce::String(entry.scene));
    const int theremin = std::max(0, scenes.indexOf("theremin"));
    layout.add(std::make_unique<AudioParameterChoice>(juce::ParameterID {ParamIds::scene, kParameterVersion},
                                                      "Scene", scenes, theremin));

    for (const auto& entry : table.scenes) {
        if (entry.specs.empty()) continue;
        auto group = std::make_unique<juce::AudioProcessorParameterGroup>(
            juce::String(entry.scene), juce::String(entry.scene), " | ");
        for (std::size_t i = 0; i < entry.specs.size(); ++i)
            if (entry.exposed[i]) group->addChild(makeSceneParameter(entry.scene, entry.specs[i]));
        layout.add(std::move(group));
    }

    // Macros: generic outputs of the mapping (docs/PLUGIN.md "Macro parameters"), written by the
    // processor with change gestures so a DAW records them or routes them to other plugins. Last,
    // so every parameter above keeps the index it had before they existed.
    auto macros = std::make_unique<juce::AudioProcessorParameterGroup>("macros", "Macros", " | ");
    for (int i = 0; i < ParamIds::kMacroCount; ++i)
        macros->addChild(std::make_unique<AudioParameterFloat>(
            juce::ParameterID {ParamIds::macros[i], kParameterVersion}, "Macro " + juce::String(i + 1),
            NormalisableRange<float>(0.0f, 1.0f), 0.0f,
            AudioParameterFloatAttributes().withStringFromValueFunction([](float v, int) { return juce::String(v, 3); })));
    layout.add(std::move(macros));
    return layout;
}

} // namespace armadillo::plugin
