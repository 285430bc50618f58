#include "Audio/SequencerOut.h"
#include "Core/Errors.h"
#include <alsa/asoundlib.h>
#include <cerrno>
#include <cstring>
#include <mutex>
#include <sys/stat.h>

namespace armadillo::audio {

namespace {
/// alsa-lib prints its own line for every failed open; the IoError says it better, once.
void quietAlsa(const char*, int, const char*, int, const char*, ...) {}
} // namespace

bool encodeSequencerEvent(const std::uint8_t* bytes, std::size_t size, int sourcePort, void* event) noexcept
{
    if (bytes == nullptr || size < 2 || event == nullptr) return false;
    auto* ev = static_cast<snd_seq_event_t*>(event);
    snd_seq_ev_clear(ev);
    const int status = bytes[0];
    const auto channel = static_cast<unsigned char>(status & 0x0F);
    const int data1 = bytes[1] & 0x7F;
    const int data2 = size >= 3 ? bytes[2] & 0x7F : 0;
    switch (status & 0xF0) {
    case 0x80: if (size < 3) return false; snd_seq_ev_set_noteoff(ev, channel, data1, data2); break;
    case 0x90: if (size < 3) return false; snd_seq_ev_set_noteon(ev, channel, data1, data2); break;
    case 0xA0: if (size < 3) return false; snd_seq_ev_set_keypress(ev, channel, data1, data2); break;
    case 0xB0: if (size < 3) return false; snd_seq_ev_set_controller(ev, channel, data1, data2); break;
    case 0xC0: snd_seq_ev_set_pgmchange(ev, channel, data1); break;
    case 0xD0: snd_seq_ev_set_chanpress(ev, channel, data1); break;
    case 0xE0: if (size < 3) return false; snd_seq_ev_set_pitchbend(ev, channel, (data1 | (data2 << 7)) - 8192); break;   // ALSA: −8192…8191
    default: return false;
    }
    snd_seq_ev_set_source(ev, static_cast<unsigned char>(sourcePort));
    snd_seq_ev_set_subs(ev);
    snd_seq_ev_set_direct(ev);
    return true;
}

SequencerOut::SequencerOut(const std::string& portName)
{
    if (portName.empty()) throw core::IoError("--midi-out needs a port name");
    static std::once_flag quiet;
    std::call_once(quiet, [] { snd_lib_error_set_handler(quietAlsa); });
    int err = snd_seq_open(&seq_, "default", SND_SEQ_OPEN_OUTPUT, 0);
    if (err < 0) {
        struct stat st {};
        const bool device = ::stat("/dev/snd/seq", &st) == 0;
        throw core::IoError(std::string("--midi-out ") + portName + ": cannot open the ALSA sequencer: " + snd_strerror(err) +
                      (device ? "" : " (/dev/snd/seq does not exist: load the snd-seq kernel module, e.g. `sudo modprobe snd-seq`, "
                                     "or give the container the sound devices)"));
    }
    snd_seq_set_client_name(seq_, "ARMadillo");
    port_ = snd_seq_create_simple_port(seq_, portName.c_str(), SND_SEQ_PORT_CAP_READ | SND_SEQ_PORT_CAP_SUBS_READ,
                                       SND_SEQ_PORT_TYPE_MIDI_GENERIC | SND_SEQ_PORT_TYPE_APPLICATION);
    if (port_ < 0) {
        const std::string why = snd_strerror(port_);
        snd_seq_close(seq_);
        seq_ = nullptr;
        throw core::IoError("--midi-out " + portName + ": cannot create the sequencer port: " + why);
    }
    client_ = snd_seq_client_id(seq_);
}

SequencerOut::~SequencerOut()
{
    if (seq_) {
        snd_seq_drain_output(seq_);
        snd_seq_close(seq_);
    }
}

bool SequencerOut::send(const std::uint8_t* bytes, std::size_t size) noexcept
{
    snd_seq_event_t ev;
    if (!encodeSequencerEvent(bytes, size, port_, &ev) || snd_seq_event_output_direct(seq_, &ev) < 0) {
        ++failed_;
        return false;
    }
    ++sent_;
    return true;
}

} // namespace armadillo::audio
