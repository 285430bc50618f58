#pragma once
// Factory presets: one or two per scene, offered to hosts as the plugin's programs (VST3 program
// list, LV2 presets written by JUCE from the programs, the standalone's program menu).
//
// Threads: the table is constant. Applying a preset sets parameters with host notification, so
// it happens on the message thread only: the processor's setCurrentProgram may be called by a
// host's audio thread (JUCE 7.0.5's VST3 wrapper applies program changes inside process()), and
// there it only records the request (an atomic) for the message thread's timer.
#include <juce_audio_processors/juce_audio_processors.h>
#include <utility>
#include <vector>

namespace armadillo::plugin {

struct FactoryPreset {
    const char* name;
    const char* scene;                                   ///< INTERFACES.md scene name
    std::vector<std::pair<const char*, float>> values;   ///< parameter id → value in its own unit
};

/// Every factory preset, in program order (program 0 is the first). Never empty.
const std::vector<FactoryPreset>& factoryPresets();

/// Message thread: every scene parameter of the preset's scene back to its default, then the
/// preset's values, the scene choice last; orientation and source are left as they are (they are
/// the performer's, not the sound's). Returns false (nothing changed) for a bad index or a
/// preset naming a parameter or scene this build does not have.
bool applyFactoryPreset(int index, juce::AudioProcessorValueTreeState& parameters);

} // namespace armadillo::plugin
