#pragma once
// The control step of the live rig, shared by the plugin (which runs it at the head of each audio
// block) and tested without JUCE: engine hand-over, source choice, bounded fusion, the scene's
// parameters, Engine::control, and the engine's audio.
//
// Threads (each method names its own):
//  - control side (real-time): tick(), render(), active(). One thread at a time: whoever holds
//    the front end's control token (the audio thread in the plugin, its idle clock otherwise).
//    No allocation, lock, I/O or exception (Tests/Live/RealtimeLoopTests.cpp proves it).
//  - builder side (message thread, prepareToPlay): offer(), collect(), replace(). Engines are
//    built and destroyed here, never on the control side.
//  - producers (device link, OSC receiver, simulator clock): input(kind).push…/store….
#include "Core/Handover.h"
#include "Core/Pose.h"
#include "Core/Scene.h"
#include "Fusion/ArmTracker.h"
#include "Engine/Engine.h"
#include "Engine/PanicGesture.h"
#include "Live/Step/LiveInput.h"
#include <array>
#include <atomic>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

namespace armadillo::engine {
struct MotionRows;
}

namespace armadillo::live {

class CuePlayer;

/// Rows of a recording that stand in for a source's mailbox at one step (the offline clock,
/// Live/Session/RowClock.h): rows [first, end) of `rows`, fused in order in full precision,
/// none dropped — a file's rows are the source's own samples, not a live queue. None: `rows` null.
struct RecordedRows {
    const engine::MotionRows* rows = nullptr;
    std::size_t first = 0, end = 0;
};

/// The tracker's state after rows [first, end) (its state as it was when the span is empty).
core::ArmState fuseRecorded(const RecordedRows& rows, fusion::ArmTracker& tracker);

/// Where the arm comes from (the plugin's `source` choice, INTERFACES.md order).
enum class SourceKind : int { Device = 0, Simulator = 1, Osc = 2, HostAutomation = 3 };
inline constexpr int kSourceCount = 4;
inline bool isLiveSource(SourceKind s) noexcept { return s != SourceKind::HostAutomation; }

/// An engine ready to run, with the front end's parameter cells for its scene.
struct EngineSlot {
    std::unique_ptr<engine::Engine> engine;
    std::string sceneName;
    /// Per Scene::parameters() index: where the front end keeps its value (nullptr: not exposed).
    std::vector<const std::atomic<float>*> params;
    std::vector<float> sent;      ///< last value given to Scene::setParameter (NaN = never); control side
    std::uint64_t generation = 0; ///< counts engines built by the front end
};

struct ControlStep {
    SourceKind source = SourceKind::HostAutomation;
    core::Pose automation {};     ///< deg; the arm under SourceKind::HostAutomation
    core::Transport transport {};
    double dt = 0.005;            ///< s since the previous step
    /// s the previous step's levels really stayed on the motor when that is not dt (a front end
    /// whose link sends levels at their time: after a host stall, LevelSchedule::onTime); < 0: dt.
    double motorOnTime = -1.0;
    /// A set list's cues (Live/Stage/SetList.h) run in place of the active engine: the arm is fused as
    /// always, then CuePlayer::control gives the levels (null: the active engine's control()).
    /// The front end keeps the player alive while it passes it here.
    CuePlayer* cues = nullptr;
    /// The front end is in panic (docs/STAGE.md): the engine (and every cue) is panicked before
    /// its control() runs, so an engine swapped in at this step is all-off from its first step.
    bool panic = false;
    /// The panic gesture is on (docs/STAGE.md, Engine/PanicGesture.h): the right forearm hanging
    /// straight down for 2 s panics the engine and every cue at this step (ControlResult::gesturePanic).
    /// Off: a hang in progress is forgotten.
    bool panicGesture = false;
    /// Two arms (docs/STAGE.md): the left arm's state this step, fused by the front end from its
    /// own source (null: one arm). An engine built with EngineConfig::twoArms hears both arms
    /// (Engine::control(right, left, …)), and so do a set list's cues built with twoArms; any
    /// other engine, the right one.
    const core::ArmState* leftArm = nullptr;
    /// The offline clock's rows (a recording, `render`): the right arm is fused from them in
    /// place of `source`'s mailbox, and the left arm from `recordedLeft` (LeftArm::fuse).
    RecordedRows recorded {};
    RecordedRows recordedLeft {};
    /// s on the monotonic clock: only live samples that arrived by then are fused at this step
    /// (LiveImu::arrival). The plugin places each step at the block position of its sample's
    /// arrival (BlockControl, issue 36); +∞ (the default): everything waiting.
    double arrivalCutoff = std::numeric_limits<double>::infinity();
};

struct ControlResult {
    core::ArmState arm {};
    core::MotorLevels levels {};
    bool ran = false;             ///< false: no engine to run
    bool swapped = false;         ///< an offered engine took over at this step
    /// The panic gesture fired at this step: the engine and step.cues are panicked; the front end
    /// records it as its own panic (the plugin's stage) and panics what it runs beside the loop.
    bool gesturePanic = false;
};

class ControlLoop {
public:
    /// IMU samples fused per step at most. A source that delivered more since the last step
    /// (a burst after a stall, a source switch with a full queue) has its oldest dropped and
    /// counted: the arm follows the newest motion, and a step's work stays bounded.
    static constexpr int kMaxImuPerStep = 8;

    ControlLoop();
    ~ControlLoop();
    ControlLoop(const ControlLoop&) = delete;
    ControlLoop& operator=(const ControlLoop&) = delete;

    /// Producers: the mailbox of a live source (HostAutomation has none: the Device one is returned).
    LiveInput& input(SourceKind kind) noexcept;

    // Builder side ----------------------------------------------------------------------------
    /// Hands an engine to the control side; it takes over at the start of the next tick(). False
    /// (the slot is given back untouched) while an earlier hand-over or retired engine is pending:
    /// call collect() and offer it again.
    bool offer(std::unique_ptr<EngineSlot>& slot) noexcept { return engines_.offer(slot); }
    /// Whether offer() would take an engine now (nothing pending, nothing retired left to collect).
    bool canOffer() const noexcept { return engines_.canOffer(); }
    /// Deletes the engine the control side gave up, if any. Builder side only.
    void collect() noexcept { engines_.collect(); }
    /// The engine the control side gave up, if any, for a builder that keeps it alive while other
    /// threads may still read it (a live session's scene change). Builder side only.
    std::unique_ptr<EngineSlot> takeRetired() noexcept { return engines_.takeRetired(); }
    /// Installs an engine at once. Only while the control side is known not to run (the caller
    /// holds the control token, or nothing runs yet); drops anything pending or retired.
    void replace(std::unique_ptr<EngineSlot> slot) noexcept;
    /// The newest engine: the pending one, else the active one (builder side, for UIs that ask
    /// the scene lock-free questions). Valid until the next collect()/replace().
    EngineSlot* newest() noexcept { return engines_.newest(); }

    // Control side (real-time) ----------------------------------------------------------------
    ControlResult tick(const ControlStep& step) noexcept;
    void render(float* left, float* right, int numSamples) noexcept;
    /// The audio input the active engine's scene listens to (Engine::processInput), before
    /// render() of the same samples.
    void processInput(const float* const* in, int channels, int numSamples) noexcept;
    /// The instrument's MIDI notes of the coming block for the active engine's scene
    /// (Engine::processMidi), before processInput() of the same samples.
    void processMidi(const core::MidiNoteEvent* events, int count) noexcept;
    EngineSlot* active() noexcept { return engines_.active(); }
    /// Control side: the arrival (monotonic s) of the oldest sample of `source` not yet fused —
    /// the front IMU sample, else a new orientation — or +∞ when none waits (always for host
    /// automation). The plugin steps at that sample's place in the block.
    double nextArrival(SourceKind source) noexcept;
    /// Forgets the arm (tracker) and which source ran: the next tick starts afresh.
    void resetArm() noexcept;

    /// IMU samples dropped because more than kMaxImuPerStep were waiting (any thread).
    std::uint64_t droppedImu() const noexcept { return droppedImu_.load(std::memory_order_relaxed); }
    /// Engine hand-overs done on the control side (any thread).
    std::uint64_t swaps() const noexcept { return swaps_.load(std::memory_order_relaxed); }

private:
    void swapInPending() noexcept;
    core::ArmState fuse(LiveInput& in, double cutoff) noexcept;

    std::array<LiveInput, 3> inputs_;   // device, simulator, OSC
    core::Handover<EngineSlot> engines_; // builder → control side (Core/Handover.h)

    fusion::ArmTracker tracker_;        // control side
    double clock_ = 0.0;                // s, advanced by dt per step
    engine::PanicGesture panicGesture_; // control side: the right arm's hang (ControlStep::panicGesture)
    int lastSource_ = -1;
    std::uint64_t lastOrientationSerial_ = 0;
    LiveOrientation lastOrientation_ {};
    std::atomic<std::uint64_t> droppedImu_ {0};
    std::atomic<std::uint64_t> swaps_ {0};
};

/// One arm's fusion for one control step — the right arm's source in ControlLoop, a left arm's in
/// `play` (LiveSession) and in the plugin (Live/Step/LeftArm.h): more than
/// ControlLoop::kMaxImuPerStep IMU samples waiting → the oldest are dropped (counted in
/// `dropped` when given) and the newest fused; no IMU sample this step → the newest orientation
/// of a sender that fuses itself, once (`last` is what was read, `lastUsedSerial` the serial
/// last fused; both the caller's, zero to start afresh). Returns the tracker's state after it.
/// Real-time: no allocation, lock or throw.
/// With a finite `cutoff` (monotonic s) only samples that arrived by then are fused (IMU samples
/// in order; the orientation when its arrival is not later).
core::ArmState fuseStep(LiveInput& in, fusion::ArmTracker& tracker, LiveOrientation& last, std::uint64_t& lastUsedSerial,
                  std::atomic<std::uint64_t>* dropped = nullptr,
                  double cutoff = std::numeric_limits<double>::infinity()) noexcept;

} // namespace armadillo::live
