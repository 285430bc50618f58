#include "Mapping/MidiFile.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include <algorithm>
#include <cmath>

namespace armadillo::mapping {

namespace {
void be32(std::vector<std::uint8_t>& out, std::uint32_t v)
{
    for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<std::uint8_t>(v >> s));
}
void be16(std::vector<std::uint8_t>& out, std::uint32_t v)
{
    out.push_back(static_cast<std::uint8_t>(v >> 8));
    out.push_back(static_cast<std::uint8_t>(v));
}
/// Variable-length quantity (SMF 1.0: 7 bits a byte, most significant first, bit 7 = "more").
void vlq(std::vector<std::uint8_t>& out, std::uint32_t v)
{
    std::uint8_t buf[5];
    int n = 0;
    buf[n++] = static_cast<std::uint8_t>(v & 0x7F);
    while ((v >>= 7) != 0) buf[n++] = static_cast<std::uint8_t>(0x80 | (v & 0x7F));
    while (n > 0) out.push_back(buf[--n]);
}
void chunk(std::vector<std::uint8_t>& out, const char* id, const std::vector<std::uint8_t>& body)
{
    out.insert(out.end(), id, id + 4);
    be32(out, static_cast<std::uint32_t>(body.size()));
    out.insert(out.end(), body.begin(), body.end());
}
} // namespace

std::uint32_t smfTicks(double seconds) noexcept
{
    if (!(seconds > 0.0)) return 0;
    const double ticks = seconds * 1e6 / kSmfMicrosPerQuarter * kSmfTicksPerQuarter;
    return ticks >= 4.0e9 ? 4000000000u : static_cast<std::uint32_t>(std::llround(ticks));
}

void MidiFileWriter::add(const MidiEvent& e)
{
    if (e.size >= 1 && e.size <= 3) events_.push_back(e);
}

void MidiFileWriter::addAll(const MappingOutput& out)
{
    for (int i = 0; i < out.midiCount; ++i) add(out.midi[static_cast<std::size_t>(i)]);
}

std::vector<std::uint8_t> MidiFileWriter::bytes() const
{
    std::vector<std::size_t> order(events_.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return events_[a].t < events_[b].t; });

    std::vector<std::uint8_t> tempo;   // track 0: the tempo the tick times assume
    vlq(tempo, 0);
    tempo.insert(tempo.end(), {0xFF, 0x51, 0x03});
    tempo.push_back(static_cast<std::uint8_t>(kSmfMicrosPerQuarter >> 16));
    tempo.push_back(static_cast<std::uint8_t>(kSmfMicrosPerQuarter >> 8));
    tempo.push_back(static_cast<std::uint8_t>(kSmfMicrosPerQuarter));
    vlq(tempo, 0);
    tempo.insert(tempo.end(), {0xFF, 0x2F, 0x00});

    std::vector<std::uint8_t> track;   // track 1: the mapped events, no running status
    static constexpr char kName[] = "ARMadillo mapping";
    vlq(track, 0);
    track.insert(track.end(), {0xFF, 0x03});
    vlq(track, sizeof kName - 1);
    track.insert(track.end(), kName, kName + sizeof kName - 1);
    std::uint32_t last = 0;
    for (std::size_t i : order) {
        const MidiEvent& e = events_[i];
        const std::uint32_t tick = std::max(last, smfTicks(e.t - t0_));
        vlq(track, tick - last);
        last = tick;
        track.insert(track.end(), e.bytes.begin(), e.bytes.begin() + e.size);
    }
    vlq(track, 0);
    track.insert(track.end(), {0xFF, 0x2F, 0x00});

    std::vector<std::uint8_t> file;
    std::vector<std::uint8_t> header;
    be16(header, 1);                    // format 1
    be16(header, 2);                    // two tracks
    be16(header, kSmfTicksPerQuarter);  // metrical division
    chunk(file, "MThd", header);
    chunk(file, "MTrk", tempo);
    chunk(file, "MTrk", track);
    return file;
}

void MidiFileWriter::write(const std::string& path) const
{
    const std::vector<std::uint8_t> b = bytes();
    core::writeFileAtomically(path, std::string_view(reinterpret_cast<const char*>(b.data()), b.size()));
}

} // namespace armadillo::mapping
