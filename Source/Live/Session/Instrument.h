#pragma once
// The instrument's core, once for every clock (issue 45): the parts of the live instrument that do
// not depend on what drives it, built in one order and torn down in the reverse, and the one
// control step with what follows it. `play`, `read`, `navigate` and Pd's [armadillo] hold one in
// LiveSession (the source's clock: a packet → step); the app, the plugin and Pd's [armadillo~]
// hold one in BlockInstrument (the block clock: BlockControl's 200 Hz grid and its idle clock);
// `render` holds one in RowClock (a motion file's rows: one step per row, Live/Session/RowClock.h).
// Each clock adds only what is its own: how its sources are described (from a command line, or
// chosen while it runs), where its levels go, its audio and its recordings.
//
// What it owns, in the order it is built:
//  - MessagesRig     messages on the arm (MQTT): first, so it goes last — a braille scene may still
//                    hold a message its presenter handed over until the engines are gone;
//  - NavigationRig   a walk's route and position source: before the loop, because the navigation
//                    scene reads its link until its engine goes;
//  - ControlLoop     the engine(s), the sources' mailboxes and the fusion (ControlLoop.h);
//  - Stage           set list, panic and resume; every stage command applied by one switch;
//  - LeftArm         the second arm's mailbox and tracker (off with one arm): before the clock's
//                    sources, which write its mailbox;
//  - StepRunner      the one control step (StepRunner.h);
//  - StepPublisher   what each step leaves for the rest: the frame and the gestures;
//  - the sources     each arm's source, opened by the clock that drives it from a description
//                    through the registry (Live/Sources/SourceRegistry.h) into the slot kept
//                    here: last, so they close first — no source thread writes a mailbox, the
//                    left arm or the publisher that has gone.
//
// The step (control side: the source's thread, or the block clock's token holder; real-time, no
// allocation, lock, I/O or throw): beginStage() at the start of a packet's or a block's work, then
// step() once per control update. Both say, once for every clock, when the mapping's sounding
// notes must be silenced: at the first moment of a panic — a stage command, a key, MIDI, OSC, the
// web page or the panic gesture — and not again until resume.
#include "Live/Outputs/MessagesRig.h"
#include "Live/Outputs/StepPublisher.h"
#include "Live/Stage/Stage.h"
#include "Live/Step/ControlLoop.h"
#include "Live/Step/LeftArm.h"
#include "Live/Step/StepRunner.h"
#include "Live/Sources/SourceRegistry.h"
#include "Mapping/Mapper.h"
#include "Navigation/NavigationRig.h"
#include <array>

namespace armadillo::live {

class Instrument {
public:
    Instrument() = default;
    ~Instrument() = default;
    Instrument(const Instrument&) = delete;
    Instrument& operator=(const Instrument&) = delete;

    MessagesRig& messages() noexcept { return messages_; }
    const MessagesRig& messages() const noexcept { return messages_; }
    navigation::NavigationRig& navigation() noexcept { return navigation_; }
    const navigation::NavigationRig& navigation() const noexcept { return navigation_; }
    ControlLoop& loop() noexcept { return loop_; }
    const ControlLoop& loop() const noexcept { return loop_; }
    Stage& stage() noexcept { return stage_; }
    const Stage& stage() const noexcept { return stage_; }
    LeftArm& leftArm() noexcept { return leftArm_; }
    const LeftArm& leftArm() const noexcept { return leftArm_; }
    StepRunner& runner() noexcept { return runner_; }
    const StepRunner& runner() const noexcept { return runner_; }
    StepPublisher& published() noexcept { return published_; }
    const StepPublisher& published() const noexcept { return published_; }

    /// Where each arm's source is kept: the right arm's forearm (it fills the Device mailbox),
    /// its OSC sender (the Osc mailbox) and the left arm's source (LeftArm's mailbox).
    enum class Feed { Device, Osc, Left };
    ArmSourceSlot& source(Feed feed) noexcept { return sources_[static_cast<std::size_t>(feed)]; }
    const ArmSourceSlot& source(Feed feed) const noexcept { return sources_[static_cast<std::size_t>(feed)]; }

    /// The start of a packet's or a block's work (control side): the stage's set list, cue
    /// requests, panic and resume reach the engine and the cues (StepRunner::beginStage).
    struct Begun {
        StepRunner::StageChange change = StepRunner::StageChange::None;
        bool silenceMapping = false;   ///< a panic starts now: end the mapping's notes (Mapper::panic)
    };
    Begun beginStage() noexcept;

    /// One control step, as every clock takes it: the left arm fused (when on), the step run
    /// (StepRunner::step), and the frame published at time `t` with the levels when they reach
    /// the motors (`levelsOut`; zeros otherwise) and the engine's gestures.
    struct Stepped {
        ControlResult result {};
        const core::ArmState* leftArm = nullptr;   ///< this step's left arm (null: one arm)
        engine::Engine* engine = nullptr;          ///< the engine that sounds (a cue's with a set list)
        bool panicked = false;                     ///< in panic (the stage's, or this step's gesture): only stage commands map
        bool silenceMapping = false;               ///< the panic's first step the mapping hears of: end its notes now
    };
    Stepped step(ControlStep step, double t, bool levelsOut) noexcept;

    /// The audio side of what plays (the block clock's audio, or the rows' clock between two
    /// rows; real-time): the set list's cues when the stage has one, else the loop's engine. In
    /// each block: the instrument's MIDI notes, then the recording it hears, then its sound.
    void processMidi(const core::MidiNoteEvent* events, int count) noexcept;
    void processInput(const float* const* in, int channels, int numSamples) noexcept;
    void render(float* left, float* right, int numSamples) noexcept;

    /// Two arms: the left arm's levels of the last step (the set list's, after its own safety
    /// stage; else the engine's); null with one arm. Control side.
    const core::MotorLevels* leftLevels() noexcept;

    /// The mapping's view of a step (Mapping/Mapper.h): both arms, the scene's values, the step's
    /// gestures, and stage commands only while in panic. `t` is the mapping's time of the step.
    mapping::MappingInput mappingInput(const Stepped& stepped, double t) const noexcept;

private:
    MessagesRig messages_;
    navigation::NavigationRig navigation_;
    ControlLoop loop_;
    Stage stage_;
    LeftArm leftArm_;
    StepRunner runner_ {loop_, &stage_};
    StepPublisher published_;
    bool mappingSilenced_ = false;   // control side: the mapping was silenced for the panic that holds
    std::array<ArmSourceSlot, 3> sources_;   // last: closed first
};

} // namespace armadillo::live
