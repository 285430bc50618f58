#pragma once
// Hosting the built plugin binaries through JUCE's own hosting classes, as a DAW does (VST3 and
// LV2): loading, preparing, parameters by their host-visible names, rendering, the real-time
// guard around processBlock, and the plugin's own state document. Shared by the plugin host
// tests (PluginHostTests.cpp, MappingHostTests.cpp); nothing here links the plugin's code.
#include <catch2/catch.hpp>

#include <juce_audio_processors/juce_audio_processors.h>
#include <juce_events/juce_events.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <memory>
#include <vector>

#include "Common/RealtimeGuard.h"

namespace armadillo::test::host {

struct Hosted {
    std::unique_ptr<juce::AudioPluginInstance> plugin;
    std::map<juce::String, juce::AudioProcessorParameter*> byName;
    bool lv2 = false;
    juce::AudioProcessorParameter* param(const juce::String& name) const
    {
        auto it = byName.find(name);
        return it == byName.end() ? nullptr : it->second;
    }
};

constexpr double kRate = 48000.0;
constexpr int kBlock = 256;

inline void index(Hosted& h)
{
    h.byName.clear();
    for (auto* p : h.plugin->getParameters()) h.byName[p->getName(200)] = p;
}

inline Hosted loadVst3()
{
    juce::VST3PluginFormat format;
    juce::OwnedArray<juce::PluginDescription> types;
    format.findAllTypesForFile(types, ARMADILLO_VST3_PATH);
    REQUIRE(types.size() == 1);
    CHECK(types[0]->name == "ARMadillo");
    CHECK(types[0]->isInstrument);
    juce::String error;
    Hosted h;
    h.plugin = format.createInstanceFromDescription(*types[0], kRate, kBlock, error);
    INFO(error);
    REQUIRE(h.plugin != nullptr);
    index(h);
    return h;
}

inline juce::LV2PluginFormat& lv2Format()
{
    static juce::LV2PluginFormat format;   // one lilv world for the whole run
    return format;
}

inline Hosted loadLv2()
{
    auto& format = lv2Format();
    const auto bundle = juce::File(ARMADILLO_LV2_PATH);
    REQUIRE(bundle.isDirectory());
    format.searchPathsForPlugins(juce::FileSearchPath(bundle.getParentDirectory().getFullPathName()), false, false);
    juce::OwnedArray<juce::PluginDescription> types;
    format.findAllTypesForFile(types, "urn:armadillo:armadillo");
    REQUIRE(types.size() == 1);
    juce::String error;
    Hosted h;
    h.lv2 = true;
    h.plugin = format.createInstanceFromDescription(*types[0], kRate, kBlock, error);
    INFO(error);
    REQUIRE(h.plugin != nullptr);
    index(h);
    return h;
}

/// `withInput`: the test needs the main input (the track the plugin listens to).
inline void prepare(Hosted& h, bool withInput = false)
{
    // The LV2 and the VST3 have a stereo input (docs/PLUGIN.md, "Audio input"). The blocks carry
    // two channels, in place.
    const int inputs = h.plugin->getBusesLayout().getMainInputChannels();
    if (withInput) REQUIRE(inputs == 2);
    h.plugin->setPlayConfigDetails(inputs, 2, kRate, kBlock);
    h.plugin->prepareToPlay(kRate, kBlock);
}

/// Choice orders of the contract (INTERFACES.md): the index is what a host stores.
inline int choiceIndex(const juce::String& name, const juce::String& choice)
{
    static const juce::StringArray sources {"device", "simulator", "OSC", "host automation"};
    static const juce::StringArray scenes {"monitor", "theremin", "cymbal", "panel", "sound-design", "compass", "braille", "score", "audio-touch",
                                                   "layered-keyboard", "theremin-duo"};
    return (name == "Source" ? sources : scenes).indexOf(choice);
}

/// Sets a choice parameter by its contract index; the host must show the same text (under LV2
/// that text comes from the bundle's scale points, which the build corrects after JUCE 7.0.5's
/// export: cmake/fix-lv2-scale-points.awk).
inline void setChoice(Hosted& h, const juce::String& name, const juce::String& choice)
{
    auto* p = h.param(name);
    REQUIRE(p != nullptr);
    const int index = choiceIndex(name, choice);
    REQUIRE(index >= 0);
    const int steps = p->getNumSteps();
    REQUIRE(steps > index);
    const float v = static_cast<float>(index) / static_cast<float>(steps - 1);
    CHECK(p->getText(v, 100) == choice);
    p->setValueNotifyingHost(v);
}

inline bool choiceIs(Hosted& h, const juce::String& name, const juce::String& choice)
{
    auto* p = h.param(name);
    REQUIRE(p != nullptr);
    const int index = juce::roundToInt(p->getValue() * static_cast<float>(p->getNumSteps() - 1));
    CHECK(p->getCurrentValueAsText() == choice);
    return index == choiceIndex(name, choice);
}

/// Sets a float parameter in its own unit (linear range lo..hi).
inline void setValue(Hosted& h, const juce::String& name, float value, float lo, float hi)
{
    auto* p = h.param(name);
    REQUIRE(p != nullptr);
    p->setValueNotifyingHost((value - lo) / (hi - lo));
}

inline float valueOf(Hosted& h, const juce::String& name, float lo, float hi)
{
    auto* p = h.param(name);
    REQUIRE(p != nullptr);
    return lo + p->getValue() * (hi - lo);
}

/// Renders `seconds` of audio; returns the left channel.
inline std::vector<float> render(Hosted& h, double seconds, int* midiEvents = nullptr)
{
    std::vector<float> out;
    juce::AudioBuffer<float> buffer(2, kBlock);
    juce::MidiBuffer midi;
    const int blocks = static_cast<int>(std::ceil(seconds * kRate / kBlock));
    for (int b = 0; b < blocks; ++b) {
        buffer.clear();
        midi.clear();
        h.plugin->processBlock(buffer, midi);
        // The plugin builds engines for scene changes on its message thread: let it run.
        juce::MessageManager::getInstance()->runDispatchLoopUntil(1);
        if (midiEvents != nullptr) *midiEvents += midi.getNumEvents();
        for (int i = 0; i < kBlock; ++i) out.push_back(buffer.getSample(0, i));
    }
    return out;
}

/// Set while a guarded processBlock runs: a debugger can stop on the guard's counters only then
/// (gdb: break countedMalloc if gInGuardedBlock).
inline volatile bool gInGuardedBlock = false;

struct BlockCounts {
    std::uint64_t allocations = 0, deallocations = 0, locks = 0, throws = 0, blocks = 0;
    std::uint64_t midiEvents = 0;        ///< MIDI events the plugin put out in these blocks
    std::uint64_t hostGrowthAllocations = 0;   ///< in blocks that carried more MIDI events than any before
};

/// JUCE's VST3 hosting side takes 3 locks for every MIDI event the plugin puts out (its
/// MidiEventList: measured with gdb, exactly 3 per event) and grows that list the first time a
/// block carries more events than any before. Pose CCs come whenever the tracked pose crosses a
/// CC step, which may happen in any measured block, so the lock budget counts them on the
/// host's side.
constexpr double kHostLocksPerMidiEvent = 3.0;
inline std::uint64_t gMostMidiEventsInABlock = 0;

/// What processBlock did on this thread over `blocks` blocks. With `automate`, every parameter
/// but Source and Scene moves each block (values set between blocks, as a host's automation
/// would, and picked up inside processBlock).
inline BlockCounts countDuringProcessing(Hosted& h, int blocks, bool automate)
{
    using armadillo::test::RealtimeGuard;
    juce::AudioBuffer<float> buffer(2, kBlock);
    juce::MidiBuffer midi;
    midi.ensureSize(8192);
    BlockCounts c;
    const auto params = h.plugin->getParameters();
    for (int b = 0; b < blocks; ++b) {
        if (automate)
            for (int i = 0; i < params.size(); ++i) {
                auto* p = params[i];
                const auto name = p->getName(100);
                // Source and scene are chosen by the test; a program change is a preset, not automation.
                // What a DAW cannot automate is left alone too: the wrapper's bypass (bypassed
                // blocks never reach processBlock) and, since the plugin has a MIDI input, the VST3
                // wrapper's hidden MIDI-CC parameters (JUCE_VST3_EMULATE_MIDI_CC_WITH_PARAMETERS).
                if (name == "Source" || name == "Scene" || name == "Program") continue;
                if (p == h.plugin->getBypassParameter() || ! p->isAutomatable()) continue;
                p->setValue(0.5f + 0.49f * std::sin(0.05f * static_cast<float>(b) + static_cast<float>(i)));
            }
        // ARMADILLO_GUARD_TRAP=1 (under a debugger) stops at the first allocation, free or lock
        // inside a block, to find where it happens (Tests/Common/RealtimeGuard.h).
        static const bool trap = std::getenv("ARMADILLO_GUARD_TRAP") != nullptr;
        RealtimeGuard guard(trap ? RealtimeGuard::Mode::Trap : RealtimeGuard::Mode::Count);
        gInGuardedBlock = true;
        h.plugin->processBlock(buffer, midi);
        gInGuardedBlock = false;
        const auto events = static_cast<std::uint64_t>(midi.getNumEvents());
        if (events > gMostMidiEventsInABlock) {   // the host's event list grows (its side of the call)
            gMostMidiEventsInABlock = events;
            c.hostGrowthAllocations += guard.allocations();
        } else {
            c.allocations += guard.allocations();
        }
        c.deallocations += guard.deallocations();
        c.locks += guard.locks();
        c.throws += guard.throws();
        c.midiEvents += events;
        ++c.blocks;
        midi.clear();
    }
    return c;
}

/// The plugin's own state document (docs/PLUGIN.md "State") out of JUCE's VST3 host wrapper.
inline std::unique_ptr<juce::XmlElement> ownState(Hosted& h)
{
    juce::MemoryBlock hostState, own;
    h.plugin->getStateInformation(hostState);
    auto outer = juce::AudioProcessor::getXmlFromBinary(hostState.getData(), static_cast<int>(hostState.getSize()));
    REQUIRE(outer != nullptr);
    REQUIRE(outer->getChildByName("IComponent") != nullptr);
    own.fromBase64Encoding(outer->getChildByName("IComponent")->getAllSubText());
    auto xml = juce::AudioProcessor::getXmlFromBinary(own.getData(), static_cast<int>(own.getSize()));
    REQUIRE(xml != nullptr);
    return xml;
}

/// The plugin's own state document given to the plugin through JUCE's VST3 state wrapper, as a
/// DAW restores a session.
inline void setOwnStateVst3(Hosted& h, const juce::XmlElement& own)
{
    juce::MemoryBlock payload, blob;
    juce::AudioProcessor::copyXmlToBinary(own, payload);
    juce::XmlElement state("VST3PluginState");
    state.createNewChildElement("IComponent")->addTextElement(payload.toBase64Encoding());
    juce::AudioProcessor::copyXmlToBinary(state, blob);
    h.plugin->setStateInformation(blob.getData(), static_cast<int>(blob.getSize()));
}

/// Some of the plugin's own settings (docs/PLUGIN.md "State") changed, the rest kept.
inline void setOwnSettings(Hosted& h, const std::map<juce::String, juce::var>& values)
{
    auto own = ownState(h);
    auto* settings = own->getChildByName("SETTINGS");
    REQUIRE(settings != nullptr);
    for (const auto& [k, v] : values) settings->setAttribute(k, v.toString());
    setOwnStateVst3(h, *own);
}

/// Frequency from positive-going zero crossings (interpolated), over the whole span.
inline double frequency(const std::vector<float>& x, std::size_t from)
{
    double first = -1.0, last = -1.0;
    int crossings = 0;
    for (std::size_t i = std::max<std::size_t>(from, 1); i < x.size(); ++i) {
        if (x[i - 1] < 0.0f && x[i] >= 0.0f) {
            const double t = static_cast<double>(i - 1) + x[i - 1] / static_cast<double>(x[i - 1] - x[i]);
            if (first < 0.0) first = t;
            last = t;
            ++crossings;
        }
    }
    if (crossings < 3) return 0.0;
    return (crossings - 1) / ((last - first) / kRate);
}

/// The theremin's pitch map with its default parameters (thesis §3.5, Instruments/Frets.h):
/// semitones linear in sin(elevation) from −45° (220 Hz) to +45° (440 Hz).
inline double expectedThereminHz(double elevationDeg)
{
    const double s = std::sin(elevationDeg * M_PI / 180.0);
    const double lo = std::sin(-M_PI / 4.0), hi = std::sin(M_PI / 4.0);
    const double e = 12.0 * (std::clamp(s, lo, hi) - lo) / (hi - lo);
    return 220.0 * std::pow(2.0, e / 12.0);
}

} // namespace armadillo::test::host
