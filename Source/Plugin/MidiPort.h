#pragma once
// The standalone app's own MIDI output: a virtual ALSA sequencer port ("ARMadillo", created with
// juce::MidiOutput::createNewDevice, which on Linux makes an ALSA seq port that JACK, a2jmidid and
// every Linux DAW can connect to), carrying what the mapping sends (docs/PLUGIN.md "MIDI out").
//
// Threads:
//  - message thread: open() / close() (the sequencer client and port are created and destroyed
//    there only), status().
//  - control side (real-time, the control-token holder): push() — copies the event into a
//    fixed-size SPSC queue; never blocks, never allocates; a full queue drops and counts.
//  - the control clock (one non-audio thread): drain() — sends the queued events to the port.
//    The port is shared with open()/close() under a mutex the audio thread never takes.
#include "Core/SpscQueue.h"
#include <juce_core/juce_core.h>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>

namespace juce {
class MidiOutput;
}

namespace armadillo::plugin {

class MidiPort {
public:
    MidiPort();
    ~MidiPort();

    /// Message thread: opens the virtual port `name`. False with the cause (no ALSA sequencer
    /// device, no permission, a platform without virtual ports) in `why`.
    bool open(const juce::String& name, juce::String& why);
    void close();
    bool isOpen() const;
    /// "ALSA sequencer port 'ARMadillo' (client 128:0), 1234 events sent" or why it is closed.
    juce::String status() const;

    /// Control side: one MIDI message (1–3 bytes). False when the queue is full or the port is
    /// closed (nothing is queued then). Inline: the control path needs no JUCE device code.
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
    /// Control clock: sends every queued event. Returns how many were sent.
    int drain();

    std::uint64_t sent() const noexcept { return sent_.load(std::memory_order_relaxed); }
    std::uint64_t dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }

private:
    struct Event {
        std::uint8_t bytes[3] {};
        std::uint8_t size = 0;
    };
    mutable std::mutex mutex_;                 // open/close (message) vs drain (clock); never audio
    std::unique_ptr<juce::MidiOutput> out_;
    juce::String why_ = "MIDI output port not opened";
    std::atomic<bool> open_ {false};
    SpscQueue<Event, 4096> queue_;
    std::atomic<std::uint64_t> sent_ {0}, dropped_ {0};
};

} // namespace armadillo::plugin
