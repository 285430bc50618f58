#pragma once
// The standalone app's own MIDI output: a virtual ALSA sequencer port ("ARMadillo", created with
// juce::MidiOutput::createNewDevice, which on Linux makes an ALSA seq port that JACK, a2jmidid and
// every Linux DAW can connect to), carrying what the mapping sends (docs/PLUGIN.md "MIDI out").
//
// Threads:
//  - message thread: open() / close() (the sequencer client and port are created and destroyed
//    there only), status().
//  - control side (real-time, the control-token holder): queue().push() (Live/Outputs/MidiOutQueue.h).
//  - the control clock (one non-audio thread): drain() — sends the queued events to the port.
//    The port is shared with open()/close() under a mutex the audio thread never takes.
#include "Live/Outputs/MidiOutQueue.h"
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

    /// The control side's queue (Live/Outputs/MidiOutQueue.h): what the rig pushes, drain() sends.
    live::MidiOutQueue& queue() noexcept { return queue_; }
    /// Control clock: sends every queued event. Returns how many were sent.
    int drain();

    std::uint64_t sent() const noexcept { return sent_.load(std::memory_order_relaxed); }
    std::uint64_t dropped() const noexcept { return queue_.dropped(); }

private:
    mutable std::mutex mutex_;                 // open/close (message) vs drain (clock); never audio
    std::unique_ptr<juce::MidiOutput> out_;
    juce::String why_ = "MIDI output port not opened";
    live::MidiOutQueue queue_;
    std::atomic<std::uint64_t> sent_ {0};
};

} // namespace armadillo::plugin
