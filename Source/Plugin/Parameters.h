#pragma once
// The plugin's one parameter layout (STYLE.md convention 7). IDs are stable contracts
// (INTERFACES.md "Plugin parameters"): hosts store automation under them, and LV2 uses them as
// property symbols. The version hint is bumped only for a parameter whose meaning changes.
#include "Core/Scene.h"
#include "Live/Step/ControlLoop.h"
#include "Live/Step/SceneParameters.h"
#include <juce_audio_processors/juce_audio_processors.h>
#include <string>
#include <vector>

namespace armadillo::plugin {

namespace ParamIds {
inline constexpr const char* elevation = "elevation";   ///< deg, −90…90
inline constexpr const char* azimuth = "azimuth";       ///< deg, 0…360
inline constexpr const char* roll = "roll";             ///< deg, −180…180
inline constexpr const char* source = "source";         ///< SourceKind
inline constexpr const char* scene = "scene";           ///< index into sceneNames()
/// The mapping's macro destinations (docs/MAPPING.md): `macro1`…`macro8`, 0…1, last in the
/// layout (after every scene's parameters) so the existing parameters keep their indices.
inline constexpr int kMacroCount = mapping::kMacroCount;
inline constexpr const char* macros[kMacroCount] {"macro1", "macro2", "macro3", "macro4",
                                                  "macro5", "macro6", "macro7", "macro8"};
} // namespace ParamIds

/// Version hint of every parameter in this layout (JUCE ParameterID).
inline constexpr int kParameterVersion = 1;

/// Where the arm's orientation comes from. The order is the `source` choice order (a contract).
using SourceKind = live::SourceKind;   // Device, Simulator, Osc, HostAutomation (contract order)
const juce::StringArray& sourceChoiceNames();
using live::isLiveSource;

/// Every scene's own parameters, queried once from the scenes themselves (Live/Step/SceneParameters.h).
using live::SceneParameterTable;
live::SceneParameterTable querySceneParameters();

juce::AudioProcessorValueTreeState::ParameterLayout createParameterLayout(const SceneParameterTable& table);

} // namespace armadillo::plugin
