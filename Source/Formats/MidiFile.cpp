// Standard MIDI File reader. Reference: MMA "Standard MIDI Files 1.0" (RP-001), the chunk layout,
// variable-length quantities, running status ("sysex and meta events cancel any running status"),
// and the meta events listed in MidiFile.h.
#include "Formats/MidiFile.h"
#include "Core/Errors.h"
#include <algorithm>
#include <deque>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

namespace armadillo::formats {

namespace {

class Reader {
public:
    Reader(std::string_view bytes, const std::string& source, std::size_t base)
        : bytes_(bytes), source_(source), base_(base) {}

    bool done() const noexcept { return pos_ >= bytes_.size(); }
    std::size_t offset() const noexcept { return base_ + pos_; }

    [[noreturn]] void fail(const std::string& message) const
    {
        throw core::InputError(source_, 0, "byte " + std::to_string(offset()), message);
    }
    std::uint8_t byte()
    {
        if (pos_ >= bytes_.size()) fail("the data ends in the middle of an event");
        return static_cast<std::uint8_t>(bytes_[pos_++]);
    }
    std::uint8_t peek() const
    {
        if (pos_ >= bytes_.size()) fail("the data ends in the middle of an event");
        return static_cast<std::uint8_t>(bytes_[pos_]);
    }
    std::uint32_t variable()
    {
        std::uint32_t v = 0;
        for (int i = 0; i < 4; ++i) {
            const std::uint8_t b = byte();
            v = (v << 7) | (b & 0x7Fu);
            if (!(b & 0x80u)) return v;
        }
        fail("a variable-length number longer than 4 bytes");
    }
    std::string_view take(std::size_t n)
    {
        if (n > bytes_.size() - pos_) fail("an event's data runs past the end of its track");
        const std::string_view s = bytes_.substr(pos_, n);
        pos_ += n;
        return s;
    }

private:
    std::string_view bytes_;
    const std::string& source_;
    std::size_t base_;
    std::size_t pos_ = 0;
};

std::uint32_t be32(std::string_view s, std::size_t at)
{
    return (std::uint32_t(std::uint8_t(s[at])) << 24) | (std::uint32_t(std::uint8_t(s[at + 1])) << 16) |
           (std::uint32_t(std::uint8_t(s[at + 2])) << 8) | std::uint32_t(std::uint8_t(s[at + 3]));
}
std::uint16_t be16(std::string_view s, std::size_t at)
{
    return static_cast<std::uint16_t>((std::uint16_t(std::uint8_t(s[at])) << 8) | std::uint16_t(std::uint8_t(s[at + 1])));
}

/// Text of a meta event: printable ASCII kept, anything else dropped (names and markers only
/// become cue names and comments).
std::string cleanText(std::string_view s)
{
    std::string out;
    for (const char c : s)
        if (c >= 0x20 && c < 0x7F) out += c;
    return out;
}

} // namespace

double MidiFile::secondsAt(std::int64_t tick) const noexcept
{
    if (smpte) return ticksPerSecond > 0.0 ? static_cast<double>(tick) / ticksPerSecond : 0.0;
    double seconds = 0.0;
    for (std::size_t i = 0; i < tempo.size(); ++i) {
        const std::int64_t from = tempo[i].tick;
        if (from >= tick) break;
        const std::int64_t to = i + 1 < tempo.size() ? std::min(tick, tempo[i + 1].tick) : tick;
        seconds += static_cast<double>(to - from) * tempo[i].microsPerQuarter * 1e-6 / ticksPerQuarter;
    }
    return seconds;
}

MidiFile parseMidiFile(std::string_view bytes, const std::string& source)
{
    MidiFile f;
    if (bytes.size() < 14 || bytes.substr(0, 4) != "MThd")
        throw core::InputError(source, 0, "byte 0", "not a Standard MIDI File (no 'MThd' header)");
    const std::uint32_t headerLength = be32(bytes, 4);
    if (headerLength < 6 || headerLength > bytes.size() - 8)
        throw core::InputError(source, 0, "byte 4", "a header chunk of " + std::to_string(headerLength) + " bytes (6 expected)");
    const int format = be16(bytes, 8);
    // bytes 10..11, the number of tracks, is not trusted: the track chunks found count (a wrong
    // count in the header is common and harmless).
    const std::uint16_t division = be16(bytes, 12);
    if (format == 2) throw core::InputError(source, 0, "byte 8", "format 2 (independent sequences) is not supported: only format 0 and 1");
    if (format > 2) throw core::InputError(source, 0, "byte 8", "unknown format " + std::to_string(format));
    f.format = format;
    if (division & 0x8000u) {
        // SMPTE: the high byte is −(frames per second) as a two's-complement byte, the low byte
        // ticks per frame. −29 means 29.97 (30 drop-frame).
        const int fps = -static_cast<int>(static_cast<std::int8_t>(division >> 8));
        const int perFrame = division & 0xFF;
        if ((fps != 24 && fps != 25 && fps != 29 && fps != 30) || perFrame == 0)
            throw core::InputError(source, 0, "byte 12", "an SMPTE division of " + std::to_string(fps) + " frames/s × " + std::to_string(perFrame) + " ticks");
        f.smpte = true;
        f.ticksPerSecond = (fps == 29 ? 29.97 : fps) * perFrame;
    } else {
        if (division == 0) throw core::InputError(source, 0, "byte 12", "a division of 0 ticks per quarter note");
        f.ticksPerQuarter = division;
    }

    struct Open {
        std::int64_t start;
        int velocity;
    };
    std::vector<MidiTempoChange> tempo;
    std::size_t pos = 8 + headerLength;
    int track = 0;
    while (pos + 8 <= bytes.size()) {
        const std::string_view type = bytes.substr(pos, 4);
        const std::uint32_t length = be32(bytes, pos + 4);
        if (length > bytes.size() - pos - 8)
            throw core::InputError(source, 0, "byte " + std::to_string(pos + 4), "a chunk of " + std::to_string(length) + " bytes runs past the end of the file");
        const std::size_t body = pos + 8;
        pos = body + length;
        if (type != "MTrk") continue;   // alien chunks are skipped, as the standard says
        Reader r(bytes.substr(body, length), source, body);
        f.trackNames.emplace_back();
        std::map<std::pair<int, int>, std::deque<Open>> open;   // (channel, key) → notes sounding, oldest first
        std::int64_t tick = 0;
        int status = 0;
        bool ended = false;
        while (!r.done() && !ended) {
            tick += r.variable();
            int b = r.peek();
            if (b & 0x80) {
                r.byte();
            } else {
                if (status == 0) r.fail("a data byte with no running status in effect");
                b = status;
            }
            if (b == 0xFF) {
                status = 0;
                const int metaType = r.byte();
                const std::string_view data = r.take(r.variable());
                if (metaType == 0x2F) ended = true;
                else if (metaType == 0x51) {
                    if (data.size() != 3) r.fail("a tempo event of " + std::to_string(data.size()) + " bytes (3 expected)");
                    const auto us = (std::uint32_t(std::uint8_t(data[0])) << 16) | (std::uint32_t(std::uint8_t(data[1])) << 8) | std::uint8_t(data[2]);
                    if (us == 0) r.fail("a tempo of 0 µs per quarter note");
                    tempo.push_back({tick, static_cast<double>(us)});
                } else if (metaType == 0x03) {
                    if (f.trackNames.back().empty()) f.trackNames.back() = cleanText(data);
                } else if (metaType == 0x06 || metaType == 0x07) {
                    f.markers.push_back({tick, cleanText(data), metaType == 0x07});
                }
            } else if (b == 0xF0 || b == 0xF7) {
                status = 0;
                r.take(r.variable());
            } else if (b >= 0xF8 || (b >= 0xF1 && b <= 0xF6)) {
                static const char* const kHex = "0123456789ABCDEF";
                r.fail(std::string("a system message (0x") + kHex[(b >> 4) & 0xF] + kHex[b & 0xF] + ") is not allowed in a MIDI file");
            } else {
                status = b;
                const int kind = b & 0xF0, channel = b & 0x0F;
                const int d1 = r.byte();
                const int d2 = (kind == 0xC0 || kind == 0xD0) ? 0 : r.byte();
                if ((d1 | d2) & 0x80) r.fail("a data byte above 127");
                if (kind == 0x90 && d2 > 0) {
                    open[{channel, d1}].push_back({tick, d2});
                } else if (kind == 0x80 || kind == 0x90) {
                    auto it = open.find({channel, d1});
                    if (it == open.end() || it->second.empty()) {
                        ++f.unmatchedNoteOffs;
                    } else {
                        const Open o = it->second.front();
                        it->second.pop_front();
                        if (tick > o.start) f.notes.push_back({o.start, tick, d1, o.velocity, channel, track});
                    }
                }
            }
        }
        for (auto& [key, notes] : open)
            for (const Open& o : notes) {
                ++f.unterminatedNotes;
                if (tick > o.start) f.notes.push_back({o.start, tick, key.second, o.velocity, key.first, track});
            }
        f.endTick = std::max(f.endTick, tick);
        ++track;
    }
    if (track == 0) throw core::InputError(source, 0, "byte " + std::to_string(pos), "no track chunk ('MTrk')");
    if (format == 0 && track > 1) throw core::InputError(source, 0, "byte 10", "a format 0 file with " + std::to_string(track) + " tracks (one expected)");
    std::stable_sort(f.notes.begin(), f.notes.end(), [](const MidiNote& a, const MidiNote& b) {
        return std::tie(a.start, a.key) < std::tie(b.start, b.key);
    });
    std::stable_sort(tempo.begin(), tempo.end(), [](const MidiTempoChange& a, const MidiTempoChange& b) { return a.tick < b.tick; });
    // One tempo per tick (the last one written wins), one at tick 0.
    for (const MidiTempoChange& t : tempo) {
        if (!f.tempo.empty() && f.tempo.back().tick == t.tick) f.tempo.back() = t;
        else f.tempo.push_back(t);
    }
    if (f.tempo.empty() || f.tempo.front().tick != 0) f.tempo.insert(f.tempo.begin(), MidiTempoChange {});
    std::stable_sort(f.markers.begin(), f.markers.end(), [](const MidiMarker& a, const MidiMarker& b) { return a.tick < b.tick; });
    return f;
}

MidiFile readMidiFile(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) throw core::IoError("cannot read " + path);
    std::ostringstream s;
    s << in.rdbuf();
    if (in.bad()) throw core::IoError("cannot read " + path);
    return parseMidiFile(s.str(), path);
}

} // namespace armadillo::formats
