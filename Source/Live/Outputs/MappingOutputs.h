#pragma once
// What the mapping's control-side run on the block clock (BlockControl.h) hands to the non-real-time side, each over a
// lock-free path (STYLE.md convention 5; docs/PLUGIN.md "Mapping"):
//  - macro values (8 atomics) → the message thread writes the `macro1…8` parameters with change
//    gestures (a DAW records them);
//  - encoded OSC packets (a fixed-size SPSC queue) → the control clock sends them (socket I/O
//    never on the audio thread);
//  - channel messages arriving at the plugin's MIDI input (an SPSC queue) → the editor's
//    "learn destination";
//  - the range a source covered while "learn range" is on (atomics).
//
// Threads: the push/set side is the control-token holder (audio thread or idle clock: real-time,
// no allocation, lock or I/O), except pushIncoming (the audio thread only); each pop side is one
// named non-audio thread.
#include "Core/SpscQueue.h"
#include "Mapping/Mapper.h"
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>

namespace armadillo::live {

/// One channel message seen at the plugin's MIDI input (1–3 bytes).
struct IncomingMidi {
    std::uint8_t bytes[3] {};
    std::uint8_t size = 0;
};

class MappingOutputs {
public:
    MappingOutputs()
    {
        for (auto& m : macros_) m.store(std::numeric_limits<float>::quiet_NaN(), std::memory_order_relaxed);
    }

    // Control side ------------------------------------------------------------------------------
    void setMacro(int index, float value01) noexcept
    {
        if (index >= 0 && index < mapping::kMacroCount && std::isfinite(value01))
            macros_[static_cast<std::size_t>(index)].store(value01 < 0.0f ? 0.0f : (value01 > 1.0f ? 1.0f : value01),
                                                           std::memory_order_relaxed);
    }
    bool pushOsc(const mapping::OscPacket& p) noexcept
    {
        if (osc_.push(p)) return true;
        oscDropped_.fetch_add(1, std::memory_order_relaxed);
        return false;
    }
    /// The audio thread, for each channel message at the MIDI input (dropped when full).
    void pushIncoming(const IncomingMidi& m) noexcept { (void) incoming_.push(m); }

    // Range learning: the message thread names the source (learnSource >= 0 starts, −1 stops);
    // the control side reads it every step and publishes the smallest and largest value seen.
    std::atomic<int> learnSource {-1};            ///< mapping::SourceKind as int, −1 = off
    std::atomic<bool> learnForward {false};       ///< azimuth relative to forward
    std::atomic<std::uint32_t> learnGeneration {0};   ///< bumped by the message thread to restart
    std::atomic<double> learnedLo {0.0}, learnedHi {0.0};
    std::atomic<int> learnedCount {0};

    // Readers -----------------------------------------------------------------------------------
    /// Any thread: the newest value the mapping wrote to macro `index` (0-based), NaN when none.
    float macro(int index) const noexcept
    {
        return index >= 0 && index < mapping::kMacroCount ? macros_[static_cast<std::size_t>(index)].load(std::memory_order_relaxed)
                                                           : std::numeric_limits<float>::quiet_NaN();
    }
    /// Message thread: a macro no mapping drives any longer goes back to "none".
    void releaseMacro(int index) noexcept
    {
        if (index >= 0 && index < mapping::kMacroCount)
            macros_[static_cast<std::size_t>(index)].store(std::numeric_limits<float>::quiet_NaN(), std::memory_order_relaxed);
    }
    /// The control clock (one consumer).
    bool popOsc(mapping::OscPacket& p) noexcept { return osc_.pop(p); }
    std::uint64_t oscDropped() const noexcept { return oscDropped_.load(std::memory_order_relaxed); }
    /// The message thread (one consumer).
    bool popIncoming(IncomingMidi& m) noexcept { return incoming_.pop(m); }

private:
    std::array<std::atomic<float>, mapping::kMacroCount> macros_ {};
    core::SpscQueue<mapping::OscPacket, 256> osc_;
    core::SpscQueue<IncomingMidi, 256> incoming_;
    std::atomic<std::uint64_t> oscDropped_ {0};
};

} // namespace armadillo::live
