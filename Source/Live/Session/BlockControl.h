#pragma once
// The live rig on the audio clock: the same control step as `play` (ControlLoop: engine
// hand-over, source choice, bounded fusion, Engine::control) run at 200 Hz on an audio block
// timeline — the plugin's and the standalone app's — rendering the engine's audio between steps,
// running the mapping (Mapping/Mapper.h: arm features and gestures → MIDI at the step's sample
// offset, OSC, macros, scene parameters), publishing each step's frame for the UI and OSC, and
// handing each step's motor levels to the device link stamped with the step's time
// (Link/LevelSchedule.h: the link sends them when that time comes and goes all-off when they
// stop coming, so the motor budget holds on the packet timeline whatever the host does).
// `play` runs the same step clocked by its source (LiveSession); this clock is driven by a host's
// blocks (processBlock) or, while no audio comes, by an idle clock (idleTick). No JUCE: the
// plugin hands its buffers in as an AudioBlock, its MIDI as a BlockMidi and its play head as a
// Transport (Plugin/HostBlock.h).
//
// Threads:
//  - the token holder (ControlToken): processBlock on the audio thread, or idleTick on the idle
//    control clock while no audio comes. Real-time: no allocation, lock, I/O or throw
//    (Tests/Plugin and Tests/Live/RealtimeLoopTests.cpp hold it to that).
//  - prepare(): message thread, with the token held by the caller.
//  - the accessors below: any thread (atomics, a seqlock, one SPSC queue for one consumer).
#include "Core/Handover.h"
#include "Core/SpscQueue.h"
#include "Link/LevelSchedule.h"
#include "Live/Step/ControlLoop.h"
#include "Live/Step/ControlToken.h"
#include "Live/Session/Instrument.h"
#include "Live/Outputs/MappingDelivery.h"
#include "Live/Outputs/MappingOutputs.h"
#include "Live/Outputs/MidiOutQueue.h"
#include "Live/Outputs/StepPublisher.h"
#include "Live/Sources/OscLink.h"
#include "Live/Step/SceneParameters.h"
#include "Live/Stage/Stage.h"
#include "Live/Step/StepRunner.h"
#include "Mapping/Mapper.h"
#include "Tactors/TactorRenderer.h"
#include <array>
#include <atomic>
#include <cstdint>
#include <limits>

namespace armadillo::access {
class TactilePlayer;
}
namespace armadillo::mqtt {
class MessageService;
}

namespace armadillo::live {

class TactorOutput;

/// One audio block of the host's buffer: `numChannels` channels of `numSamples` samples, written
/// in place (channels 0 and 1 are the output; the others the inputs and the Tactors bus).
struct AudioBlock {
    float* const* channels = nullptr;
    int numChannels = 0;
    int numSamples = 0;
};

/// The host's MIDI for one block: its input, read first and in time order, then its output,
/// which starts empty. The plugin wraps juce::MidiBuffer (Plugin/HostBlock.h); real-time.
class BlockMidi {
public:
    struct Event {
        const std::uint8_t* data = nullptr;
        int size = 0;
        int offset = 0;   ///< sample position in the block
    };
    virtual ~BlockMidi() = default;
    /// The next event of the block's input; false when all were read.
    virtual bool nextInput(Event& e) noexcept = 0;
    /// The input is read: the buffer now carries the output (empty).
    virtual void beginOutput() noexcept = 0;
    /// One event out at `offset`; false when the block's storage is full (the event is dropped).
    virtual bool add(const std::uint8_t* data, int size, int offset) noexcept = 0;
};

class BlockControl final : private MappingSinks {
public:
    static constexpr double kControlRateHz = 200.0;

    /// The parameter cells the control step reads (all owned by the processor's parameters).
    struct Cells {
        const std::atomic<float>* elevation = nullptr;
        const std::atomic<float>* azimuth = nullptr;
        const std::atomic<float>* roll = nullptr;
        const std::atomic<float>* source = nullptr;
    };

    /// The clock of `instrument` (its loop, stage, left arm, step and publisher: Instrument.h).
    BlockControl(Instrument& instrument, ControlToken& token, const Cells& cells, link::LevelSchedule& motors);

    /// Message thread, token held: a new sample rate. The mapping's sounding notes are ended at
    /// the start of the next block.
    void prepare(double sampleRate);
    /// Before the control side runs (construction): the scenes' parameter table, for the
    /// mapping's scene-parameter destinations (constant, read lock-free), and the standalone
    /// app's MIDI port (nullptr in a host).
    void setSceneTable(const SceneParameterTable* table) noexcept { sceneTable_ = table; }
    void setMidiPort(MidiOutQueue* port) noexcept { port_ = port; }
    /// The app's sensitivity test (Procedures/TouchTest.h, issue 26): while set, each control step's
    /// levels come from this player (its own TactileEngine and SafetyStage) instead of the
    /// scene's (never during a panic: Live/Step/StepRunner.h applies it); nullptr gives the motors
    /// back to the scene. Any thread; the player must outlive this object (the instrument owns both).
    void setStimulus(access::TactilePlayer* player) noexcept { runner_.setStimulus(player); }
    /// The Tactors bus's renderer (issue 33): every control step's levels (the scene's, or a
    /// stimulus's) go to it with the step's dt, and processBlock renders it into the bus's
    /// channels segment by segment, so a level change starts at its step's sample. It renders in
    /// offline (non-real-time) renders too: a bounce records the tactile track.
    /// installTactors: the token held (prepareToPlay), null = none. offerTactors: any time from
    /// the message thread (false, `next` untouched, while an earlier one is in flight: retry);
    /// collectTactors deletes the one the audio thread gave up, on the message thread.
    void installTactors(std::unique_ptr<tactors::TactorRenderer> renderer) noexcept { tactors_.replace(std::move(renderer)); }
    bool offerTactors(std::unique_ptr<tactors::TactorRenderer>& next) noexcept { return tactors_.offer(next); }
    void collectTactors() noexcept { tactors_.collect(); }
    /// The standalone app's tactor output on a sound card or JACK (Live/Outputs/TactorOutput.h): each
    /// step whose levels reach the motors is pushed to it too (its SPSC queue). Any thread; null
    /// = none. Before deleting an output set here, set null and take the token once.
    void setTactorOutput(TactorOutput* output) noexcept { tactorOut_.store(output, std::memory_order_release); }
    /// The app's MQTT connection (Live/Outputs/MessagesRig.h): the mapping's `mqtt` destinations are published
    /// through it (its client's SPSC outbox). Any thread; null = none (they are dropped and counted
    /// in mappedMqttDropped()). The service must outlive its use here (MessagesRig keeps every one).
    void setMqtt(mqtt::MessageService* service) noexcept { mqtt_.store(service, std::memory_order_release); }
    std::uint64_t mappedMqttDropped() const noexcept { return tally_.mqttDropped.load(std::memory_order_relaxed); }
    /// Which channels of the host's buffer carry the audio the scenes listen to (the main input
    /// or the sidechain), and whether it is played through to the output (the main input: an
    /// effect that listens must not mute its track).
    ///
    /// Stems (the VST3's sidechain buses, docs/PLUGIN.md "Stems"): each is one bus, mixed to one
    /// mono channel (the mean of its channels, as `render --stem` mixes a stem file). While the
    /// active engine's scene was built with as many stems (SceneConfig::stems, in the same order:
    /// audio-touch feels each on its own motors) it hears the stems, then the `first`/`count`
    /// channels after them (audio-touch's `mixed` choice and its fallback when the stems are
    /// silent); any other engine hears `first`/`count` alone, as before. An engine built with a different number
    /// of stems (a hand-over in flight across a layout change) hears nothing until it matches.
    static constexpr int kMaxStems = 4;
    struct Bus {
        int first = 0;          ///< first channel of the bus in the host's buffer
        int count = 0;          ///< its channels (1 or 2)
    };
    struct Listen {
        int first = 0;
        int count = 0;          ///< channels listened to from `first` (0: no audio input)
        int through = 0;        ///< main-input channels (from channel 0) played through to the output
        std::array<Bus, kMaxStems> stems {};
        int stemCount = 0;      ///< stems in use, stems[0 .. stemCount)
        /// The VST3's Tactors output bus (issue 33, docs/TACTORS.md): how many tactor channels it
        /// has (0: disabled) and where tactor channel k sits in the host's buffer. The renderer
        /// installed with installTactors() writes them; channels it does not fill are silent.
        int tactorCount = 0;
        std::array<int, tactors::kMaxChannels> tactorChannel {};
    };
    /// Audio thread: the whole block. `transport` is the host's play head at the block's first
    /// sample (Transport {} when it has none); `offline` is the host's non-realtime render (its
    /// blocks do not reach the motors: they get all-off).
    void processBlock(const AudioBlock& buffer, BlockMidi& midi, const core::Transport& transport, bool offline,
                      const Listen& listen) noexcept;
    /// The same without an audio input.
    void processBlock(const AudioBlock& buffer, BlockMidi& midi, const core::Transport& transport, bool offline) noexcept
    {
        processBlock(buffer, midi, transport, offline, Listen {});
    }
    /// Audio thread, the host's bypass: silence and an empty MIDI buffer, except the note-offs
    /// of the mapping's sounding notes in the first bypassed block. No control step runs.
    void bypassBlock(const AudioBlock& buffer, BlockMidi& midi) noexcept;
    /// Idle control clock (no audio for a while): `dt` s since its previous call. Runs the
    /// control step itself when no audio callback came for kIdleAfterMs and the token is free —
    /// never after an offline block until a real-time block or prepare() (a slow bounce is not
    /// interrupted). A block that comes while an idle step holds the token is silent and takes no
    /// step; the 200 Hz grid still counts its samples (mapped MIDI stays on the host's grid).
    void idleTick(double dt) noexcept;
    static constexpr double kIdleAfterMs = 100.0;

    SourceKind source() const noexcept;
    /// Whether the idle clock's steps reach the motors: yes in the standalone app (a performer
    /// without a sound card), no in a host (a host that stops calling processBlock has stopped,
    /// bypassed or removed the plugin: the motors go all-off and stay off).
    void setIdleDrivesMotors(bool on) noexcept { idleDrivesMotors_.store(on, std::memory_order_relaxed); }
    /// The newest motor levels' stamp may run ahead of the wall clock by this much (a host that
    /// renders ahead); further ahead, stamps follow the wall clock. Behind by kMaxLag, they jump
    /// to it (a late or stalled host).
    static constexpr double kMaxLead = 0.5, kMaxLag = 0.010;
    /// Live sources (issue 36): a sample that arrives while the host runs blocks gets its control
    /// step (fusion, scene, mapping, motor levels) at the block position of its arrival time — the
    /// block stands for the wall-clock stretch just before its call, [call − n/fs, call), as JUCE's
    /// MidiMessageCollector places timestamped MIDI input — instead of at the next 200 Hz grid
    /// point. The grid still steps when no sample comes (at most 5 ms apart); steps are at least
    /// this far apart (a burst is fused together). Host automation and offline renders keep the
    /// grid alone, so renders stay sample-exact.
    static constexpr double kMinStepSeconds = 0.00025;
    /// The mapping runner (its builder side belongs to the message thread, MappingSession).
    mapping::Mapper& mapper() noexcept { return mapper_; }
    /// MIDI events the mapping produced that did not fit the block's MIDI storage (any thread).
    std::uint64_t midiDropped() const noexcept { return tally_.midiDropped.load(std::memory_order_relaxed) + tally_.overflow.load(std::memory_order_relaxed); }
    /// Note-ons/offs of the MIDI input one block hands to the scene (Scene::processMidi); more
    /// are dropped and counted (any thread).
    static constexpr int kMaxNotesIn = 256;
    std::uint64_t notesInDropped() const noexcept { return notesInDropped_.load(std::memory_order_relaxed); }

    // Published (any thread).
    // What each step leaves for the rest (Live/Outputs/StepPublisher.h, the same as play's).
    ArmFrame latestFrame() const noexcept { return published_.latest(); }
    /// Gestures of the control steps, for one consumer (the clock thread's OSC sender).
    bool popGesture(engine::GestureEvent& g) noexcept { return published_.popGesture(g); }
    const char* lastGesture() const noexcept { return published_.lastGesture(); }
    std::uint64_t gestureCount() const noexcept { return published_.gestureCount(); }
    std::uint64_t gesturesDropped() const noexcept { return published_.gesturesDropped(); }
    std::uint64_t ticks() const noexcept { return published_.steps(); }
    /// The stamp (monotonic s) of the newest levels handed to the link, < 0 when none since the
    /// last all-off. The token holder's thread, or any thread while no control step runs (tests).
    double lastMotorStamp() const noexcept { return lastStamp_; }
    /// The mapping's outputs for the non-real-time side (macros, meters, OSC, MIDI learn).
    /// Stage commands the mapping's "stage" destinations fired (any thread; docs/STAGE.md).
    std::uint64_t mappedStageCommands() const noexcept { return tally_.stage.load(std::memory_order_relaxed); }
    MappingOutputs& mappingOutputs() noexcept { return outputs_; }
    const MappingOutputs& mappingOutputs() const noexcept { return outputs_; }

private:
    /// What a block's buffer holds for this block's stretches (processBlock's first step).
    struct BlockPlan {
        int listenCount = 0;    ///< main-input channels the scene hears (≤ 2)
        int throughCount = 0;   ///< main-input channels played through
        int stemCount = 0;      ///< stems whose channels all lie in the buffer
        int busCount = 0;       ///< Tactors bus channels in the buffer (0: none)
        int busRendered = 0;    ///< of them, the ones the renderer fills
        tactors::TactorRenderer* tactorBus = nullptr;
    };
    BlockPlan planBlock(const AudioBlock& buffer, const Listen& listen) noexcept;
    /// The block's MIDI input: stage messages to the stage, notes for the scene, the rest to the
    /// message thread; then the buffer is the block's MIDI output.
    void readMidiInput(BlockMidi& midi, int n) noexcept;
    /// The 200 Hz grid moved past the samples of blocks skipped since the last one.
    void moveGridPastSkipped(int samplesPerTick) noexcept;
    /// One stretch between steps: the scene hears its notes and input ([pos, pos + len)), the
    /// main input is kept for the pass-through …
    void hearStretch(const AudioBlock& buffer, const Listen& listen, const BlockPlan& plan, int pos, int len) noexcept;
    /// … then its sound is rendered over the output, the input passed through, the Tactors bus rendered.
    void renderStretch(const AudioBlock& buffer, const Listen& listen, const BlockPlan& plan, int pos, int len) noexcept;
    /// The block's end: the sound to the app's voice coil, the extra inputs silenced, the
    /// mapping's due note-offs delivered.
    void finishBlock(const AudioBlock& buffer, BlockMidi& midi, const Listen& listen, const BlockPlan& plan, double blockStart) noexcept;
    /// One control step; `wall` is the monotonic time its levels belong to by the wall clock, and
    /// `toMotors` whether they go to the link.
    /// `cutoff` (monotonic s): only live samples that arrived by then are fused (+∞: all waiting).
    void step(double dt, double wall, bool toMotors, const core::Transport& transport, BlockMidi* midi, int sampleOffset,
              double cutoff = std::numeric_limits<double>::infinity()) noexcept;
    /// Hands out what the mapping produced (deliverMapping, MappingDelivery.h) to this clock's
    /// sinks: MIDI into `midi` (when not null) at the offset of each event's time from
    /// `blockStart` (s, the mapping's timeline), clamped to the block's `blockSamples`, and to the
    /// standalone's port; OSC to the clock's queue; MQTT through the app's connection; stage
    /// commands to the stage; macros; scene parameters to the active scene. Clears `mapOut_`.
    void deliver(BlockMidi* midi, double blockStart, int blockSamples) noexcept;
    /// The active scene's parameters as the running set names them (none without a set, a scene
    /// table or an engine).
    SceneParamTarget sceneParamTarget() noexcept;
    bool midi(const mapping::MidiEvent& e) noexcept override;
    bool osc(const mapping::OscPacket& p) noexcept override;
    bool mqtt(const mapping::MqttMessage& m) noexcept override;
    void stage(const mapping::StageEvent& e) noexcept override;
    void macro(int index, float value01) noexcept override { outputs_.setMacro(index, value01); }
    /// The stage at the start of a block or idle step (token holder): takes an offered set
    /// list, applies cue requests, panic and resume. On panic: every engine (and cue) panicked
    /// before anything of this block is rendered, the mapping's sounding notes ended and CC 120
    /// + CC 123 sent on all 16 channels, into `midi` at offset 0 (when not null) and the port.
    void beginStage(BlockMidi* midi, double blockStart, int blockSamples) noexcept;
    /// The current cue's engine with a set list, else the active engine (null: none).
    engine::Engine* runningEngine() noexcept;
    void renderRunning(float* left, float* right, int numSamples) noexcept;
    void inputRunning(const float* const* in, int channels, int numSamples) noexcept;
    /// The MIDI input's notes that fall in [from, from + len) of the block, offsets made
    /// relative to `from`, to the running engine or the set list's cues (before their input).
    void notesRunning(int from, int len) noexcept;
    void learnRange(const mapping::MappingInput& in) noexcept;

    Instrument& instrument_;
    ControlLoop& loop_;   ///< instrument_'s
    ControlToken& token_;
    Cells cells_;
    link::LevelSchedule& motors_;
    std::atomic<double> sampleRate_ {48000.0};
    std::atomic<double> lastAudioMs_ {-1.0e9};
    std::atomic<bool> idleDrivesMotors_ {false};
    std::atomic<bool> offlineRender_ {false};   ///< the last block was the host's offline render
    core::Handover<tactors::TactorRenderer> tactors_;
    std::atomic<TactorOutput*> tactorOut_ {nullptr};
    std::atomic<mqtt::MessageService*> mqtt_ {nullptr};

    // Token holder only.
    double clock_ = 0.0;              ///< s since start, advanced by dt per step
    int samplesToTick_ = 0;           ///< samples to the next step on the 200 Hz grid (or sooner: a live sample's arrival)
    int samplesSinceStep_ = 0;        ///< samples since the previous step: its dt
    long long skippedSamples_ = 0;    ///< audio thread (with or without the token): samples of blocks skipped since the last block
    double lastStamp_ = -1.0;         ///< monotonic s of the previous step's levels (< 0: none)
    bool motorsOff_ = true;           ///< the schedule was told allOff and nothing pushed since
    int blockSamples_ = 0;              ///< the current block's length
    std::atomic<bool> notesOffPending_ {false};
    bool bypassed_ = false;             ///< audio thread: the previous block was bypassed
    // The mapping (control side): runner, its fixed-capacity output, the step's gestures.
    mapping::Mapper mapper_;
    mapping::MappingOutput mapOut_ {};
    mapping::RangeLearner learner_;
    std::uint32_t learnGeneration_ = 0;
    const SceneParameterTable* sceneTable_ = nullptr;
    MidiOutQueue* port_ = nullptr;
    Stage* stage_ = nullptr;               ///< instrument_'s (never null)
    StepRunner& runner_;                   ///< instrument_'s: the stage applied, the control step (Live/Step/StepRunner.h)
    MappingTally tally_;                             ///< what the mapping delivered and lost
    BlockMidi* deliverMidi_ = nullptr;               ///< deliver()'s block while it runs (token holder)
    double deliverStart_ = 0.0;
    int deliverSamples_ = 0;
    /// The listened-to input of one control step (≤ 192 kHz / 200 Hz samples), fixed size.
    static constexpr int kInputScratch = 1024;
    std::array<std::array<float, kInputScratch>, kMaxStems + 2> input_ {};   // the stems, then the main input
    std::array<std::array<float, kInputScratch>, 2> through_ {};
    std::array<float, kInputScratch> tactorSound_ {};   // the scene's sound, mono, for a voice coil handed it
    /// Control side: how many stems the active engine's scene takes (SceneConfig::stems).
    int engineStems() noexcept;
    /// The MIDI input's notes of the current block, in time order (audio thread; fixed size).
    std::array<core::MidiNoteEvent, kMaxNotesIn> notesIn_ {};
    int notesInCount_ = 0, notesInNext_ = 0;
    std::atomic<std::uint64_t> notesInDropped_ {0};

    MappingOutputs outputs_;
    StepPublisher& published_;   ///< instrument_'s
};

} // namespace armadillo::live
