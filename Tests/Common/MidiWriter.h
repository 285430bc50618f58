#pragma once
// The tests' own Standard MIDI File writer, independent of Source/Formats: written from the MMA
// "Standard MIDI Files 1.0" layout (MThd, MTrk, variable-length deltas, running status, meta
// events), so the reader is checked against files it did not produce.
#include <algorithm>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace armadillo::test {

struct WrittenNote {
    double beat = 0.0, beats = 1.0;   ///< start and length in quarter notes
    int key = 60, velocity = 80, track = 0, channel = 0;
};
struct WrittenTempo {
    double beat = 0.0, bpm = 120.0;
};

inline void putVariable(std::string& out, std::uint32_t v)
{
    char bytes[5];
    int n = 0;
    bytes[n++] = static_cast<char>(v & 0x7F);
    while (v >>= 7) bytes[n++] = static_cast<char>((v & 0x7F) | 0x80);
    while (n > 0) out += bytes[--n];
}

inline void put32(std::string& out, std::uint32_t v)
{
    for (int s = 24; s >= 0; s -= 8) out += static_cast<char>((v >> s) & 0xFF);
}

/// Format 1: track 0 = tempo map, markers and names; one track per `tracks` after it. Note-offs
/// are written as note-ons of velocity 0 under running status (what most sequencers write).
inline std::string midiBytes(const std::vector<WrittenNote>& notes, const std::vector<WrittenTempo>& tempo, int tracks, int ppq = 480,
                             const std::vector<std::pair<double, std::string>>& markers = {})
{
    struct Ev {
        long tick;
        int order;   // offs before ons at the same tick
        std::string bytes;
    };
    std::string file = "MThd";
    put32(file, 6);
    file += '\0';
    file += '\1';
    file += static_cast<char>(((tracks + 1) >> 8) & 0xFF);
    file += static_cast<char>((tracks + 1) & 0xFF);
    file += static_cast<char>((ppq >> 8) & 0xFF);
    file += static_cast<char>(ppq & 0xFF);
    for (int t = -1; t < tracks; ++t) {
        std::vector<Ev> ev;
        if (t < 0) {
            for (const auto& tp : tempo) {
                const auto us = static_cast<std::uint32_t>(60.0e6 / tp.bpm + 0.5);
                std::string b = "\xFF\x51\x03";
                b += static_cast<char>((us >> 16) & 0xFF);
                b += static_cast<char>((us >> 8) & 0xFF);
                b += static_cast<char>(us & 0xFF);
                ev.push_back({static_cast<long>(tp.beat * ppq + 0.5), 0, b});
            }
            for (const auto& [beat, text] : markers) {
                std::string b = "\xFF\x06";
                putVariable(b, static_cast<std::uint32_t>(text.size()));
                ev.push_back({static_cast<long>(beat * ppq + 0.5), 0, b + text});
            }
        } else {
            std::string name = "\xFF\x03";
            const std::string nm = "voice " + std::to_string(t + 1);
            putVariable(name, static_cast<std::uint32_t>(nm.size()));
            ev.push_back({0, 0, name + nm});
            for (const auto& n : notes) {
                if (n.track != t) continue;
                const long on = static_cast<long>(n.beat * ppq + 0.5), off = static_cast<long>((n.beat + n.beats) * ppq + 0.5);
                ev.push_back({on, 2, std::string {static_cast<char>(0x90 | n.channel), static_cast<char>(n.key), static_cast<char>(n.velocity)}});
                ev.push_back({off, 1, std::string {static_cast<char>(0x90 | n.channel), static_cast<char>(n.key), '\0'}});
            }
        }
        std::stable_sort(ev.begin(), ev.end(), [](const Ev& a, const Ev& b) { return a.tick != b.tick ? a.tick < b.tick : a.order < b.order; });
        std::string data;
        long last = 0;
        int status = 0;
        for (const Ev& e : ev) {
            putVariable(data, static_cast<std::uint32_t>(e.tick - last));
            last = e.tick;
            const int s = static_cast<unsigned char>(e.bytes[0]);
            if (s < 0xF0 && s == status) {
                data += e.bytes.substr(1);   // running status
            } else {
                data += e.bytes;
                status = s < 0xF0 ? s : 0;
            }
        }
        data += std::string("\x00\xFF\x2F\x00", 4);
        file += "MTrk";
        put32(file, static_cast<std::uint32_t>(data.size()));
        file += data;
    }
    return file;
}

inline void writeFile(const std::string& path, const std::string& bytes)
{
    std::ofstream out(path, std::ios::binary);
    out << bytes;
}

} // namespace armadillo::test
