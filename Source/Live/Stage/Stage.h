#pragma once
// On stage in the plugin and the app (docs/STAGE.md, issue 28): a set list's CuePlayer handed to
// the control side lock-free, panic / resume, cue steps, and the MIDI stage messages of the
// plugin's input.
//
// Threads:
//  - message thread (and prepareToPlay, audio stopped): offer(), replace(), collect(), newest().
//    A CuePlayer is built and prepared there (every cue's Engine) and deleted there, never on
//    the audio thread (Core/Handover.h: pending → active → retired).
//  - control side (the control-token holder, real-time): beginStep() and cues(). No allocation,
//    lock, I/O or throw.
//  - any thread: panic(), resume(), next(), previous(), cue(i), the MIDI decoding (the audio
//    thread calls it for each input event), the counters. Each is an atomic store or add; the
//    control side applies them at the start of its next block (or idle step).
//
// The MIDI input (any channel; docs/INTERFACES.md "MIDI implementation"):
//   program change N        → cue N (past the end: the last cue)
//   note-on of kNextNote    → next cue       (settable: the cueNextNote setting, −1 = off)
//   note-on of kPrevNote    → previous cue   (settable: the cuePrevNote setting, −1 = off)
//   CC 120 All Sound Off    → panic
//   CC 119, value ≥ 64      → resume (CC 119 is undefined in the MIDI 1.0 table; CC 121 is
//                             Reset All Controllers and is left alone)
#include "Core/Handover.h"
#include "Core/StageCommand.h"
#include "Live/Stage/SetList.h"
#include <atomic>
#include <cstdint>
#include <memory>

namespace armadillo::live {

class Stage {
public:
    static constexpr int kNextNote = 0;     ///< C-1: below any piano's keys, a foot switch's note
    static constexpr int kPrevNote = 1;     ///< C#-1
    static constexpr int kPanicCc = 120;    ///< All Sound Off
    static constexpr int kResumeCc = 119;

    Stage() = default;
    ~Stage();
    Stage(const Stage&) = delete;
    Stage& operator=(const Stage&) = delete;

    // Message thread ------------------------------------------------------------------------------
    /// Hands a set list's player (null: no set list) to the control side; it takes over at the
    /// start of the next block. False (the player is given back) while an earlier hand-over is
    /// in flight: collect() and offer it again.
    bool offer(std::unique_ptr<live::CuePlayer>& player) noexcept;
    /// Installs a player at once; only while the control side is known not to run (the control
    /// token held, or nothing runs yet).
    void replace(std::unique_ptr<live::CuePlayer> player) noexcept;
    /// Deletes the player the control side gave up.
    void collect() noexcept;
    bool canOffer() const noexcept { return players_.canOffer(); }
    /// The newest player (pending, else active; null: no set list), valid until the next
    /// collect()/replace() on this thread: for the UI's cue names and current cue.
    live::CuePlayer* newest() const noexcept
    {
        const Slot* slot = players_.newest();
        return slot != nullptr ? slot->get() : nullptr;
    }

    // Any thread ----------------------------------------------------------------------------------
    /// Every stage command, from wherever it comes (OSC control port, keys, MIDI, a mapping's
    /// "stage" destination, the app's buttons), is applied here and only here: the one switch.
    /// Atomics only; the control side acts on it at the start of its next step (beginStep()).
    void apply(const core::StageCommand& command) noexcept;
    void panic() noexcept;
    void resume() noexcept;
    bool panicked() const noexcept { return panic_.load(std::memory_order_acquire); }
    std::uint32_t panics() const noexcept { return panics_.load(std::memory_order_relaxed); }
    void next() noexcept { delta_.fetch_add(1, std::memory_order_acq_rel); }
    void previous() noexcept { delta_.fetch_sub(1, std::memory_order_acq_rel); }
    void cue(int index) noexcept { goto_.store(index < 0 ? 0 : index, std::memory_order_release); }
    /// One MIDI message of the plugin's input (1–3 bytes) as a stage command (see above): false
    /// when it is none. Real-time.
    bool commandFromMidi(const std::uint8_t* bytes, int size, core::StageCommand& out) const noexcept;
    /// commandFromMidi, then apply(): true when the message was a stage command. Real-time.
    bool handleMidi(const std::uint8_t* bytes, int size) noexcept;
    /// The notes that step the cues (−1: none).
    void setCueNotes(int nextNote, int previousNote) noexcept
    {
        nextNote_.store(nextNote, std::memory_order_relaxed);
        prevNote_.store(previousNote, std::memory_order_relaxed);
    }
    int nextNote() const noexcept { return nextNote_.load(std::memory_order_relaxed); }
    int previousNote() const noexcept { return prevNote_.load(std::memory_order_relaxed); }
    /// The panic gesture (the panicGesture setting; Engine/PanicGesture.h): while on, the
    /// control step panics when the right forearm hangs straight down for 2 s.
    void setPanicGesture(bool on) noexcept { panicGesture_.store(on, std::memory_order_relaxed); }
    bool panicGesture() const noexcept { return panicGesture_.load(std::memory_order_relaxed); }

    // Control side (real-time) --------------------------------------------------------------------
    /// Start of a block (or an idle step): takes an offered player, applies the cue requests
    /// that came since. Returns the player to run (null: the single engine).
    live::CuePlayer* beginStep() noexcept;
    live::CuePlayer* cues() const noexcept
    {
        const Slot* slot = players_.active();
        return slot != nullptr ? slot->get() : nullptr;
    }

private:
    using Slot = std::unique_ptr<live::CuePlayer>;
    core::Handover<Slot> players_;                 // message thread → control side (Core/Handover.h)
    std::atomic<bool> panic_ {false};
    std::atomic<std::uint32_t> panics_ {0};
    std::atomic<int> delta_ {0};                   // next/previous steps not applied yet
    std::atomic<int> goto_ {-1};                   // a cue asked for by index, not applied yet
    std::atomic<int> nextNote_ {kNextNote}, prevNote_ {kPrevNote};
    std::atomic<bool> panicGesture_ {false};
};

} // namespace armadillo::live
