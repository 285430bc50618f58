#pragma once
// The mapping matrix at run time (issue 23, docs/MAPPING.md). A MappingSet is a MappingDocument
// compiled off the audio thread into fixed tables (OSC addresses pre-expanded, postures indexed,
// per-mapping state preallocated). A Mapper runs the active set once per control update:
// process() is REAL-TIME — no allocation, lock, I/O or throw (Tests/Mapping proves it with 64
// mappings) — and writes MIDI events, encoded OSC packets, macro values and scene-parameter
// changes (and stage commands) into a caller-owned fixed-capacity MappingOutput. The front ends deliver them: the
// plugin into its MidiBuffer and parameters, the CLI into a Standard MIDI File or an ALSA
// sequencer port and UDP.
//
// Emission rule: a destination sends only when its encoded value changes (a 14-bit CC pair when
// the 14-bit value changes, an OSC message when one of its encoded arguments does), so a still arm
// sends nothing; and only what the set names is sent.
//
// Threads:
//  - builder (message/UI thread, CLI start-up): MappingSet::build, Mapper::offer/collect/replace.
//  - control side (the audio thread in the plugin, the control thread in the CLI): process(),
//    flush(), allNotesOff(). One thread at a time.
//  - any thread: requestForward(), setForwardAzimuth(), MappingSet::setMuted(), meters.
#include "Core/ArmState.h"
#include "Core/Scene.h"
#include "Mapping/MappingSpec.h"
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace armadillo::mapping {

// ---------------------------------------------------------------------------------------------
// Input

/// A gesture as a scene emitted it (Engine's GestureEvent: name is a string literal).
struct GestureIn {
    const char* name = "";
    float value = 0.0f;
};

/// Everything one control update offers the mapping. Pointers are borrowed for the call.
struct MappingInput {
    double t = 0.0;                                   ///< s on the front end's timeline (events carry it)
    const core::ArmState* arm[kMaxArms] {nullptr, nullptr}; ///< arm[0] = the worn arm; nullptr or !valid: continuous sources hold
    core::SceneValues scene {};                       ///< the scene's own outputs (Core/Scene.h; NaN = the scene has none)
    const GestureIn* gestures = nullptr;              ///< gestures since the previous update
    int gestureCount = 0;
    /// Only the mappings whose destination is a stage command run (the others keep their state):
    /// the front ends set it while in panic, when nothing else may be sent but a mapped resume
    /// must still be heard.
    bool stageOnly = false;
};

// ---------------------------------------------------------------------------------------------
// Output (fixed capacity; what does not fit is dropped and counted, never grown)

struct MidiEvent {
    double t = 0.0;                        ///< s, same timeline as MappingInput::t (note-offs may be earlier than the update's t)
    std::uint8_t size = 0;                 ///< 1…3
    std::array<std::uint8_t, 3> bytes {};  ///< status byte first (channel in its low nibble)
};

inline constexpr std::size_t kOscPacketCapacity = 256;   ///< bytes of one encoded OSC message

struct OscPacket {
    double t = 0.0;
    int target = 0;                        ///< index into MappingSet::oscTargets()
    std::uint16_t size = 0;
    std::array<std::uint8_t, kOscPacketCapacity> bytes {};   ///< encoded with Device/Osc.h (OSC 1.0)
};

/// An MQTT message an Mqtt destination made (issue 35, docs/MQTT.md): fixed size, formatted on the
/// control thread without allocation; the front end hands it to the MQTT client's queue.
struct MqttMessage {
    static constexpr std::size_t kMaxTopic = 160;
    static constexpr std::size_t kMaxPayload = 440;
    double t = 0.0;
    std::array<char, kMaxTopic> topic {};
    std::array<char, kMaxPayload> payload {};
    std::uint16_t topicLength = 0, payloadLength = 0;
    std::uint8_t qos = 0;
    bool retain = false;
    float rate = -1.0f;                    ///< per-topic messages/s (DestinationSpec::rate)
};

/// A stage command a Stage destination fired (docs/STAGE.md): once per rising edge of its source.
struct StageEvent {
    double t = 0.0;
    core::StageCommand command {};         ///< what it asks (CueGoto: command.cue is the cue, 0-based)
    int mapping = 0;                       ///< index of the mapping that fired it
};

struct SceneParamChange {
    int index = 0;                         ///< into MappingSet::sceneParamIds()
    float value = 0.0f;
    bool normalised = true;                ///< true: 0…1 over the parameter's range; false: its own unit
};

/// About 60 KB: allocate it once off the audio thread (make_unique) and reuse it; clear() between
/// deliveries.
struct MappingOutput {
    static constexpr int kMaxMidi = 1024;
    static constexpr int kMaxOsc = 64;
    static constexpr int kMaxParams = 64;
    static constexpr int kMaxStage = 16;
    static constexpr int kMaxMqtt = 32;

    std::array<MidiEvent, kMaxMidi> midi {};
    int midiCount = 0;
    std::array<OscPacket, kMaxOsc> osc {};
    int oscCount = 0;
    std::array<float, kMacroCount> macro {};        ///< macro k+1's value 0…1, valid where macroChanged bit k is set
    std::uint32_t macroChanged = 0;
    std::array<SceneParamChange, kMaxParams> params {};
    int paramCount = 0;
    std::array<StageEvent, kMaxStage> stage {};      ///< stage commands in the order fired
    int stageCount = 0;
    std::array<MqttMessage, kMaxMqtt> mqtt {};       ///< MQTT messages in the order made
    int mqttCount = 0;
    std::uint64_t dropped = 0;                       ///< events that did not fit (cumulative until clear())
    bool forwardChanged = false;                     ///< the forward reference was set during this update

    /// Empties the lists (keeps nothing). Real-time.
    void clear() noexcept;
};

// ---------------------------------------------------------------------------------------------
// The compiled set

struct OscTarget {
    std::string host;   ///< empty: the front end's default target
    int port = 0;       ///< 0: the front end's default port
};

struct BuildOptions {
    /// Scene parameter ids the active scene offers; a SceneParam destination naming another id is
    /// an InputError at build time. Empty: not checked (the front end checks when it resolves).
    std::vector<std::string> sceneParamIds;
    std::string sourceName;   ///< for error messages ("mapping.json", "preset classic")
};

class MappingSet {
public:
    /// Compiles a document. Not real-time (allocates everything process() will need). Throws
    /// InputError for what parsing cannot see (too many mappings, an OSC address that does not
    /// encode, an unknown scene parameter).
    static std::unique_ptr<MappingSet> build(const MappingDocument& doc, const BuildOptions& options = {});
    ~MappingSet();
    MappingSet(const MappingSet&) = delete;
    MappingSet& operator=(const MappingSet&) = delete;

    const MappingDocument& document() const noexcept;
    std::size_t size() const noexcept;
    /// OSC targets named by the set (index = OscPacket::target); target 0 is always the default.
    const std::vector<OscTarget>& oscTargets() const noexcept;
    /// Scene parameter ids named by the set (index = SceneParamChange::index).
    const std::vector<std::string>& sceneParamIds() const noexcept;
    /// Which macros (bit k = macro k+1) some mapping drives.
    std::uint32_t macrosUsed() const noexcept;

    /// Any thread: mute or unmute mapping i (a muted mapping sends nothing; its sounding notes
    /// are ended at the next update).
    void setMuted(std::size_t i, bool muted) noexcept;
    bool muted(std::size_t i) const noexcept;
    /// Any thread: mapping i's latest value, normalised 0…1 (after the transform, before the
    /// destination's encoding), for meters; NaN before its first value.
    float meter(std::size_t i) const noexcept;
    /// Any thread: whether mapping i's event/zone is on (a zone entered, a note sounding).
    bool active(std::size_t i) const noexcept;

    struct Impl;
    Impl& impl() noexcept { return *impl_; }

private:
    MappingSet();
    std::unique_ptr<Impl> impl_;
};

// ---------------------------------------------------------------------------------------------
// The runner

class Mapper {
public:
    Mapper();
    ~Mapper();
    Mapper(const Mapper&) = delete;
    Mapper& operator=(const Mapper&) = delete;

    // Builder side --------------------------------------------------------------------------
    /// Hands a set to the control side; it takes over at the next process() (after the old set's
    /// sounding notes are ended there). False (set untouched) while an earlier hand-over or a
    /// retired set is pending: collect() and offer again.
    bool offer(std::unique_ptr<MappingSet>& set) noexcept;
    bool canOffer() const noexcept;
    /// Deletes the set the control side gave up, if any.
    void collect() noexcept;
    /// Installs a set at once: only while process() cannot run (CLI start-up, the plugin with
    /// its control token). Drops anything pending or retired.
    void replace(std::unique_ptr<MappingSet> set) noexcept;
    /// The newest set (the last one offered or installed: pending, else active), for UIs reading
    /// meters; builder thread. Valid until the next replace(), or the next offer() and collect().
    MappingSet* newest() noexcept;

    // Control side (REAL-TIME) --------------------------------------------------------------
    /// One control update: reads every source, runs every unmuted mapping, appends to `out`
    /// (does not clear it). Swaps in an offered set first.
    void process(const MappingInput& in, MappingOutput& out) noexcept;
    /// Note-offs that fall due up to time t without a control update (the end of a plugin block,
    /// the end of a render).
    void flush(double t, MappingOutput& out) noexcept;
    /// Ends every sounding note now (stop, bypass, transport jump) and forgets the last sent
    /// values, so the next update sends every destination afresh.
    void allNotesOff(double t, MappingOutput& out) noexcept;
    /// A new engine took over (a state loaded, a rebuild): its scene has its defaults, so every
    /// scene-parameter destination is sent again at the next update, changed or not. Control side.
    void resendSceneParams() noexcept;
    /// Panic (docs/STAGE.md): allNotesOff(), then All Sound Off (CC 120) and All Notes Off
    /// (CC 123), value 0, on all 16 channels at t (MIDI 1.0 Channel Mode messages), for whatever
    /// the receivers still hold. The plugin and `play --midi-out` send the same.
    void panic(double t, MappingOutput& out) noexcept;
    MappingSet* active() noexcept;

    // Forward reference (any thread) --------------------------------------------------------
    /// The next process() takes the current azimuth as forward (a button, a MIDI note, an OSC
    /// message, the SetForward destination).
    void requestForward() noexcept;
    /// Sets forward to an azimuth in degrees (0…360; restored from a saved state).
    void setForwardAzimuth(double deg) noexcept;
    double forwardAzimuth() const noexcept;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

// ---------------------------------------------------------------------------------------------
// Helpers the editors and the tests share (not real-time unless said)

/// A source's value from one update's input, in the units SourceKind names; NaN when it has none
/// (no valid arm, a scene output the scene lacks, an event source). Real-time.
double readSource(const SourceSpec& source, const MappingInput& in, double forwardDeg) noexcept;

/// MIDI learn of a destination: the next channel message another plugin or a controller sends.
/// Fills `out` (kind, channel, number) for a CC (7-bit; a CC 0…31 followed by its +32 partner
/// within the same call's bytes gives Cc14), pitch bend, channel pressure, note or program
/// change; false for anything else. Real-time.
bool learnDestination(const std::uint8_t* bytes, int size, DestinationSpec& out) noexcept;

/// Learns a source's range while the performer moves over it ("move the arm over the range you
/// want"): the smallest and largest value seen. Real-time.
struct RangeLearner {
    double lo = 0.0, hi = 0.0;
    int count = 0;
    void reset() noexcept { count = 0; }
    void add(double v) noexcept;
    /// [lo, hi] when at least 2 distinct values were seen; false otherwise.
    bool range(double& outLo, double& outHi) const noexcept;
};

} // namespace armadillo::mapping
