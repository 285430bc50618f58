#pragma once
// The MIDI an audio-clocked rig sends outside the host's buffer (the standalone app's own port):
// the control side pushes each event into a fixed-size SPSC queue — never blocks, never
// allocates, a full queue or a closed port drops and counts — and one non-audio thread (the
// control clock) pops them and hands them to the port (Plugin/MidiPort, an ALSA sequencer port).
#include "Core/SpscQueue.h"
#include <atomic>
#include <cstdint>

namespace armadillo::live {

class MidiOutQueue {
public:
    struct Event {
        std::uint8_t bytes[3] {};
        std::uint8_t size = 0;
    };

    /// Control side: one MIDI message (1–3 bytes). False when the queue is full or the port is
    /// closed (nothing is queued then).
    bool push(const std::uint8_t* bytes, int size) noexcept
    {
        if (! open_.load(std::memory_order_acquire) || size < 1 || size > 3) return false;
        Event e;
        for (int i = 0; i < size; ++i) e.bytes[i] = bytes[i];
        e.size = static_cast<std::uint8_t>(size);
        if (queue_.push(e)) return true;
        dropped_.fetch_add(1, std::memory_order_relaxed);
        return false;
    }
    /// The consumer thread: the oldest queued event; false when none.
    bool pop(Event& e) noexcept { return queue_.pop(e); }
    /// The port's owner: events are queued only while open (opening discards what was queued).
    void setOpen(bool open) noexcept
    {
        if (open) {
            Event e;
            while (queue_.pop(e)) {}
        }
        open_.store(open, std::memory_order_release);
    }
    bool isOpen() const noexcept { return open_.load(std::memory_order_acquire); }
    std::uint64_t dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }

private:
    std::atomic<bool> open_ {false};
    core::SpscQueue<Event, 4096> queue_;
    std::atomic<std::uint64_t> dropped_ {0};
};

} // namespace armadillo::live
