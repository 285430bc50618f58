// The MIDI import rule (docs/FORMATS.md, "MIDI files"), checked on the score it writes.
#include "Common/MidiWriter.h"
#include "Core/Errors.h"
#include "Formats/ScoreImport.h"
#include <catch2/catch.hpp>
#include <map>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::formats;
using namespace armadillo::tactile;
using namespace armadillo::test;

namespace {
ImportedScore importNotes(const std::vector<WrittenNote>& notes, const MidiImportOptions& o = {}, const std::vector<WrittenTempo>& tempo = {{0, 120}},
                          int tracks = 1, const std::vector<std::pair<double, std::string>>& markers = {})
{
    return importMidi(parseMidiFile(midiBytes(notes, tempo, tracks, 480, markers), "piece.mid"), o, "piece.mid");
}
int motorOf(const ScoreNote& n)
{
    for (int m = 0; m < kMaxMotors; ++m)
        if (n.motors & (1u << m)) return m;
    return -1;
}
const ScoreNote* noteAt(const Score& s, double start, double pitchHz)
{
    for (const auto& n : s.notes)
        if (std::fabs(n.start - start) < 1e-6 && std::fabs(n.pitchHz / pitchHz - 1.0) < 1e-3) return &n;
    return nullptr;
}
double hz(int key) { return 440.0 * std::pow(2.0, (key - 69) / 12.0); }
} // namespace

TEST_CASE("midi import: lowest pitch at the elbow, highest at the wrist, nine bins across the grid", "[formats][import]")
{
    // Nine keys, one per bin of the range 48..74 (27 keys, 3 per bin), one after the other.
    std::vector<WrittenNote> notes;
    for (int b = 0; b < 9; ++b) notes.push_back({static_cast<double>(b), 1.0, 48 + 3 * b + (b == 8 ? 2 : 0), 80, 0, 0});
    const ImportedScore s = importNotes(notes);
    REQUIRE(s.score.notes.size() == 9);
    // bin b → row 2 − b/3 (elbow .. wrist), column b % 3: motors (k) 7 8 9 4 5 6 1 2 3.
    const int expected[9] = {6, 7, 8, 3, 4, 5, 0, 1, 2};
    for (int b = 0; b < 9; ++b) {
        CAPTURE(b);
        CHECK(motorOf(s.score.notes[static_cast<std::size_t>(b)]) == expected[b]);
    }
    CHECK(s.score.version == 2);
    CHECK(s.score.parts.size() == 1);
    CHECK(s.score.parts[0].followNotes);
}

TEST_CASE("midi import: a chord over the budget keeps its outer voices; held notes make room; never two notes on a motor", "[formats][import]")
{
    std::vector<WrittenNote> notes {{0, 8, 36, 80, 0, 0}, {0, 8, 43, 80, 0, 0}};   // a held bass fifth
    for (int k : {60, 64, 67, 70, 72, 76}) notes.push_back({4, 1, k, 90, 0, 0});     // six notes at beat 4
    MidiImportOptions o;
    o.maxMotors = 4;
    const ImportedScore s = importNotes(notes, o);
    CHECK(s.report.dropped == 2);    // six at once, a budget of four
    CHECK(s.report.shortened == 2);  // the held fifth ends at beat 4 to make room
    CHECK(noteAt(s.score, 2.0, hz(76)) != nullptr);   // the highest (beat 4 = 2 s at 120 bpm)
    CHECK(noteAt(s.score, 2.0, hz(60)) != nullptr);   // the lowest
    CHECK(noteAt(s.score, 2.0, hz(72)) != nullptr);   // then from the top down
    CHECK(noteAt(s.score, 2.0, hz(70)) != nullptr);
    CHECK(noteAt(s.score, 2.0, hz(64)) == nullptr);
    CHECK(noteAt(s.score, 2.0, hz(67)) == nullptr);
    // At no time more notes than the budget, nor two notes on one motor.
    for (double t = 0.0; t < 5.0; t += 0.01) {
        int sounding = 0;
        std::map<int, int> onMotor;
        for (const auto& n : s.score.notes)
            if (t >= n.start && t < n.end) {
                ++sounding;
                ++onMotor[motorOf(n)];
            }
        CAPTURE(t);
        CHECK(sounding <= 4);
        for (const auto& [m, count] : onMotor) CHECK(count == 1);
    }
}

TEST_CASE("midi import: velocity to level through the safety-aware curve; soft and fast starts", "[formats][import]")
{
    MidiImportOptions o;
    const SafetyParams safety;
    // Long notes (longer than the run allowed above the rating) top out at the rated level.
    CHECK(midiVelocityLevel(127, 1.0, o) == Approx(static_cast<float>(safety.ratedLevel)));
    CHECK(midiVelocityLevel(1, 1.0, o) == Approx(o.quietLevel));
    // Short notes may go up to shortTop.
    CHECK(midiVelocityLevel(127, 0.2, o) == Approx(o.shortTop));
    CHECK(midiVelocityLevel(64, 0.2, o) == Approx(std::round(2.0 * (1.5 + 8.5 * 63.0 / 126.0)) / 2.0));
    // A quiet long note starts soft; a loud one, or a quiet short one, fast.
    const ImportedScore s = importNotes({{0, 4, 60, 30, 0, 0}, {4, 4, 62, 100, 0, 0}, {8, 0.25, 64, 30, 0, 0}});
    REQUIRE(s.score.notes.size() == 3);
    CHECK(s.score.notes[0].soft);
    CHECK_FALSE(s.score.notes[1].soft);
    CHECK_FALSE(s.score.notes[2].soft);
    CHECK(s.score.notes[1].envelope[0] == Approx(midiVelocityLevel(100, 2.0, o)));
    CHECK(s.score.notes[2].envelope[0] == Approx(midiVelocityLevel(30, 0.125, o)));
}

TEST_CASE("midi import: per-track motors, tracks left out, percussion, tempo changes and markers as cues", "[formats][import]")
{
    const std::vector<WrittenNote> notes {{0, 1, 72, 80, 0, 0}, {1, 1, 74, 80, 0, 0}, {0, 2, 40, 80, 1, 0}, {0, 1, 50, 80, 2, 0}, {1, 0.25, 36, 100, 2, 9}};
    MidiImportOptions o;
    o.tracks.push_back({2, 0, false});
    REQUIRE(parseMotorSet("back", o.tracks.back().motors));
    o.tracks.push_back({4, 0, true});   // track 4 = voice 3 (track 1 holds the tempo map): left out
    const ImportedScore s = importNotes(notes, o, {{0, 120}, {2, 60}}, 3, {{1.0, "Verse 2"}});
    // Track 2 (file order; track 1 is the tempo map) = voice 1: on the back motors 10..12.
    for (const auto& n : s.score.notes) {
        if (std::fabs(n.pitchHz / hz(72) - 1.0) < 1e-3 || std::fabs(n.pitchHz / hz(74) - 1.0) < 1e-3) CHECK(motorOf(n) >= 9);
        CHECK(std::fabs(n.pitchHz / hz(50) - 1.0) > 1e-3);   // voice 3 left out
        CHECK(std::fabs(n.pitchHz / hz(36) - 1.0) > 1e-3);
    }
    REQUIRE(s.score.cues.size() == 2);
    CHECK(s.score.cues[0].name == "verse-2");
    CHECK(s.score.cues[0].time == Approx(0.5));
    CHECK(s.score.cues[1].name == "tempo-1");
    CHECK(s.score.cues[1].time == Approx(1.0));
    REQUIRE(s.score.tempo.size() == 2);
    CHECK(s.score.tempo[1].bpm == Approx(60.0));
    CHECK_THROWS_AS(importNotes(notes, [] {
        MidiImportOptions bad;
        bad.tracks.push_back({9, 1, false});
        return bad;
    }(), {{0, 120}}, 3), InputError);
    // Percussion (channel 10) without an override: the elbow row, no pitch (not followed).
    const ImportedScore drums = importNotes({{0, 0.25, 36, 100, 0, 9}, {0, 1, 60, 80, 0, 0}});
    for (const auto& n : drums.score.notes)
        if (n.pitchHz == 0.0) CHECK(motorOf(n) >= 6);
    CHECK(drums.score.notes.size() == 2);
}
