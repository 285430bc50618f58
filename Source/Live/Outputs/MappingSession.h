#pragma once
// The mapping set of an audio-clocked rig on the message thread (docs/PLUGIN.md "Mapping"): which
// preset or file it came from, the document the editor changes, its saved form (the plugin keeps
// it in its state), compiling it (mapping::MappingSet::build, which allocates: never on the audio
// thread) and handing the compiled set to the control side lock-free (mapping::Mapper::offer; the
// old set comes back and is freed here), the OSC targets the set names, and the two learn
// procedures (a source's range from the arm's movement, a destination from the next MIDI message)
// and "set forward". The app presents it in its Mapping window; no JUCE.
//
// Threads: the message thread only (the host's state calls included, which JUCE's wrappers make
// from the message thread or a non-audio thread while the message thread is not in here).
#include "Live/Session/BlockControl.h"
#include "Live/Step/SceneParameters.h"
#include "Mapping/Mapper.h"
#include "Mapping/MappingSpec.h"
#include "Osc/HostPort.h"
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace armadillo::live {

/// The mapping as a session saves it (the plugin's MAPPING state node, docs/PLUGIN.md "State").
struct SavedMapping {
    bool present = false;    ///< false: a state from before the mapping
    std::string name;        ///< preset name or file name it came from
    std::string json;        ///< the document (docs/MAPPING.md); may be empty when `name` is a preset
    double forward = 0.0;    ///< the forward reference, azimuth deg
};

class MappingSession {
public:
    /// Opens the set's OSC targets (the rig's senders); returns "" or which could not be used.
    using OscTargets = std::function<std::string(const std::vector<osc::HostPort>&)>;
    /// `defaultChannel` gives the classic preset's MIDI channel (the `midiChannel` setting, so a
    /// session from before the mapping keeps its channel).
    MappingSession(BlockControl& control, const SceneParameterTable& table, std::function<int()> defaultChannel, OscTargets oscTargets);
    ~MappingSession();

    // The set ------------------------------------------------------------------------------------
    const mapping::MappingDocument& document() const noexcept { return doc_; }
    /// Where the set came from: a preset name, a file name, or "edited".
    const std::string& name() const noexcept { return name_; }
    /// Compiles `doc` and hands it to the control side. On an error the running set stays and
    /// the reason (naming the mapping) comes back; "" when taken.
    std::string setDocument(const mapping::MappingDocument& doc, const std::string& name);
    /// A built-in or user preset (mapping::presetNames()).
    std::string usePreset(const std::string& preset);
    std::vector<std::string> presets() const;
    /// A mapping file (JSON). Errors name the file, line and column.
    std::string loadFile(const std::string& path);
    /// Writes the document as JSON (whole or not at all).
    std::string saveFile(const std::string& path) const;

    /// The set the control side runs or is about to (meters, mute); nullptr before any.
    mapping::MappingSet* liveSet() noexcept { return control_.mapper().newest(); }
    void setMuted(int index, bool muted);
    float meter(int index) noexcept;
    bool active(int index) noexcept;
    /// "Set forward": the next control update takes the arm's azimuth as forward.
    void setForward() noexcept { control_.mapper().requestForward(); }

    // State ----------------------------------------------------------------------------------
    SavedMapping toSaved() const;
    /// Restores a saved set; none (a state from before the mapping) gives the classic preset, a
    /// name and no JSON that preset. Returns "" or what was refused (then the classic preset runs).
    std::string fromSaved(const SavedMapping& saved);

    // Learn ----------------------------------------------------------------------------------
    /// Range: from now on the control side records the smallest and largest value of mapping
    /// `index`'s source; finishRangeLearn writes them as its `in` range.
    bool startRangeLearn(int index, std::string& why);
    /// Current learned range (false until two distinct values were seen).
    bool learnedRange(double& lo, double& hi) const;
    std::string finishRangeLearn(bool apply);
    int rangeLearnIndex() const noexcept { return rangeIndex_; }
    /// Destination: the next channel message at the MIDI input becomes mapping `index`'s
    /// destination (CC, a CC 0–31 with its +32 partner as a 14-bit pair, pitch bend, pressure,
    /// note, program change).
    void startDestinationLearn(int index) { destinationIndex_ = index; }
    void cancelDestinationLearn() { destinationIndex_ = -1; }
    int destinationLearnIndex() const noexcept { return destinationIndex_; }
    /// What the last destination learn did ("" when nothing new); taking it clears it. Polled
    /// by the editor (no callback: the timer that learns holds the processor's mapping lock).
    std::string takeNotice()
    {
        auto n = notice_;
        notice_.clear();
        return n;
    }

    /// Message thread timer (50 Hz): collects the old set, retries a hand-over that had to wait,
    /// drains the MIDI input for destination learn, releases macros no mapping drives any longer.
    void timerTick();
    /// While the control side cannot run (the processor's constructor, before the clock starts),
    /// sets are installed at once instead of offered, so the first block already runs the
    /// state's set rather than the one before it.
    void setControlStopped(bool stopped) noexcept { controlStopped_ = stopped; }
    /// The default OSC target (the OSC out setting's host and port) changed.
    void setDefaultOscTarget(const std::string& host, int port);

private:
    mapping::MappingDocument withClassicChannel(mapping::MappingDocument doc, const std::string& preset) const;
    void offerWaiting();
    void configureOscTargets(const mapping::MappingSet& set);

    BlockControl& control_;
    const SceneParameterTable& table_;
    std::function<int()> defaultChannel_;
    OscTargets oscTargets_;
    mapping::MappingDocument doc_;
    std::string name_;
    std::unique_ptr<mapping::MappingSet> waiting_;   // built, not yet taken by Mapper::offer
    std::uint32_t macrosUsed_ = 0;
    std::string oscHost_ {"127.0.0.1"};
    int oscPort_ = 9000;
    bool controlStopped_ = false;
    int rangeIndex_ = -1;
    int destinationIndex_ = -1;
    std::string notice_;
};

} // namespace armadillo::live
