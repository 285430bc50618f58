#pragma once
// MIDI out through the ALSA sequencer (`armadillo play --midi-out NAME`): a client "ARMadillo"
// with one readable, subscribable output port NAME, which JACK (a2jmidid), PipeWire and every
// Linux DAW see and connect to. Events leave directly (no queue, no scheduling): a mapping's event
// reaches the sequencer microseconds after the sensor sample that produced it.
#include <cstddef>
#include <cstdint>
#include <string>

typedef struct _snd_seq snd_seq_t;

namespace armadillo::audio {

class SequencerOut {
public:
    /// Opens the sequencer and creates the port. IoError naming the cause when the sequencer is
    /// not there (no /dev/snd/seq: the snd-seq kernel module is not loaded, or a container
    /// without the sound devices) or the port cannot be made.
    explicit SequencerOut(const std::string& portName);
    ~SequencerOut();
    SequencerOut(const SequencerOut&) = delete;
    SequencerOut& operator=(const SequencerOut&) = delete;

    /// One channel message (note on/off, CC, program, pressure, pitch bend; 2 or 3 bytes with
    /// the status byte first). Real-time: builds the sequencer event on the stack and hands it
    /// to snd_seq_event_output_direct. False when the message is not a channel message or ALSA
    /// refused it (counted).
    bool send(const std::uint8_t* bytes, std::size_t size) noexcept;
    int client() const noexcept { return client_; }
    int port() const noexcept { return port_; }
    std::uint64_t sent() const noexcept { return sent_; }
    std::uint64_t failed() const noexcept { return failed_; }

private:
    snd_seq_t* seq_ = nullptr;
    int client_ = -1, port_ = -1;
    std::uint64_t sent_ = 0, failed_ = 0;
};

/// Fills an ALSA sequencer event for a MIDI channel message without sending it (what send()
/// does before snd_seq_event_output_direct; the latency benchmark times it where no sequencer
/// exists). `event` must point at a snd_seq_event_t. False for anything but a channel message.
bool encodeSequencerEvent(const std::uint8_t* bytes, std::size_t size, int sourcePort, void* event) noexcept;

} // namespace armadillo::audio
