// The mapping matrix (issue 23): the file format, every transform step and every destination's
// encoding. Expected values are computed here from the definitions (the issue's text, the MIDI
// 1.0 specification, docs/MAPPING.md), never read back from the code under test.
#include "Core/Errors.h"
#include "Osc/Osc.h"
#include "Mapping/MappingHelpers.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::mapping;
using namespace armadillo::mapping::test;

namespace {

/// The issue's example, character for character (the contract subset of INTERFACES.md).
const char* const kIssueExample = R"({"version": 1, "mappings": [
  {"source": "elevation", "in": [-45, 45], "to": {"midi": "cc14", "channel": 1, "cc": 1}},
  {"source": "roll", "in": [-90, 90], "curve": "linear", "to": {"midi": "pitchbend", "channel": 2}},
  {"source": "azimuth", "to": {"midi": "notes", "channel": 3, "velocity": 100,
     "zones": [[0, 90, 60], [90, 180, 62], [180, 270, 64], [270, 360, 65]]}},
  {"source": "elevation", "in": [-90, 90], "out": [0, 1], "to": {"osc": "/synth/cutoff"}}]})";

int expected14(double x, double lo, double hi)
{
    const double n = std::clamp((x - lo) / (hi - lo), 0.0, 1.0);
    return static_cast<int>(std::lround(n * 16383.0));
}

} // namespace

TEST_CASE("The issue's example mapping file is read as it stands", "[mapping][format]")
{
    const MappingDocument doc = parseMappingDocument(kIssueExample, "example.json");
    REQUIRE(doc.version == 1);
    REQUIRE(doc.mappings.size() == 4);
    const MappingSpec& cc = doc.mappings[0];
    CHECK(cc.source.kind == SourceKind::Elevation);
    CHECK(cc.transform.hasIn);
    CHECK(cc.transform.inLo == -45.0);
    CHECK(cc.transform.inHi == 45.0);
    CHECK(cc.to.kind == DestinationKind::Cc14);
    CHECK(cc.to.channel == 1);
    CHECK(cc.to.number == 1);
    CHECK_FALSE(cc.to.lsbFirst);
    CHECK(doc.mappings[1].to.kind == DestinationKind::PitchBend);
    CHECK(doc.mappings[1].to.channel == 2);
    const MappingSpec& notes = doc.mappings[2];
    CHECK(notes.to.kind == DestinationKind::Notes);
    CHECK(notes.to.velocity == 100);
    REQUIRE(notes.zones.size() == 4);
    CHECK(notes.zones[3].from == 270.0);
    CHECK(notes.zones[3].to == 360.0);
    CHECK(notes.zones[3].value == 65);
    const MappingSpec& osc = doc.mappings[3];
    CHECK(osc.to.kind == DestinationKind::Osc);
    CHECK(osc.to.address == "/synth/cutoff");
    CHECK(osc.transform.outLo == 0.0);
    CHECK(osc.transform.outHi == 1.0);
}

TEST_CASE("A mapping document survives writing and reading back", "[mapping][format]")
{
    const char* rich = R"({"version": 1, "name": "rich", "mappings": [
      {"label": "cutoff", "source": "elevation", "in": [-30, 60], "out": [10, 100], "invert": true, "curve": "exp", "shape": 2.5,
       "smoothMs": 20, "deadZone": 2, "steps": 12, "to": {"midi": "cc", "channel": 4, "cc": 74}},
      {"source": "azimuth", "forward": true, "hysteresis": 4.5, "zones": [{"from": 350, "to": 10, "elevation": [0, 45], "value": 5}],
       "to": {"midi": "program", "channel": 2}},
      {"source": "roll", "curve": "table", "table": [[0, 0], [0.5, 0.8], [1, 1]], "scale": "major", "root": 2, "out": [48, 72],
       "to": {"osc": "/pitch/{zone}", "args": ["$value", "-$yaw", 3, "tag"], "types": "fifs", "host": "127.0.0.1", "port": 9100}},
      {"source": "gesture:punch", "to": {"midi": "note", "note": 38, "lengthMs": 120, "velocity": {"source": "value", "in": [0, 30], "abs": true}}},
      {"source": "posture:up", "muted": true, "to": {"macro": 3}},
      {"source": "speed", "threshold": 200, "to": {"action": "forward"}},
      {"source": "azimuth", "zones": [[0, 180, 60], [180, 360, 67]],
       "to": {"midi": "mpe", "members": 7, "bend": {"source": "roll", "in": [-45, 45]}, "timbre": {"source": "elevation", "in": [0, 90]}}},
      {"source": "scene.pitch", "smooth": {"minCutoffHz": 2, "beta": 0.1, "derivativeCutoffHz": 1.5}, "to": {"param": "theremin.range"}},
      {"source": "fluxFace", "to": {"midi": "nrpn", "channel": 16, "number": 1234}},
      {"source": "qx", "curve": "s", "shape": 1, "to": {"midi": "cc14", "cc": 7, "lsbFirst": true}}],
     "postures": [{"name": "up", "radius": 25, "hysteresis": 4, "maxSpeed": 60, "examples": [[0.5, 0.5, 0.5, 0.5], [1, 0, 0, 0]]}]})";
    const MappingDocument a = parseMappingDocument(rich, "rich.json");
    const std::string text = toJson(a);
    const MappingDocument b = parseMappingDocument(text, "written.json");
    REQUIRE(toJson(b) == text);
    REQUIRE(b.mappings.size() == a.mappings.size());
    CHECK(b.mappings[0].transform.minCutoffHz == Approx(1000.0 / (2 * kPi * 20.0)));
    CHECK(b.mappings[2].to.args[1].negate);
    CHECK(b.mappings[2].to.args[1].source.kind == SourceKind::Yaw);
    CHECK(b.mappings[2].to.args[1].type == 'i');
    CHECK(b.mappings[2].to.args[3].type == 's');
    CHECK(b.mappings[3].to.velocitySource.abs);
    CHECK(b.mappings[4].muted);
    CHECK(b.postures.at(0).examples.size() == 2);
    CHECK(b.postures.at(0).radiusDeg == 25.0);
}

TEST_CASE("Bad mapping files are refused with file, line, column and the reason", "[mapping][format]")
{
    // A syntax error: line 2, the missing comma.
    std::string e = parseMessage("{\"version\": 1,\n \"mappings\": [ {\"source\": \"roll\" \"to\": {}} ]}");
    CHECK_THAT(e, Catch::Contains("bad.json:2:"));
    CHECK_THAT(e, Catch::Contains("column"));
    // Meaning errors name the place in the document.
    e = parseMessage("{\"version\": 1, \"mappings\": [\n  {\"source\": \"elbow\", \"to\": {\"midi\": \"cc\", \"cc\": 1}}]}");
    CHECK_THAT(e, Catch::Contains("bad.json:2: column 14: mappings[0].source"));
    CHECK_THAT(e, Catch::Contains("unknown source \"elbow\""));
    e = parseMessage(R"({"version": 1, "mappings": [{"source": "roll", "to": {"midi": "cc", "channel": 17, "cc": 1}}]})");
    CHECK_THAT(e, Catch::Contains("mappings[0].to.channel") && Catch::Contains("outside 1…16"));
    e = parseMessage(R"({"version": 2, "mappings": []})");
    CHECK_THAT(e, Catch::Contains("version 2 is not supported"));
    e = parseMessage(R"({"mappings": []})");
    CHECK_THAT(e, Catch::Contains("missing \"version\""));
    e = parseMessage(R"({"version": 1, "mappings": [{"source": "roll", "to": {"midi": "cc", "chanel": 2, "cc": 1}}]})");
    CHECK_THAT(e, Catch::Contains("unknown key \"chanel\""));
    e = parseMessage(R"({"version": 1, "mappings": [{"source": "azimuth", "to": {"midi": "notes", "zones": [[0, 90]]}}]})");
    CHECK_THAT(e, Catch::Contains("zones[0]") && Catch::Contains("[from, to, note]"));
    e = parseMessage(R"({"version": 1, "mappings": [{"source": "roll", "to": {"midi": "notes"}}]})");
    CHECK_THAT(e, Catch::Contains("notes need zones"));
    e = parseMessage(R"({"version": 1, "mappings": [{"source": "posture:up", "to": {"macro": 1}}]})");
    CHECK_THAT(e, Catch::Contains("no posture named \"up\""));
    e = parseMessage(R"({"version": 1, "mappings": [{"source": "roll", "arm": "both", "to": {"macro": 1}}]})");
    CHECK_THAT(e, Catch::Contains("mappings[0].arm") && Catch::Contains("unknown arm \"both\""));
    e = parseMessage(R"({"version": 1, "mappings": [{"source": "roll", "to": {"macro": 9}}]})");
    CHECK_THAT(e, Catch::Contains("to.macro"));
    e = parseMessage(R"({"version": 1, "mappings": [{"source": "roll", "to": {"osc": "synth"}}]})");
    CHECK_THAT(e, Catch::Contains("starts with '/'"));
    e = parseMessage(R"({"version": 1, "mappings": [{"source": "roll", "in": [5, 5], "to": {"macro": 1}}]})");
    CHECK_THAT(e, Catch::Contains("empty range"));
    CHECK_THAT(parseMessage(""), Catch::Contains("bad.json"));
}

TEST_CASE("cc14 sends MSB on cc and LSB on cc+32, MSB first, 0…16383 over in, clamped", "[mapping][midi]")
{
    Rig rig(R"({"version": 1, "mappings": [{"source": "elevation", "in": [-45, 45], "to": {"midi": "cc14", "channel": 3, "cc": 1}}]})");
    CcState cc;
    double t = 0.0;
    for (double e = -60.0; e <= 60.0; e += 0.37, t += 0.005) {
        const std::size_t first = rig.midi.size();
        rig.pose(e, 0.0, 0.0, t);
        const int want = expected14(e, -45.0, 45.0);
        if (rig.midi.size() > first) {
            REQUIRE(rig.midi.size() - first == 2);
            CHECK(rig.midi[first].bytes[0] == 0xB2);       // channel 3
            CHECK(rig.midi[first].bytes[1] == 1);          // MSB first
            CHECK(rig.midi[first + 1].bytes[1] == 33);     // then LSB on cc + 32
        }
        for (std::size_t i = first; i < rig.midi.size(); ++i) cc.apply(rig.midi[i]);
        CHECK(128 * cc.get(3, 1) + cc.get(3, 33) == want);
    }
    // Still arm, still value: nothing more is sent.
    const std::size_t n = rig.midi.size();
    rig.pose(10.0, 0.0, 0.0, t);
    rig.pose(10.0, 0.0, 0.0, t + 0.005);
    rig.pose(10.0, 0.0, 0.0, t + 0.010);
    CHECK(rig.midi.size() - n == 2);
}

TEST_CASE("Pitch bend, channel pressure, cc7, NRPN and program change encode as MIDI 1.0 says", "[mapping][midi]")
{
    Rig rig(R"({"version": 1, "mappings": [
        {"source": "roll", "in": [-90, 90], "to": {"midi": "pitchbend", "channel": 2}},
        {"source": "elevation", "in": [-90, 90], "to": {"midi": "pressure", "channel": 5}},
        {"source": "elevation", "in": [-90, 90], "to": {"midi": "cc", "channel": 1, "cc": 7}},
        {"source": "roll", "in": [-90, 90], "to": {"midi": "nrpn", "channel": 1, "number": 300}},
        {"source": "elevation", "in": [-90, 90], "steps": 4, "out": [0, 3], "to": {"midi": "program", "channel": 10}}]})");
    rig.pose(30.0, 0.0, -45.0, 0.0);
    const int bend = expected14(-45.0, -90.0, 90.0);
    const int seven = static_cast<int>(std::lround((30.0 + 90.0) / 180.0 * 127.0));
    std::vector<std::array<int, 3>> got;
    for (const MidiEvent& e : rig.midi) got.push_back({e.bytes[0], e.size > 1 ? e.bytes[1] : -1, e.size > 2 ? e.bytes[2] : -1});
    REQUIRE(got.size() == 1 + 1 + 1 + 4 + 1);
    CHECK(got[0] == std::array<int, 3> {0xE1, bend & 0x7F, bend >> 7});   // LSB then MSB (MIDI 1.0 pitch bend)
    CHECK(got[1] == std::array<int, 3> {0xD4, seven, -1});
    CHECK(got[2] == std::array<int, 3> {0xB0, 7, seven});
    CHECK(got[3] == std::array<int, 3> {0xB0, 99, 300 >> 7});
    CHECK(got[4] == std::array<int, 3> {0xB0, 98, 300 & 0x7F});
    CHECK(got[5] == std::array<int, 3> {0xB0, 6, bend >> 7});
    CHECK(got[6] == std::array<int, 3> {0xB0, 38, bend & 0x7F});
    // steps = 4 over [-90, 90]: 30° is 0.667 → step 2 of 0…3.
    CHECK(got[7] == std::array<int, 3> {0xC9, 2, -1});
    CHECK(rig.midi[0].size == 3);
    CHECK(rig.midi[1].size == 2);
}

TEST_CASE("Zones: the start zone sounds at once, a crossing is one off/on pair, a wiggle is nothing", "[mapping][zones]")
{
    Rig rig(kIssueExample);
    const auto notes = [&](std::size_t from) {
        std::vector<std::array<int, 2>> v;   // {on?, note}
        for (std::size_t i = from; i < rig.midi.size(); ++i) {
            const int type = rig.midi[i].bytes[0] & 0xF0;
            if ((type == 0x90 || type == 0x80) && (rig.midi[i].bytes[0] & 0x0F) == 2)
                v.push_back({type == 0x90 && rig.midi[i].bytes[2] > 0 ? 1 : 0, rig.midi[i].bytes[1]});
        }
        return v;
    };
    rig.pose(0.0, 80.0, 0.0, 0.0);
    auto v = notes(0);
    REQUIRE(v.size() == 1);
    CHECK(v[0] == std::array<int, 2> {1, 60});
    // Wiggle across the 90° border by less than the default hysteresis (between 1.5° and 5°).
    std::size_t mark = rig.midi.size();
    double t = 0.005;
    for (int i = 0; i < 200; ++i, t += 0.005) rig.pose(0.0, 90.0 + 1.4 * std::sin(i * 0.7), 0.0, t);
    CHECK(notes(mark).empty());
    CHECK(kDefaultHysteresisDeg >= 1.5);
    CHECK(kDefaultHysteresisDeg <= 5.0);
    // A real crossing: exactly one note-off (60) then one note-on (62).
    mark = rig.midi.size();
    for (double az = 90.0; az <= 120.0; az += 0.5, t += 0.005) rig.pose(0.0, az, 0.0, t);
    v = notes(mark);
    REQUIRE(v.size() == 2);
    CHECK(v[0] == std::array<int, 2> {0, 60});
    CHECK(v[1] == std::array<int, 2> {1, 62});
    // Through north (360 → 0) from the last zone into the first.
    mark = rig.midi.size();
    for (double az = 300.0; az <= 420.0; az += 1.0, t += 0.005) rig.pose(0.0, std::fmod(az, 360.0), 0.0, t);
    v = notes(mark);
    REQUIRE(v.size() == 4);   // 62 off, 65 on (jump to 300°), 65 off, 60 on (through north)
    CHECK(v[0] == std::array<int, 2> {0, 62});
    CHECK(v[1] == std::array<int, 2> {1, 65});
    CHECK(v[2] == std::array<int, 2> {0, 65});
    CHECK(v[3] == std::array<int, 2> {1, 60});
}

TEST_CASE("Note velocity is the constant or follows a source", "[mapping][zones]")
{
    Rig rig(R"({"version": 1, "mappings": [
        {"source": "azimuth", "to": {"midi": "notes", "channel": 1, "velocity": 100, "zones": [[0, 180, 60]]}},
        {"source": "azimuth", "to": {"midi": "notes", "channel": 2, "zones": [[0, 180, 61]],
                                      "velocity": {"source": "elevation", "in": [0, 90]}}}]})");
    rig.pose(45.0, 10.0, 0.0, 0.0);
    REQUIRE(rig.midi.size() == 2);
    CHECK(rig.midi[0].bytes[2] == 100);
    CHECK(rig.midi[1].bytes[2] == std::lround(0.5 * 127.0));
}

TEST_CASE("Transform: invert, curves, dead zone, steps, scale and out range", "[mapping][transform]")
{
    const auto value = [](const std::string& transform, double x) {
        Rig rig("{\"version\": 1, \"mappings\": [{\"source\": \"elevation\", \"in\": [0, 90], \"out\": [0, 16383], " + transform +
                " \"to\": {\"midi\": \"pitchbend\", \"channel\": 1}}]}");
        rig.pose(x, 0.0, 0.0, 0.0);
        REQUIRE(rig.midi.size() == 1);
        return rig.midi[0].bytes[1] + 128 * rig.midi[0].bytes[2];
    };
    const auto of = [](double n) { return static_cast<int>(std::lround(n * 16383.0)); };
    CHECK(value("", 30.0) == of(1.0 / 3.0));
    CHECK(value("\"invert\": true,", 30.0) == of(2.0 / 3.0));
    CHECK(value("\"curve\": \"exp\", \"shape\": 2,", 45.0) == of((std::exp(1.0) - 1.0) / (std::exp(2.0) - 1.0)));
    CHECK(value("\"curve\": \"log\", \"shape\": 2,", 45.0) == of(std::log(1.0 + 0.5 * (std::exp(2.0) - 1.0)) / 2.0));
    CHECK(value("\"curve\": \"s\", \"shape\": 1,", 22.5) == of(0.0625 / (0.0625 + 0.5625)));   // k = 2: n²/(n² + (1−n)²)
    CHECK(value("\"curve\": \"s\", \"shape\": 1,", 45.0) == of(0.5));
    CHECK(value("\"curve\": \"table\", \"table\": [[0, 0], [0.5, 0.9], [1, 1]],", 22.5) == of(0.45));
    CHECK(value("\"curve\": \"table\", \"table\": [[0, 0], [0.5, 0.9], [1, 1]],", 67.5) == of(0.95));
    // Dead zone of 5° around the centre (45°): 48° reads 45°, 60° is rescaled so 90° still reaches the top.
    CHECK(value("\"deadZone\": 5,", 48.0) == of(0.5));
    CHECK(value("\"deadZone\": 5,", 90.0) == of(1.0));
    CHECK(value("\"deadZone\": 5,", 67.5) == of(0.5 + 0.5 * (22.5 - 5.0) / 40.0));
    CHECK(value("\"steps\": 3,", 30.0) == of(0.5));
    CHECK(value("\"steps\": 3,", 10.0) == of(0.0));
    // Out of range clamps.
    CHECK(value("", -10.0) == 0);
    CHECK(value("", 100.0) == 16383);
}

TEST_CASE("Quantise to a scale: semitones snap to the nearest degree of the scale", "[mapping][transform]")
{
    // Output 48…72 semitones as OSC floats; D major (root 2): D E F# G A B C#.
    Rig rig(R"({"version": 1, "mappings": [{"source": "elevation", "in": [0, 24], "out": [48, 72], "scale": "major", "root": 2,
               "to": {"osc": "/note"}}]})");
    const int dMajor[] {2, 4, 6, 7, 9, 11, 1};
    double t = 0.0;
    for (int step = 0; step <= 24; ++step, t += 0.01) {
        rig.osc.clear();
        rig.pose(step, 0.0, 0.0, t);
        if (rig.osc.empty()) continue;   // same note as before: nothing sent
        float got = 0.0f;
        osc::decodeOscPacket(rig.osc[0].data(), rig.osc[0].size(), [&](const osc::OscMessage& m) { got = m.args[0].f; });
        const int semis = 48 + step;
        int best = -1;
        for (int d = 0; d <= 6 && best < 0; ++d)
            for (int cand : {semis - d, semis + d})
                if (best < 0 && std::count(std::begin(dMajor), std::end(dMajor), ((cand % 12) + 12) % 12) > 0) best = cand;
        CHECK(static_cast<int>(got) == best);
        CHECK(std::count(std::begin(dMajor), std::end(dMajor), static_cast<int>(got) % 12) == 1);
    }
}

TEST_CASE("One-euro smoothing: a step is followed with the named time constant; noise is calmed", "[mapping][transform]")
{
    // smoothMs 50 at rest (beta 0): a first-order low-pass with τ = 50 ms. After a 0 → 90° step,
    // one τ later the output is at 1 − 1/e of the step (within the discretisation at 200 Hz).
    Rig rig(R"({"version": 1, "mappings": [{"source": "elevation", "in": [0, 90], "smoothMs": 50,
               "to": {"midi": "pitchbend", "channel": 1}}]})");
    rig.pose(0.0, 0.0, 0.0, 0.0);
    double t = 0.0;
    int last = 0;
    for (int i = 1; i <= 10; ++i) {
        t = i * 0.005;
        rig.pose(90.0, 0.0, 0.0, t);
        const MidiEvent& e = rig.midi.back();
        last = e.bytes[1] + 128 * e.bytes[2];
    }
    const double alpha = 0.005 / (0.005 + 0.05);
    const double expected = 1.0 - std::pow(1.0 - alpha, 10.0);   // the discrete filter after 10 steps (= 50 ms)
    CHECK(last / 16383.0 == Approx(expected).margin(1.0 / 16383.0));
    CHECK(expected == Approx(1.0 - std::exp(-1.0)).margin(0.03));
}

TEST_CASE("Smoothing an azimuth through north does not swing round the long way", "[mapping][transform]")
{
    Rig rig(R"({"version": 1, "mappings": [{"source": "azimuth", "smoothMs": 30, "to": {"osc": "/az", "args": ["$value"]},
                "out": [0, 360]}]})");
    double t = 0.0;
    float lo = 1e9f, hi = -1e9f;
    for (int i = 0; i < 200; ++i, t += 0.005) {
        rig.osc.clear();
        rig.pose(0.0, std::fmod(359.0 + 2.0 * std::sin(i * 0.3) + 360.0, 360.0), 0.0, t);
        for (const auto& p : rig.osc)
            osc::decodeOscPacket(p.data(), p.size(), [&](const osc::OscMessage& m) {
                const double v = m.args[0].f;
                const float d = static_cast<float>(std::min(std::fabs(v - 359.0), 360.0 - std::fabs(v - 359.0)));
                lo = std::min(lo, d);
                hi = std::max(hi, d);
            });
    }
    CHECK(hi < 3.0f);   // never more than the wiggle away from 359°, on either side of north
}

TEST_CASE("Thresholds turn a continuous source into on/off events with hysteresis", "[mapping][zones]")
{
    Rig rig(R"({"version": 1, "mappings": [{"source": "elevation", "threshold": 30, "to": {"midi": "note", "channel": 1, "note": 50}}]})");
    double t = 0.0;
    rig.pose(0.0, 0.0, 0.0, t);
    CHECK(rig.midi.empty());
    rig.pose(31.0, 0.0, 0.0, t += 0.005);
    REQUIRE(rig.midi.size() == 1);
    CHECK(rig.midi[0].bytes[0] == 0x90);
    for (int i = 0; i < 100; ++i) rig.pose(30.0 + 2.5 * std::sin(i * 0.9), 0.0, 0.0, t += 0.005);   // wiggle < 3°
    CHECK(rig.midi.size() == 1);
    rig.pose(20.0, 0.0, 0.0, t += 0.005);
    REQUIRE(rig.midi.size() == 2);
    CHECK(rig.midi[1].bytes[0] == 0x80);
}

TEST_CASE("Gestures: notes of the given length, retriggered, 'other' and '*'", "[mapping][events]")
{
    Rig rig(R"({"version": 1, "mappings": [
        {"source": "gesture:punch", "to": {"midi": "note", "channel": 1, "note": 62, "velocity": {"source": "value", "in": [0, 1], "abs": true}}},
        {"source": "gesture:other", "to": {"midi": "note", "channel": 1, "note": 67, "lengthMs": 20}},
        {"source": "gesture:*", "to": {"osc": "/any", "args": ["$zone", "$on"]}}]})");
    rig.gesture("punch", -0.5f, 1.0);
    REQUIRE(rig.midi.size() == 1);
    CHECK(rig.midi[0].bytes[0] == 0x90);
    CHECK(rig.midi[0].bytes[1] == 62);
    CHECK(rig.midi[0].bytes[2] == std::lround(0.5 * 127.0));
    CHECK(rig.osc.size() == 1);
    // No note-off before 50 ms, then one exactly at 1.050 s.
    rig.pose(0, 0, 0, 1.02);
    CHECK(rig.midi.size() == 1);
    rig.pose(0, 0, 0, 1.06);
    REQUIRE(rig.midi.size() == 2);
    CHECK(rig.midi[1].bytes[0] == 0x80);
    CHECK(rig.midi[1].t == Approx(1.05));
    // 'other' takes a gesture no mapping names; a retrigger ends the sounding note first.
    rig.gesture("fret", 3.0f, 2.0);
    rig.gesture("fret", 4.0f, 2.005);
    REQUIRE(rig.midi.size() == 5);
    CHECK(rig.midi[2].bytes[1] == 67);
    CHECK(rig.midi[3].bytes[0] == 0x80);
    CHECK(rig.midi[4].bytes[0] == 0x90);
    CHECK(rig.osc.size() == 3);
    rig.mapper.flush(3.0, *rig.out);
    rig.collect();
    REQUIRE(rig.midi.size() == 6);
    CHECK(rig.midi[5].t == Approx(2.025));
}

TEST_CASE("Forward: yaw is measured from the forward direction the performer set", "[mapping][forward]")
{
    Rig rig(R"({"version": 1, "mappings": [{"source": "yaw", "to": {"osc": "/yaw", "args": ["$yaw"]}},
                                           {"source": "gesture:select", "to": {"action": "forward"}}]})");
    const auto yaw = [&](double az, double t) {
        rig.osc.clear();
        rig.pose(0.0, az, 0.0, t);
        float y = 999.0f;
        for (const auto& p : rig.osc) osc::decodeOscPacket(p.data(), p.size(), [&](const osc::OscMessage& m) { y = m.args[0].f; });
        return y;
    };
    CHECK(yaw(30.0, 0.0) == Approx(-30.0f));    // turning clockwise (east) is negative yaw
    CHECK(yaw(350.0, 0.01) == Approx(10.0f));
    rig.mapper.requestForward();
    CHECK(yaw(100.0, 0.02) == Approx(0.0f).margin(1e-4));
    CHECK(rig.mapper.forwardAzimuth() == Approx(100.0));
    CHECK(yaw(70.0, 0.03) == Approx(30.0f));
    CHECK(yaw(290.0, 0.04) == Approx(170.0f));   // wrapped to ±180
    CHECK(yaw(279.0, 0.05) == Approx(-179.0f));
    // The SetForward destination from a gesture.
    rig.gesture("select", 1.0f, 0.06, armAt(0.0, 200.0, 0.0));
    CHECK(rig.mapper.forwardAzimuth() == Approx(200.0));
    rig.mapper.setForwardAzimuth(10.0);
    CHECK(yaw(20.0, 0.07) == Approx(-10.0f));
}

TEST_CASE("MPE: one note per zone on member channels, with per-note expression", "[mapping][mpe]")
{
    Rig rig(R"({"version": 1, "mappings": [{"source": "azimuth", "zones": [[0, 90, 60], [90, 180, 62]],
        "to": {"midi": "mpe", "members": 3, "bend": {"source": "roll", "in": [-90, 90]}, "pressure": {"source": "elevation", "in": [0, 90]}}}]})");
    rig.pose(45.0, 45.0, 45.0, 0.0);
    // MPE Configuration Message on the master channel (channel 1): RPN 6 = 3 members, then the null RPN.
    REQUIRE(rig.midi.size() >= 9);
    CHECK(rig.midi[0].bytes == std::array<std::uint8_t, 3> {0xB0, 101, 0});
    CHECK(rig.midi[1].bytes == std::array<std::uint8_t, 3> {0xB0, 100, 6});
    CHECK(rig.midi[2].bytes == std::array<std::uint8_t, 3> {0xB0, 6, 3});
    const MidiEvent& on = rig.midi.back();
    CHECK(on.bytes[0] == 0x91);   // first member: channel 2
    CHECK(on.bytes[1] == 60);
    const int bend = expected14(45.0, -90.0, 90.0);
    bool sawBend = false;
    for (const MidiEvent& e : rig.midi)
        if (e.bytes[0] == 0xE1) sawBend = sawBend || (e.bytes[1] + 128 * e.bytes[2] == bend);
    CHECK(sawBend);
    // Expression follows while the note sounds, on its own channel.
    std::size_t mark = rig.midi.size();
    rig.pose(45.0, 45.0, -45.0, 0.005);
    REQUIRE(rig.midi.size() == mark + 1);
    CHECK(rig.midi[mark].bytes[0] == 0xE1);
    // The next zone's note goes to the next member channel.
    mark = rig.midi.size();
    rig.pose(45.0, 120.0, -45.0, 0.01);
    CHECK(rig.midi[mark].bytes == std::array<std::uint8_t, 3> {0x81, 60, 0});
    CHECK(rig.midi.back().bytes[0] == 0x92);
    CHECK(rig.midi.back().bytes[1] == 62);
}

TEST_CASE("Macros and scene parameters are handed to the front end", "[mapping][host]")
{
    Rig rig(R"({"version": 1, "mappings": [{"source": "elevation", "in": [-90, 90], "to": {"macro": 2}},
                                           {"source": "roll", "in": [-90, 90], "to": {"param": "theremin.range"}},
                                           {"source": "roll", "in": [-90, 90], "out": [1, 4], "to": {"param": "cymbal.damping"}}]})");
    REQUIRE(rig.mapper.active()->macrosUsed() == 0b10);
    REQUIRE(rig.mapper.active()->sceneParamIds() == std::vector<std::string> {"theremin.range", "cymbal.damping"});
    rig.pose(45.0, 0.0, 45.0, 0.0);
    CHECK(rig.macroChanged == 0b10);
    CHECK(rig.macro[1] == Approx(0.75f));
    REQUIRE(rig.params.size() == 2);
    CHECK(rig.params[0].index == 0);
    CHECK(rig.params[0].normalised);
    CHECK(rig.params[0].value == Approx(0.75f));
    CHECK(rig.params[1].index == 1);
    CHECK_FALSE(rig.params[1].normalised);
    CHECK(rig.params[1].value == Approx(1.0f + 0.75f * 3.0f));
    // A scene without that parameter is refused when the set is built.
    BuildOptions options;
    options.sceneParamIds = {"theremin.range"};
    CHECK_THROWS_WITH(MappingSet::build(rig.mapper.active()->document(), options), Catch::Contains("no parameter \"cymbal.damping\""));
}

TEST_CASE("Scene outputs are sources where the scene has them", "[mapping][sources]")
{
    Rig rig(R"({"version": 1, "mappings": [{"source": "scene.pitch", "in": [0, 127], "to": {"midi": "cc", "channel": 1, "cc": 20}}]})");
    const ArmState arm = armAt(0, 0, 0);
    rig.step(arm, 0.0);
    CHECK(rig.midi.empty());   // NaN: this scene has no pitch
    SceneValues v;
    v.pitch = 69.0f;
    rig.step(arm, 0.005, nullptr, 0, v);
    REQUIRE(rig.midi.size() == 1);
    CHECK(rig.midi[0].bytes[2] == 69);
}

TEST_CASE("Muting a mapping ends its note and silences it; unmuting sends afresh", "[mapping][host]")
{
    Rig rig(R"({"version": 1, "mappings": [{"source": "azimuth", "to": {"midi": "notes", "channel": 1, "zones": [[0, 180, 60]]}},
                                           {"source": "elevation", "to": {"midi": "cc", "channel": 1, "cc": 1}}]})");
    rig.pose(0.0, 10.0, 0.0, 0.0);
    REQUIRE(rig.midi.size() == 2);
    CHECK(rig.mapper.active()->active(0));
    rig.mapper.active()->setMuted(0, true);
    rig.mapper.active()->setMuted(1, true);
    rig.pose(20.0, 10.0, 0.0, 0.005);
    REQUIRE(rig.midi.size() == 3);
    CHECK(rig.midi[2].bytes[0] == 0x80);
    rig.pose(30.0, 10.0, 0.0, 0.01);
    CHECK(rig.midi.size() == 3);
    rig.mapper.active()->setMuted(0, false);
    rig.mapper.active()->setMuted(1, false);
    rig.pose(30.0, 10.0, 0.0, 0.015);
    CHECK(rig.midi.size() == 5);
    CHECK(rig.mapper.active()->meter(1) == Approx((30.0 + 90.0) / 180.0));
}

TEST_CASE("A new set takes over at the next update; the old one's notes end there", "[mapping][handover]")
{
    Rig rig(R"({"version": 1, "mappings": [{"source": "azimuth", "to": {"midi": "notes", "channel": 1, "zones": [[0, 180, 60]]}}]})");
    rig.pose(0.0, 10.0, 0.0, 0.0);
    REQUIRE(rig.midi.size() == 1);
    auto next = MappingSet::build(parseMappingDocument(R"({"version": 1, "mappings": [{"source": "elevation", "to": {"midi": "cc", "channel": 1, "cc": 9}}]})", "x"));
    REQUIRE(rig.mapper.offer(next));
    CHECK(next == nullptr);
    auto another = MappingSet::build(parseMappingDocument(R"({"version": 1, "mappings": []})", "y"));
    CHECK_FALSE(rig.mapper.offer(another));   // one hand-over at a time
    CHECK(another != nullptr);
    rig.pose(0.0, 10.0, 0.0, 0.005);
    REQUIRE(rig.midi.size() == 3);
    CHECK(rig.midi[1].bytes == std::array<std::uint8_t, 3> {0x80, 60, 0});
    CHECK(rig.midi[2].bytes[1] == 9);
    CHECK_FALSE(rig.mapper.canOffer());       // the retired set waits for collect()
    rig.mapper.collect();
    CHECK(rig.mapper.offer(another));
}

TEST_CASE("MIDI learn takes the destination from the next message; range learning keeps the extremes", "[mapping][learn]")
{
    DestinationSpec d;
    const std::uint8_t cc[] {0xB4, 11, 64};
    REQUIRE(learnDestination(cc, 3, d));
    CHECK(d.kind == DestinationKind::Cc7);
    CHECK(d.channel == 5);
    CHECK(d.number == 11);
    const std::uint8_t pair[] {0xB0, 1, 10, 0xB0, 33, 5};
    REQUIRE(learnDestination(pair, 6, d));
    CHECK(d.kind == DestinationKind::Cc14);
    const std::uint8_t bend[] {0xEF, 0, 64};
    REQUIRE(learnDestination(bend, 3, d));
    CHECK(d.kind == DestinationKind::PitchBend);
    CHECK(d.channel == 16);
    const std::uint8_t off[] {0x90, 60, 0};
    CHECK_FALSE(learnDestination(off, 3, d));
    const std::uint8_t sysex[] {0xF0, 1, 0xF7};
    CHECK_FALSE(learnDestination(sysex, 3, d));

    RangeLearner r;
    double lo = 0, hi = 0;
    CHECK_FALSE(r.range(lo, hi));
    for (double x : {3.0, -2.0, 1.0, kNaN}) r.add(x);
    REQUIRE(r.range(lo, hi));
    CHECK(lo == -2.0);
    CHECK(hi == 3.0);
}

TEST_CASE("Quaternion sources keep w ≥ 0 and the SceneRotator quaternion composes yaw, pitch, roll", "[mapping][sources]")
{
    const ArmState arm = armAt(20.0, 300.0, -35.0);
    MappingInput in;
    in.arm[0] = &arm;
    SourceSpec s;
    double q[4];
    const SourceKind kinds[] {SourceKind::YprQuatW, SourceKind::YprQuatX, SourceKind::YprQuatY, SourceKind::YprQuatZ};
    for (int k = 0; k < 4; ++k) {
        s.kind = kinds[k];
        q[k] = readSource(s, in, 0.0);
    }
    // Independently: q = qz(yaw) · qy(pitch) · qx(roll) with Eigen, yaw = −(300 − 0) wrapped = 60°.
    const Eigen::Quaterniond want = Eigen::AngleAxisd(degToRad(60.0), Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(degToRad(20.0), Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(degToRad(-35.0), Eigen::Vector3d::UnitX());
    const double sign = want.w() < 0 ? -1.0 : 1.0;
    CHECK(q[0] == Approx(sign * want.w()));
    CHECK(q[1] == Approx(sign * want.x()));
    CHECK(q[2] == Approx(sign * want.y()));
    CHECK(q[3] == Approx(sign * want.z()));
    s.kind = SourceKind::QuatW;
    CHECK(readSource(s, in, 0.0) >= 0.0);
    s.kind = SourceKind::Elevation;
    MappingInput none;
    CHECK(std::isnan(readSource(s, none, 0.0)));
}

TEST_CASE("Panic: the sounding notes end, then CC 120 and CC 123 (value 0) on all 16 channels", "[mapping][panic]")
{
    Rig rig(kIssueExample);
    rig.pose(0.0, 80.0, 0.0, 0.0);   // azimuth 80°: zone note 60 sounds on channel 3
    std::size_t mark = rig.midi.size();
    rig.mapper.panic(0.5, *rig.out);
    rig.collect();
    // MIDI 1.0 Channel Mode messages: Bn 78 00 (All Sound Off), Bn 7B 00 (All Notes Off).
    std::vector<std::array<int, 3>> expected {{0x82, 60, 0}};   // the note-off first (channel 3 = n 2)
    for (int n = 0; n < 16; ++n) {
        expected.push_back({0xB0 + n, 0x78, 0});
        expected.push_back({0xB0 + n, 0x7B, 0});
    }
    const auto since = [&](std::size_t from, double t) {
        std::vector<std::array<int, 3>> v;
        for (std::size_t i = from; i < rig.midi.size(); ++i) {
            const MidiEvent& e = rig.midi[i];
            // A note-off may be sent as 8n or as 9n with velocity 0 (MIDI 1.0): compare as 8n.
            const bool off = (e.bytes[0] & 0xF0) == 0x90 && e.bytes[2] == 0;
            v.push_back({off ? (0x80 | (e.bytes[0] & 0x0F)) : e.bytes[0], e.bytes[1], off ? 0 : e.bytes[2]});
            CHECK(e.t == t);
        }
        return v;
    };
    CHECK(since(mark, 0.5) == expected);
    // Nothing sounding: the 32 controller messages alone.
    mark = rig.midi.size();
    rig.mapper.panic(0.6, *rig.out);
    rig.collect();
    CHECK(since(mark, 0.6) == std::vector<std::array<int, 3>>(expected.begin() + 1, expected.end()));
}
