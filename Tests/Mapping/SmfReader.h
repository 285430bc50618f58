#pragma once
// A Standard MIDI File reader for the tests, written from the SMF 1.0 specification (MThd: format,
// track count, division; MTrk: variable-length delta times, running status, meta and sysex
// events). Independent of Mapping/MidiFile.cpp; used by the mapping and CLI tests.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace armadillo::mapping::test {

struct SmfEvent {
    double seconds = 0.0;
    std::uint32_t tick = 0;
    int track = 0;
    std::vector<std::uint8_t> bytes;   // channel messages only
};

struct Smf {
    int format = -1, tracks = 0, division = 0;
    std::uint32_t tempo = 500000;   // µs per quarter (the default when none is given)
    std::vector<SmfEvent> events;   // every track's channel events, in file order per track, merged by time
};

inline Smf readSmf(const std::vector<std::uint8_t>& b)
{
    std::size_t p = 0;
    const auto need = [&](std::size_t n) {
        if (p + n > b.size()) throw std::runtime_error("SMF: truncated at byte " + std::to_string(p));
    };
    const auto u32 = [&]() {
        need(4);
        const std::uint32_t v = (std::uint32_t(b[p]) << 24) | (std::uint32_t(b[p + 1]) << 16) | (std::uint32_t(b[p + 2]) << 8) | b[p + 3];
        p += 4;
        return v;
    };
    const auto u16 = [&]() {
        need(2);
        const int v = (b[p] << 8) | b[p + 1];
        p += 2;
        return v;
    };
    const auto vlq = [&]() {
        std::uint32_t v = 0;
        for (int i = 0; i < 4; ++i) {
            need(1);
            const std::uint8_t c = b[p++];
            v = (v << 7) | (c & 0x7F);
            if (!(c & 0x80)) return v;
        }
        throw std::runtime_error("SMF: variable-length quantity longer than 4 bytes");
    };
    Smf smf;
    need(4);
    if (std::string(b.begin(), b.begin() + 4) != "MThd") throw std::runtime_error("SMF: no MThd");
    p = 4;
    if (u32() != 6) throw std::runtime_error("SMF: header length is not 6");
    smf.format = u16();
    smf.tracks = u16();
    smf.division = u16();
    if (smf.division & 0x8000) throw std::runtime_error("SMF: SMPTE division not handled by this reader");
    std::vector<SmfEvent> all;
    for (int tr = 0; tr < smf.tracks; ++tr) {
        need(4);
        if (std::string(b.begin() + static_cast<long>(p), b.begin() + static_cast<long>(p) + 4) != "MTrk") throw std::runtime_error("SMF: no MTrk");
        p += 4;
        const std::uint32_t len = u32();
        const std::size_t end = p + len;
        if (end > b.size()) throw std::runtime_error("SMF: track longer than the file");
        std::uint32_t tick = 0;
        std::uint8_t running = 0;
        bool ended = false;
        while (p < end) {
            tick += vlq();
            need(1);
            std::uint8_t status = b[p];
            if (status == 0xFF) {
                need(2);
                const std::uint8_t type = b[p + 1];
                p += 2;
                const std::uint32_t n = vlq();
                need(n);
                if (type == 0x51 && n == 3) smf.tempo = (std::uint32_t(b[p]) << 16) | (std::uint32_t(b[p + 1]) << 8) | b[p + 2];
                if (type == 0x2F) ended = true;
                p += n;
                continue;
            }
            if (status == 0xF0 || status == 0xF7) {
                ++p;
                const std::uint32_t n = vlq();
                need(n);
                p += n;
                continue;
            }
            if (status & 0x80) {
                running = status;
                ++p;
            } else if (running == 0) {
                throw std::runtime_error("SMF: data byte without a status");
            }
            status = running;
            const int type = status & 0xF0;
            const std::size_t n = (type == 0xC0 || type == 0xD0) ? 1 : 2;
            need(n);
            SmfEvent e;
            e.tick = tick;
            e.track = tr;
            e.bytes.push_back(status);
            for (std::size_t i = 0; i < n; ++i) e.bytes.push_back(b[p + i]);
            p += n;
            all.push_back(e);
        }
        if (!ended) throw std::runtime_error("SMF: track without End of Track");
    }
    // One tempo (ours never changes): seconds = ticks × tempo / division.
    for (auto& e : all) e.seconds = double(e.tick) * smf.tempo / smf.division / 1e6;
    smf.events = all;
    return smf;
}

} // namespace armadillo::mapping::test
