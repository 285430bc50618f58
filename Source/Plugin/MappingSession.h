#pragma once
// The plugin's mapping set on the message thread (docs/PLUGIN.md "Mapping"): which preset or
// file it came from, the document the editor changes, saving it in the plugin state and in files,
// compiling it (mapping::MappingSet::build, which allocates: never on the audio thread) and handing
// the compiled set to the control side lock-free (mapping::Mapper::offer; the old set comes back
// and is freed here), the OSC targets the set names, and MIDI learn (range and destination).
//
// Threads: the message thread only (the host's state calls included, which JUCE's wrappers make
// from the message thread or a non-audio thread while the message thread is not in here).
#include "Mapping/Mapper.h"
#include "Mapping/MappingSpec.h"
#include "Live/BlockControl.h"
#include "Plugin/Parameters.h"
#include <juce_audio_processors/juce_audio_processors.h>
#include <functional>
#include <memory>

namespace armadillo::plugin {

class Connections;

namespace MappingIds {
inline const juce::Identifier root {"MAPPING"};       ///< child of the saved state (docs/PLUGIN.md "State")
inline const juce::Identifier name {"name"};          ///< preset name or file name it came from
inline const juce::Identifier json {"json"};          ///< the document (docs/MAPPING.md)
inline const juce::Identifier forward {"forward"};    ///< the forward reference, azimuth deg
} // namespace MappingIds

class MappingSession {
public:
    /// `defaultChannel` gives the classic preset's MIDI channel (the `midiChannel` setting, so a
    /// session from before the mapping keeps its channel).
    MappingSession(live::BlockControl& control, Connections& connections, const SceneParameterTable& table,
                   std::function<int()> defaultChannel);
    ~MappingSession();

    // The set ------------------------------------------------------------------------------------
    const mapping::MappingDocument& document() const noexcept { return doc_; }
    /// Where the set came from: a preset name, a file name, or "edited".
    const juce::String& name() const noexcept { return name_; }
    /// Compiles `doc` and hands it to the control side. On an error the running set stays and
    /// the reason (naming the mapping) comes back; "" when taken.
    juce::String setDocument(const mapping::MappingDocument& doc, const juce::String& name);
    /// A built-in or user preset (mapping::presetNames()).
    juce::String usePreset(const juce::String& preset);
    juce::StringArray presets() const;
    /// A mapping file (JSON). Errors name the file, line and column.
    juce::String loadFile(const juce::File& file);
    /// Writes the document as JSON (to a temporary file, then moved over the target).
    juce::String saveFile(const juce::File& file) const;

    /// The set the control side runs or is about to (meters, mute); nullptr before any.
    mapping::MappingSet* liveSet() noexcept { return control_.mapper().newest(); }
    void setMuted(int index, bool muted);
    float meter(int index) noexcept;
    bool active(int index) noexcept;
    /// "Set forward": the next control update takes the arm's azimuth as forward.
    void setForward() noexcept { control_.mapper().requestForward(); }

    // State ----------------------------------------------------------------------------------
    juce::ValueTree toState() const;
    /// Restores a saved set; an invalid node (a state from before the mapping) gives the classic
    /// preset, a node with a name and no JSON that preset. Returns "" or what was refused (then
    /// the classic preset runs).
    juce::String fromState(const juce::ValueTree& node);

    // Learn ----------------------------------------------------------------------------------
    /// Range: from now on the control side records the smallest and largest value of mapping
    /// `index`'s source; finishRangeLearn writes them as its `in` range.
    bool startRangeLearn(int index, juce::String& why);
    /// Current learned range (false until two distinct values were seen).
    bool learnedRange(double& lo, double& hi) const;
    juce::String finishRangeLearn(bool apply);
    int rangeLearnIndex() const noexcept { return rangeIndex_; }
    /// Destination: the next channel message at the plugin's MIDI input becomes mapping
    /// `index`'s destination (CC, a CC 0–31 with its +32 partner as a 14-bit pair, pitch bend,
    /// pressure, note, program change).
    void startDestinationLearn(int index) { destinationIndex_ = index; }
    void cancelDestinationLearn() { destinationIndex_ = -1; }
    int destinationLearnIndex() const noexcept { return destinationIndex_; }
    /// What the last destination learn did ("" when nothing new); taking it clears it. Polled
    /// by the editor (no callback: the timer that learns holds the processor's mapping lock).
    juce::String takeNotice()
    {
        auto n = notice_;
        notice_.clear();
        return n;
    }

    /// Message thread timer (the processor's, 50 Hz): collects the old set, retries a hand-over
    /// that had to wait, drains the MIDI input for destination learn, releases macros no mapping
    /// drives any longer.
    void timerTick();
    /// While the control side cannot run (the processor's constructor, before the clock starts),
    /// sets are installed at once instead of offered, so the first block already runs the
    /// state's set rather than the one before it.
    void setControlStopped(bool stopped) noexcept { controlStopped_ = stopped; }
    /// The default OSC target (the OSC out setting's host and port) changed.
    void setDefaultOscTarget(const juce::String& host, int port);

private:
    mapping::MappingDocument withClassicChannel(mapping::MappingDocument doc, const juce::String& preset) const;
    void offerWaiting();
    void configureOscTargets(const mapping::MappingSet& set);

    live::BlockControl& control_;
    Connections& connections_;
    const SceneParameterTable& table_;
    std::function<int()> defaultChannel_;
    mapping::MappingDocument doc_;
    juce::String name_;
    std::unique_ptr<mapping::MappingSet> waiting_;   // built, not yet taken by Mapper::offer
    std::uint32_t macrosUsed_ = 0;
    juce::String oscHost_ {"127.0.0.1"};
    int oscPort_ = 9000;
    bool controlStopped_ = false;
    int rangeIndex_ = -1;
    int destinationIndex_ = -1;
    juce::String notice_;
};

} // namespace armadillo::plugin
