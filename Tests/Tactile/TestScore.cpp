// The tactile score format: what it reads, and that it refuses bad files naming the line.
#include "Core/Errors.h"
#include "Tactile/Score.h"
#include <catch2/catch.hpp>
#include <fstream>
#include <random>
#include <sstream>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::tactile;

namespace {
std::string shipped(const std::string& name)
{
    std::ifstream in(std::string(ARMADILLO_SOURCE_DIR) + "/Resources/Scores/" + name + ".score");
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

long refusedLine(const std::string& text)
{
    try {
        parseScore(text, "bad.score");
    } catch (const InputError& e) {
        CHECK(e.file() == "bad.score");
        CHECK(std::string(e.what()).find("bad.score") == 0);
        return e.line();
    }
    return -1;
}
} // namespace

TEST_CASE("Score: notes, tempo map, relative times, motor sets and envelopes", "[score]")
{
    const Score s = parseScore(R"(# a comment line
armadillo-score 1
title A small test   # with a comment
units beats
tempo 60
0     note m=1 dur=2 level=3
+2    note m=wrist dur=1 level=2->8
4     tempo 120
4     note m=1,3-4,back dur=2 level=0->10->0
6     pattern breathing m=all level=5 rate=0.5 voice=1
8     stop voice=1
8     pattern geiger m=9 voice=2 dur=hold
9     pattern accent m=elbow level=12 voice=3
)", "t.score");
    CHECK(s.title == "A small test");
    CHECK(s.inBeats);
    REQUIRE(s.notes.size() == 3);
    CHECK(s.notes[0].start == 0.0);
    CHECK(s.notes[0].end == 2.0);
    CHECK(s.notes[1].start == 2.0);
    CHECK(s.notes[1].motors == 0x7);
    CHECK(s.notes[1].levelAt(2.5) == Approx(5.0f));
    // Beat 4 at 60 bpm = 4 s; then 120 bpm: beat 6 = 5 s.
    CHECK(s.notes[2].start == Approx(4.0));
    CHECK(s.notes[2].end == Approx(5.0));
    CHECK(s.notes[2].motors == (1u | 4u | 8u | 0x0E00u));
    CHECK(s.notes[2].levelAt(4.5) == Approx(10.0f));
    CHECK(s.notes[2].levelAt(4.25) == Approx(5.0f));
    CHECK(s.notes[2].levelAt(5.0) == 0.0f);
    CHECK(s.secondsAtBeat(8) == Approx(6.0));
    CHECK(s.beatAtSeconds(5.5) == Approx(7.0));
    CHECK(s.bpmAtSeconds(3.9) == 60.0);
    CHECK(s.bpmAtSeconds(4.1) == 120.0);
    REQUIRE(s.patterns.size() == 3);
    CHECK(s.patterns[0].request.kind == PatternKind::Breathing);
    CHECK(s.patterns[0].request.voice == 1);
    CHECK(s.patterns[0].request.rate == 0.5);
    CHECK(s.patterns[0].start == Approx(5.0));
    CHECK(s.patterns[0].end == Approx(6.0));   // the stop at beat 8
    CHECK(s.patterns[1].request.kind == PatternKind::Geiger);
    CHECK(s.patterns[1].request.motors == (1u << 8));
    CHECK(s.patterns[1].request.level == 10.0f);   // the default level
    CHECK(s.patterns[2].end == Approx(s.patterns[2].start + 0.1));   // accent: its default length
    // Held until the score ends: the last event (the accent) ends it.
    CHECK(s.patterns[1].end == Approx(s.length));
    CHECK(s.length == Approx(6.5 + 0.1));
}

TEST_CASE("Score: seconds, explicit length, a later pattern replaces one on its voice", "[score]")
{
    const Score s = parseScore("armadillo-score 1\nunits seconds\n1.5 pattern twist voice=0\n3 pattern jolt voice=0\nlength 10\n", "s");
    CHECK_FALSE(s.inBeats);
    REQUIRE(s.patterns.size() == 2);
    CHECK(s.patterns[0].start == 1.5);
    CHECK(s.patterns[0].end == 3.0);
    CHECK(s.patterns[1].end == Approx(3.06));
    CHECK(s.length == 10.0);
}

TEST_CASE("Score: motor set syntax", "[score]")
{
    std::uint16_t m = 0;
    CHECK(parseMotorSet("1", m));
    CHECK(m == 1);
    CHECK(parseMotorSet("1-3,9", m));
    CHECK(m == (0x7 | 0x100));
    CHECK(parseMotorSet("wrist-anchors", m));
    CHECK(m == 0x5);
    CHECK(parseMotorSet("16", m));
    CHECK(m == 0x8000);
    for (const char* bad : {"", "0", "17", "3-1", "1,,2", "a", "1-", "-2", "1,", "123", "wrist,x"}) {
        INFO(bad);
        CHECK_FALSE(parseMotorSet(bad, m));
    }
}

TEST_CASE("Score: bad files are refused with the line that is wrong", "[score]")
{
    const std::string h = "armadillo-score 1\n";
    struct Bad {
        std::string text;
        long line;
    };
    const Bad cases[] = {
        {"", 0},
        {"# only a comment\n\n", 0},
        {"hello\n", 1},
        {"armadillo-score 3\n", 1},
        {h + "0 note m=3 dur=1\n", 2},
        {h + "\n# x\n0 note m=17 dur=1 level=3\n", 4},
        {h + "0 note m=3 dur=1 level=16\n", 2},
        {h + "0 note m=3 dur=1 level=-1\n", 2},
        {h + "1 note m=3 dur=1 level=3\n0.5 note m=3 dur=1 level=3\n", 3},
        {h + "0 nope\n", 2},
        {h + "0\n", 2},
        {h + "0 pattern sparkle\n", 2},
        {h + "0 pattern\n", 2},
        {h + "0 pattern twist voice=9\n", 2},
        {h + "0 pattern twist voice=1.5\n", 2},
        {h + "0 pattern twist rate=0\n", 2},
        {h + "0 pattern twist dur=forever\n", 2},
        {h + "0 note m=3 dur=1 level=3 colour=red\n", 2},
        {h + "0 note m=3 dur=1 dur=2 level=3\n", 2},
        {h + "0 note m=3 dur=1 level=3 =4\n", 2},
        {h + "0 note m=3 dur=1 level=3 x\n", 2},
        {h + "units minutes\n", 2},
        {h + "units beats\nunits seconds\n", 3},
        {h + "0 note m=3 dur=0 level=3\n", 2},
        {h + "0 note m=3 dur=1 level=2->\n", 2},
        {h + "0 note m=3 dur=1 level=->2\n", 2},
        {h + "units seconds\n0 tempo 60\n", 3},
        {h + "0 note m=3 dur=1 level=3\ntitle late\n", 3},
        {h + "tempo 0\n", 2},
        {h + "tempo 60 70\n", 2},
        {h + "title\n", 2},
        {h + "0 note m=3 dur=abc level=3\n", 2},
        {h + "0 note m=3 dur=0x10 level=3\n", 2},
        {h + "0 note m=3 dur=inf level=3\n", 2},
        {h + "1e400 note m=3 dur=1 level=3\n", 2},
        {h + "+-1 note m=3 dur=1 level=3\n", 2},
        {h + "0 stop\n", 2},
        {h + "0 stop voice=x\n", 2},
        {h + "0 tempo\n", 2},
        {h + "length 1\n0 note m=3 dur=2 level=3\n", 2},
        {h + "colour red\n", 2},
        {h + "0 note m=3 dur=1 level=3\n" + std::string("1 note m=3 dur=1 level=3\0", 26) + "\n", 3},
    };
    for (const Bad& b : cases) {
        INFO(b.text);
        CHECK(refusedLine(b.text) == b.line);
    }
}

TEST_CASE("Score: fuzzed files either parse into sane scores or are refused with a line", "[score][fuzz]")
{
    const std::string seeds[] = {shipped("rite-of-spring"), shipped("polytope")};
    REQUIRE(seeds[0].size() > 100);
    REQUIRE(seeds[1].size() > 100);
    const std::string tokens[] = {" ", "\n", "#", "=", "->", "-", "+", ",", ".", "0", "1e9", "-1", "99", "m=",
                                  "dur=", "level=", "voice=", "note", "pattern", "stop", "tempo", "hold", "all",
                                  "twist", "units", "seconds", "length", "\t", "\r", "nan", "1e-300", "\xff"};
    std::mt19937_64 rng(2026);
    int parsed = 0, refused = 0;
    for (int iteration = 0; iteration < 4000; ++iteration) {
        std::string text = seeds[iteration % 2];
        const int edits = 1 + static_cast<int>(rng() % 6);
        for (int k = 0; k < edits; ++k) {
            const std::size_t at = rng() % (text.size() + 1);
            switch (rng() % 4) {
            case 0: if (at < text.size()) text[at] = static_cast<char>(rng() % 256); break;
            case 1: if (at < text.size()) text.erase(at, 1 + rng() % 12); break;
            case 2: text.insert(at, tokens[rng() % std::size(tokens)]); break;
            case 3: {   // duplicate a slice somewhere else
                const std::size_t len = rng() % 40;
                const std::size_t from = rng() % text.size();
                text.insert(at, text.substr(from, len));
                break;
            }
            }
        }
        const long lines = static_cast<long>(std::count(text.begin(), text.end(), '\n')) + 1;
        try {
            const Score s = parseScore(text, "fuzz");
            ++parsed;
            CHECK(std::isfinite(s.length));
            for (const auto& n : s.notes) {
                CHECK(n.start < n.end);
                CHECK(n.motors != 0);
                for (float l : n.envelope) CHECK((l >= 0.0f && l <= 15.0f));
            }
            for (const auto& p : s.patterns) {
                CHECK(p.start < p.end);
                CHECK((p.request.voice >= 0 && p.request.voice < kPatternVoices));
                CHECK((p.request.level >= 0.0f && p.request.level <= 15.0f));
            }
        } catch (const InputError& e) {
            ++refused;
            CHECK((e.line() >= 0 && e.line() <= lines));
        }
    }
    CHECK(parsed > 100);    // the fuzzer keeps some files valid …
    CHECK(refused > 1000);  // … and breaks most
}

TEST_CASE("Score v2: parts, pitches, soft starts and cues; v1 files keep loading and v2 words need v2", "[score][v2]")
{
    const Score s = parseScore("armadillo-score 2\n"
                               "units seconds\n"
                               "part solo follow=notes attack=5 release=80\n"
                               "part swell follow=notes+amplitude curve=db floor=-40 top=-10\n"
                               "0 note m=2 dur=2 pitch=C5 level=1->5 part=swell start=soft\n"
                               "2 note m=3 dur=0.5 pitch=B4 level=5 part=solo\n"
                               "2.5 note m=6 dur=0.5 pitch=Fs4 level=4 part=solo\n"
                               "3 note m=9 dur=1 pitch=330hz level=4\n"
                               "3 cue wind detect=loud level=-20 window=2\n"
                               "4 cue glass detect=onset\n",
                               "v2.score");
    CHECK(s.version == 2);
    REQUIRE(s.parts.size() == 2);
    CHECK(s.parts[0].name == "solo");
    CHECK(s.parts[0].followNotes);
    CHECK_FALSE(s.parts[0].followAmplitude);
    CHECK(s.parts[0].attackMs == 5.0);
    CHECK(s.parts[0].releaseMs == 80.0);
    CHECK(s.parts[1].followNotes);
    CHECK(s.parts[1].followAmplitude);
    CHECK(s.parts[1].curveDb);
    CHECK(s.parts[1].floorDb == -40.0);
    CHECK(s.parts[1].topDb == -10.0);
    REQUIRE(s.notes.size() == 4);
    // Pitches from the equal-tempered formula, A4 = 440 Hz.
    CHECK(s.notes[0].pitchHz == Approx(440.0 * std::pow(2.0, 3.0 / 12.0)));
    CHECK(s.notes[1].pitchHz == Approx(440.0 * std::pow(2.0, 2.0 / 12.0)));
    CHECK(s.notes[2].pitchHz == Approx(440.0 * std::pow(2.0, -3.0 / 12.0)));
    CHECK(s.notes[3].pitchHz == Approx(330.0));
    CHECK(s.notes[0].part == 1);
    CHECK(s.notes[0].soft);
    CHECK_FALSE(s.notes[1].soft);
    CHECK(s.notes[3].part == -1);
    REQUIRE(s.cues.size() == 2);
    CHECK(s.cues[0].name == "wind");
    CHECK(s.cues[0].detect == ScoreCue::Detect::Loud);
    CHECK(s.cues[0].levelDb == -20.0);
    CHECK(s.cues[0].window == 2.0);
    CHECK(s.cues[1].time == 4.0);
    CHECK(s.cues[1].detect == ScoreCue::Detect::Onset);
    CHECK(parsePitch("Bb3") == Approx(440.0 * std::pow(2.0, -11.0 / 12.0)));
    CHECK(parsePitch("H4") == 0.0);
    CHECK(parsePitch("C#") == 0.0);

    // Refused, with their line.
    const std::string v1 = "armadillo-score 1\nunits seconds\n";
    const std::string v2 = "armadillo-score 2\nunits seconds\n";
    struct Bad {
        std::string text;
        long line;
    };
    const std::vector<Bad> cases {
        {v1 + "part a follow=notes\n", 3},                        // v2 words in a v1 file
        {v1 + "0 note m=1 dur=1 level=2 pitch=C4\n", 3},
        {v1 + "0 note m=1 dur=1 level=2 start=soft\n", 3},
        {v1 + "0 cue a\n", 3},
        {v2 + "part a follow=sideways\n", 3},
        {v2 + "part a curve=cubic\n", 3},
        {v2 + "part a floor=-10 top=-20\n", 3},
        {v2 + "part a\npart a\n", 4},
        {v2 + "part follow=notes\n", 3},
        {v2 + "part a follow=notes\n0 note m=1 dur=1 level=2 part=a\n", 4},   // a followed note needs a pitch
        {v2 + "0 note m=1 dur=1 level=2 part=b\n", 3},
        {v2 + "0 note m=1 dur=1 level=2 pitch=X4\n", 3},
        {v2 + "0 note m=1 dur=1 level=2 pitch=9000hz\n", 3},
        {v2 + "0 note m=1 dur=1 level=2 start=slow\n", 3},
        {v2 + "0 cue\n", 3},
        {v2 + "0 cue a detect=maybe\n", 3},
        {v2 + "0 cue a\n1 cue a\n", 4},
        {v2 + "0 cue a window=-1\n", 3},
        {v2 + "0 note m=1 dur=1 level=2\npart late\n", 4},            // parts go before events
    };
    for (const Bad& b : cases) {
        INFO(b.text);
        CHECK(refusedLine(b.text) == b.line);
    }
}
