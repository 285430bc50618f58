#include "Plugin/MidiPort.h"
#include <juce_audio_devices/juce_audio_devices.h>

namespace armadillo::plugin {

MidiPort::MidiPort() = default;

MidiPort::~MidiPort()
{
    close();
}

bool MidiPort::open(const juce::String& name, juce::String& why)
{
    close();
    std::lock_guard<std::mutex> lock(mutex_);
#if JUCE_LINUX || JUCE_BSD
    // The ALSA sequencer lives in the kernel (module snd-seq) behind /dev/snd/seq; without it
    // JUCE's ALSA client has no handle and cannot make a port. Name that cause first.
    const juce::File seq("/dev/snd/seq");
    if (! seq.exists()) {
        why_ = "No MIDI output port: the ALSA sequencer is not available (/dev/snd/seq does not exist; load the "
               "snd-seq kernel module, e.g. 'sudo modprobe snd-seq', and restart the app). The mapping still runs; "
               "its MIDI reaches only the MIDI output chosen in the app's audio/MIDI settings.";
        why = why_;
        return false;
    }
    if (! seq.hasReadAccess() || ! seq.hasWriteAccess()) {
        why_ = "No MIDI output port: /dev/snd/seq is not readable and writable by this user (add the user to the "
               "'audio' group). The mapping still runs; its MIDI reaches only the MIDI output chosen in the app's "
               "audio/MIDI settings.";
        why = why_;
        return false;
    }
#endif
#if JUCE_LINUX || JUCE_BSD || JUCE_MAC || JUCE_IOS
    out_ = juce::MidiOutput::createNewDevice(name);
#endif
    if (out_ == nullptr) {
        why_ = "No MIDI output port: the ALSA sequencer refused to create the port '" + name
               + "' (is the sequencer running? 'cat /proc/asound/seq/clients' lists it).";
        why = why_;
        return false;
    }
    why_ = {};
    why = {};
    queue_.setOpen(true);   // nothing from before the port existed
    return true;
}

void MidiPort::close()
{
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.setOpen(false);
    out_.reset();
    if (why_.isEmpty()) why_ = "MIDI output port closed";
}

bool MidiPort::isOpen() const
{
    return queue_.isOpen();
}

juce::String MidiPort::status() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (out_ == nullptr) return why_;
    return "MIDI out: ALSA sequencer port '" + out_->getName() + "' (" + out_->getIdentifier() + "), "
           + juce::String(static_cast<juce::int64>(sent())) + " events sent"
           + (dropped() > 0 ? ", " + juce::String(static_cast<juce::int64>(dropped())) + " dropped (queue full)" : juce::String());
}

int MidiPort::drain()
{
    std::lock_guard<std::mutex> lock(mutex_);
    int n = 0;
    live::MidiOutQueue::Event e;
    while (queue_.pop(e)) {
        if (out_ == nullptr) continue;
        out_->sendMessageNow(juce::MidiMessage(e.bytes, e.size));
        ++n;
    }
    sent_.fetch_add(static_cast<std::uint64_t>(n), std::memory_order_relaxed);
    return n;
}

} // namespace armadillo::plugin
