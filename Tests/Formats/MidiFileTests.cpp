// The Standard MIDI File reader against files the tests write themselves (Common/MidiWriter.h)
// or spell out byte by byte from the SMF 1.0 layout.
#include "Common/MidiWriter.h"
#include "Core/Errors.h"
#include "Formats/MidiFile.h"
#include <catch2/catch.hpp>
#include <random>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::formats;
using namespace armadillo::test;

namespace {
std::string bytes(std::initializer_list<int> b)
{
    std::string s;
    for (int x : b) s += static_cast<char>(x);
    return s;
}
/// A file: header (format, tracks, division) and the given track bodies (without end-of-track).
std::string smf(int format, int division, const std::vector<std::string>& tracks)
{
    std::string f = "MThd" + bytes({0, 0, 0, 6, 0, format, 0, static_cast<int>(tracks.size()), (division >> 8) & 0xFF, division & 0xFF});
    for (const auto& t : tracks) {
        const std::string body = t + bytes({0, 0xFF, 0x2F, 0});
        f += "MTrk";
        put32(f, static_cast<std::uint32_t>(body.size()));
        f += body;
    }
    return f;
}
} // namespace

TEST_CASE("midi: a format 1 file with a tempo map, names, markers and running status", "[formats][midi]")
{
    const std::vector<WrittenNote> notes {
        {0, 1, 60, 100, 0, 0}, {1, 0.5, 64, 90, 0, 0}, {1.5, 2.5, 67, 80, 0, 0}, {0, 4, 36, 70, 1, 3}, {4, 2, 38, 60, 1, 3}};
    const std::vector<WrittenTempo> tempo {{0, 90}, {2, 120}, {5, 60}};
    const MidiFile f = parseMidiFile(midiBytes(notes, tempo, 2, 96, {{4.0, "Coda"}}), "piece.mid");
    CHECK(f.format == 1);
    CHECK(f.ticksPerQuarter == 96);
    REQUIRE(f.trackNames.size() == 3);
    CHECK(f.trackNames[1] == "voice 1");
    REQUIRE(f.notes.size() == notes.size());
    // Sorted by start, then key: (0, 36), (0, 60), (96, 64), (144, 67), (384, 38).
    CHECK(f.notes[0].key == 36);
    CHECK(f.notes[0].channel == 3);
    CHECK(f.notes[0].track == 2);
    CHECK(f.notes[0].end == 384);
    CHECK(f.notes[1].key == 60);
    CHECK(f.notes[1].velocity == 100);
    CHECK(f.notes[2].start == 96);
    CHECK(f.notes[2].end == 144);
    CHECK(f.notes[3].start == 144);
    CHECK(f.notes[4].key == 38);
    REQUIRE(f.tempo.size() == 3);
    CHECK(f.tempo[1].tick == 192);
    // Seconds through the tempo map, from the definition: 2 beats at 90, 3 at 120, then 60.
    CHECK(f.secondsAt(192) == Approx(2 * 60.0 / 90.0));
    CHECK(f.secondsAt(96 * 5) == Approx(2 * 60.0 / 90.0 + 3 * 0.5));
    CHECK(f.secondsAt(96 * 6) == Approx(2 * 60.0 / 90.0 + 3 * 0.5 + 1.0));
    REQUIRE(f.markers.size() == 1);
    CHECK(f.markers[0].text == "Coda");
    CHECK(f.markers[0].tick == 384);
}

TEST_CASE("midi: format 0, explicit note-offs, running status across them, 120 bpm by default", "[formats][midi]")
{
    // Delta 0: note on C4 (90 3C 64); delta 0: running status, note on E4; delta 96: running
    // status, velocity 0 = C4 off; delta 48: an explicit note-off (80 40 40) for E4.
    const std::string track = bytes({0x00, 0x90, 0x3C, 0x64, 0x00, 0x40, 0x50, 0x60, 0x3C, 0x00, 0x30, 0x80, 0x40, 0x40});
    const MidiFile f = parseMidiFile(smf(0, 96, {track}), "f0.mid");
    REQUIRE(f.notes.size() == 2);
    CHECK(f.notes[0].key == 0x3C);
    CHECK(f.notes[0].end == 0x60);
    CHECK(f.notes[1].key == 0x40);
    CHECK(f.notes[1].end == 0x60 + 0x30);
    REQUIRE(f.tempo.size() == 1);
    CHECK(f.secondsAt(96) == Approx(0.5));
}

TEST_CASE("midi: an SMPTE division gives seconds (25 fps x 40 ticks = 1000 ticks/s)", "[formats][midi]")
{
    const std::string track = bytes({0x00, 0x90, 0x45, 0x70, 0x83, 0x74, 0x45, 0x00});   // 500 ticks later
    const MidiFile f = parseMidiFile(smf(0, 0xE728, {track}), "smpte.mid");
    CHECK(f.smpte);
    CHECK(f.ticksPerSecond == Approx(1000.0));
    REQUIRE(f.notes.size() == 1);
    CHECK(f.secondsAt(f.notes[0].end) == Approx(0.5));
}

TEST_CASE("midi: bad files are refused with the byte that is wrong", "[formats][midi]")
{
    const std::string good = smf(0, 96, {bytes({0x00, 0x90, 0x3C, 0x64, 0x60, 0x3C, 0x00})});
    const auto refused = [](const std::string& data, const std::string& what) {
        CAPTURE(what);
        try {
            (void) parseMidiFile(data, "bad.mid");
            FAIL("accepted");
        } catch (const InputError& e) {
            CHECK(std::string(e.what()).find("bad.mid") != std::string::npos);
            CHECK(std::string(e.what()).find("byte") != std::string::npos);
        }
    };
    refused("RIFF....", "not a MIDI file");
    refused(good.substr(0, good.size() - 3), "truncated track");
    refused(smf(2, 96, {bytes({0x00, 0x90, 0x3C, 0x64})}), "format 2");
    refused(smf(0, 96, {bytes({0x00, 0x3C, 0x64})}), "a data byte with no running status");
    refused(smf(0, 96, {bytes({0x80, 0x80, 0x80, 0x80, 0x01, 0x90, 0x3C, 0x64})}), "a 5-byte delta");
    refused(smf(0, 96, {bytes({0x00, 0xFF, 0x51, 0x02, 0x07, 0xA1})}), "a 2-byte tempo");
    refused(smf(0, 96, {bytes({0x00, 0xFF, 0x51, 0x03, 0, 0, 0})}), "a tempo of 0");
    refused(smf(0, 0, {bytes({0x00, 0x90, 0x3C, 0x64})}), "division 0");
    refused(smf(0, 96, {bytes({0x00, 0x90, 0x3C, 0x64}), bytes({0x00, 0x90, 0x3C, 0x64})}), "format 0 with two tracks");
    refused(smf(0, 96, {bytes({0x00, 0xF8})}), "a real-time message");
    refused("MThd" + bytes({0, 0, 0, 6, 0, 1, 0, 0, 0, 96}), "no track");
}

TEST_CASE("midi: mutated files never crash or hang: parsed or refused", "[formats][midi][fuzz]")
{
    const std::string base = midiBytes({{0, 1, 60, 100, 0, 0}, {1, 2, 64, 90, 1, 1}, {1, 2, 67, 90, 1, 1}}, {{0, 100}, {2, 80}}, 2, 480, {{1.0, "A"}});
    std::mt19937 rng(7);
    int parsed = 0, refused = 0;
    for (int i = 0; i < 4000; ++i) {
        std::string m = base;
        const int edits = 1 + static_cast<int>(rng() % 4);
        for (int e = 0; e < edits; ++e) {
            const auto at = rng() % m.size();
            switch (rng() % 3) {
            case 0: m[at] = static_cast<char>(rng() & 0xFF); break;
            case 1: m.erase(at, 1 + rng() % 4); break;
            default: m.insert(at, 1, static_cast<char>(rng() & 0xFF)); break;
            }
            if (m.empty()) m = "M";
        }
        try {
            const MidiFile f = parseMidiFile(m, "fuzz.mid");
            for (const auto& n : f.notes) REQUIRE(n.end > n.start);
            ++parsed;
        } catch (const InputError&) {
            ++refused;
        }
    }
    CHECK(parsed + refused == 4000);
    CHECK(refused > 0);
}
