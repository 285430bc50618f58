#pragma once
// The plugin's host-visible parameters by name, for the benchmarks that host the built VST3
// (bench_plugin, bench_mapping_latency, bench_tactor_bus).
#include <juce_audio_processors/juce_audio_processors.h>

namespace armadillo::bench {

inline juce::AudioProcessorParameter* findParameter(juce::AudioPluginInstance& p, const juce::String& name)
{
    for (auto* param : p.getParameters())
        if (param->getName(100) == name) return param;
    return nullptr;
}

/// Sets a choice parameter to the choice whose text is `text`; false when it has none.
inline bool setChoice(juce::AudioProcessorParameter* p, const juce::String& text)
{
    const int steps = p->getNumSteps();
    for (int i = 0; i < steps; ++i) {
        const float v = static_cast<float>(i) / static_cast<float>(steps - 1);
        if (p->getText(v, 100) == text) {
            p->setValueNotifyingHost(v);
            return true;
        }
    }
    return false;
}

} // namespace armadillo::bench
