// The mapping layer with two arms (issue 28, docs/MAPPING.md "Two arms"): every arm source per
// arm ("left." names), the relative sources (arms.angle, arms.roll, arms.raised), and one arm
// giving those no value. Expected values are computed here from the definitions (spherical
// geometry of the two forearm directions, the documented gate), not read back from the code.
#include "Core/Errors.h"
#include "Mapping/MappingHelpers.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::mapping;
using namespace armadillo::mapping::test;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// An arm at a pose that is also turning and accelerating (so speed, fluxes and punch have values).
ArmState movingArm(double el, double az, double roll, double spin)
{
    ArmState a = armAt(el, az, roll);
    a.gyro = Eigen::Vector3d(0.3 * spin, -0.2 * spin, 0.5 * spin);
    a.accel = Eigen::Vector3d(1.0 + spin, 9.0, 0.5);
    a.features.fluxFace = 0.1 * spin;
    a.features.fluxEdge = -0.4 * spin;
    a.features.rollTrigger = 0.7 * spin;
    a.features.punch = 2.0 * spin;
    return a;
}

/// A Mapper stepped with two arms (or one: left = nullptr), collecting MIDI.
struct TwoArmRig {
    Mapper mapper;
    std::unique_ptr<MappingOutput> out = std::make_unique<MappingOutput>();
    std::vector<MidiEvent> midi;
    explicit TwoArmRig(const std::string& json) { mapper.replace(MappingSet::build(parseMappingDocument(json, "two.json"))); }
    std::size_t step(const ArmState& right, const ArmState* left, double t)
    {
        MappingInput in;
        in.t = t;
        in.arm[0] = &right;
        in.arm[1] = left;
        const std::size_t before = midi.size();
        mapper.process(in, *out);
        for (int i = 0; i < out->midiCount; ++i) midi.push_back(out->midi[static_cast<std::size_t>(i)]);
        out->clear();
        return midi.size() - before;
    }
};

/// Every source read from one arm, by its file name.
const char* const kArmSources[] = {"elevation", "azimuth",  "roll",        "yaw",   "pitch",  "qw",     "qx",     "qy",     "qz",
                                   "speed",     "fluxFace", "fluxEdge", "rollTrigger", "punch", "ypr.qw", "ypr.qx", "ypr.qy", "ypr.qz"};

double read(const std::string& name, const ArmState& right, const ArmState* left)
{
    SourceSpec s;
    REQUIRE(parseSourceName(name, s));
    MappingInput in;
    in.arm[0] = &right;
    in.arm[1] = left;
    return readSource(s, in, 0.0);
}

/// The angle between two forearm directions from their elevations and azimuths alone (the
/// spherical law of cosines), degrees.
double angleBetween(double el1, double az1, double el2, double az2)
{
    const double d = kPi / 180.0;
    const double c = std::sin(el1 * d) * std::sin(el2 * d) + std::cos(el1 * d) * std::cos(el2 * d) * std::cos((az1 - az2) * d);
    return std::acos(std::clamp(c, -1.0, 1.0)) / d;
}

} // namespace

TEST_CASE("Two arms: every arm source has a left-arm name; relative sources; the file round-trips", "[mapping][twoarms]")
{
    for (const char* name : kArmSources) {
        SourceSpec s;
        REQUIRE(parseSourceName(std::string("left.") + name, s));
        CHECK(s.arm == 1);
        CHECK(isArmSource(s.kind));
        CHECK(sourceName(s) == std::string("left.") + name);
        SourceSpec r;
        REQUIRE(parseSourceName(std::string("right.") + name, r));   // the unprefixed name's alias
        CHECK(r.arm == 0);
        CHECK(r.kind == s.kind);
        CHECK(sourceName(r) == name);
    }
    for (const char* name : {"arms.angle", "arms.roll", "arms.raised"}) {
        SourceSpec s;
        REQUIRE(parseSourceName(name, s));
        CHECK(isTwoArmSource(s.kind));
        CHECK_FALSE(isArmSource(s.kind));
        CHECK(sourceName(s) == name);
    }
    SourceSpec none;
    for (const char* bad : {"left.scene.pitch", "left.gesture:punch", "left.posture:up", "left.arms.angle", "left.left.roll", "left.", "centre.roll"})
        CHECK_FALSE(parseSourceName(bad, none));

    // "arm": "left" is the same as the left. name, and is written back as it.
    const MappingDocument doc = parseMappingDocument(R"({"version": 1, "mappings": [
        {"source": "roll", "arm": "left", "to": {"midi": "cc", "cc": 1}},
        {"source": "left.elevation", "arm": 1, "to": {"midi": "cc", "cc": 2}},
        {"source": "arms.angle", "to": {"osc": "/angle", "args": ["$arms.angle", "$left.yaw"]}},
        {"source": "arms.raised", "to": {"midi": "note", "note": 40}},
        {"source": "arms.raised", "threshold": 60, "hysteresis": 5, "to": {"midi": "cc", "cc": 3}}]})",
                                                     "two.json");
    REQUIRE(doc.mappings.size() == 5);
    CHECK(doc.mappings[0].source.arm == 1);
    CHECK(doc.mappings[1].source.arm == 1);
    CHECK(doc.mappings[2].to.args[1].source.arm == 1);
    CHECK(doc.mappings[3].transform.hasThreshold);   // a gate: the documented default threshold
    CHECK(doc.mappings[3].transform.threshold == kDefaultArmsRaisedDeg);
    CHECK(doc.mappings[4].transform.threshold == 60.0);
    const MappingDocument back = parseMappingDocument(toJson(doc), "back.json");
    REQUIRE(back.mappings.size() == 5);
    for (std::size_t i = 0; i < 5; ++i) {
        CHECK(back.mappings[i].source.kind == doc.mappings[i].source.kind);
        CHECK(back.mappings[i].source.arm == doc.mappings[i].source.arm);
        CHECK(back.mappings[i].transform.threshold == doc.mappings[i].transform.threshold);
    }
    CHECK(toJson(doc).find("\"left.roll\"") != std::string::npos);
    REQUIRE_NOTHROW(MappingSet::build(doc));

    // Mistakes name the file, line, column and place.
    std::string e = parseMessage("{\"version\": 1, \"mappings\": [\n {\"source\": \"left.scene.pitch\", \"to\": {\"macro\": 1}}]}", "two.json");
    CHECK_THAT(e, Catch::Contains("two.json:2: column 13: mappings[0].source") && Catch::Contains("left.NAME"));
    e = parseMessage("{\"version\": 1, \"mappings\": [\n {\"source\": \"left.roll\", \"arm\": \"right\", \"to\": {\"macro\": 1}}]}", "two.json");
    CHECK_THAT(e, Catch::Contains("two.json:2:") && Catch::Contains("mappings[0].arm") && Catch::Contains("left arm's"));
    e = parseMessage(R"({"version": 1, "mappings": [{"source": "scene.pitch", "arm": "left", "to": {"macro": 1}}]})", "two.json");
    CHECK_THAT(e, Catch::Contains("mappings[0].arm") && Catch::Contains("not read from one arm"));
    e = parseMessage(R"({"version": 1, "mappings": [{"source": "roll", "arm": "middle", "to": {"macro": 1}}]})", "two.json");
    CHECK_THAT(e, Catch::Contains("unknown arm \"middle\""));
    e = parseMessage(R"({"version": 1, "mappings": [{"source": "arms.raised", "to": {"midi": "notes", "zones": [[0, 90, 60]]}}]})", "two.json");
    CHECK_THAT(e, Catch::Contains("mappings[0].source") && Catch::Contains("a gate"));
}

TEST_CASE("Two arms: varying one arm changes only that arm's sources", "[mapping][twoarms]")
{
    const ArmState right0 = movingArm(10.0, 20.0, 30.0, 1.0), right1 = movingArm(50.0, 100.0, -60.0, 2.5);
    const ArmState left0 = movingArm(-20.0, 300.0, 80.0, -1.0), left1 = movingArm(35.0, 200.0, -10.0, 3.0);
    for (const char* name : kArmSources) {
        const std::string l = std::string("left.") + name;
        INFO(name);
        // The right arm moves: its sources change, the left arm's stay exactly as they were.
        CHECK(read(l, right0, &left0) == read(l, right1, &left0));
        CHECK(read(name, right0, &left0) != read(name, right1, &left0));
        // The left arm moves: the other way round.
        CHECK(read(name, right0, &left0) == read(name, right0, &left1));
        CHECK(read(l, right0, &left0) != read(l, right0, &left1));
        // A left-arm source reads the left arm as its right-arm name reads the right arm.
        CHECK(read(l, right0, &left1) == Approx(read(name, left1, nullptr)).margin(1e-12));
    }

    // Through the mapper: a CC per arm; moving one arm sends only its own CC.
    TwoArmRig rig(R"({"version": 1, "mappings": [
        {"source": "elevation", "to": {"midi": "cc", "cc": 1}},
        {"source": "left.elevation", "to": {"midi": "cc", "cc": 2}}]})");
    rig.step(armAt(0, 0, 0), &left0, 0.0);
    REQUIRE(rig.midi.size() == 2);
    rig.midi.clear();
    for (int i = 1; i <= 20; ++i) rig.step(armAt(2.0 * i, 0, 0), &left0, 0.01 * i);
    REQUIRE_FALSE(rig.midi.empty());
    for (const MidiEvent& m : rig.midi) CHECK(m.bytes[1] == 1);
    rig.midi.clear();
    const ArmState still = armAt(40.0, 0, 0);
    for (int i = 1; i <= 20; ++i) {
        const ArmState l = armAt(-20.0 + 3.0 * i, 300.0, 80.0);
        rig.step(still, &l, 1.0 + 0.01 * i);
    }
    REQUIRE_FALSE(rig.midi.empty());
    for (const MidiEvent& m : rig.midi) CHECK(m.bytes[1] == 2);
}

TEST_CASE("Two arms: arms.angle is the angle between the forearms; arms.roll their roll difference, wrapped", "[mapping][twoarms]")
{
    // A grid of poses over the whole sphere (rolls too: they must not matter to the angle).
    double worst = 0.0;
    int n = 0;
    for (double e1 = -85.0; e1 <= 85.0; e1 += 34.0)
        for (double a1 = 0.0; a1 < 360.0; a1 += 65.0)
            for (double e2 = -80.0; e2 <= 80.0; e2 += 40.0)
                for (double a2 = 5.0; a2 < 360.0; a2 += 50.0) {
                    const double r1 = std::fmod(e1 * 7.0 + a2, 360.0) - 180.0, r2 = std::fmod(a1 * 3.0 + e2 + 400.0, 360.0) - 180.0;
                    const ArmState right = armAt(e1, a1, r1), left = armAt(e2, a2, r2);
                    const double got = read("arms.angle", right, &left);
                    worst = std::max(worst, std::fabs(got - angleBetween(e1, a1, e2, a2)));
                    CHECK(got >= 0.0);
                    CHECK(got <= 180.0);
                    ++n;
                }
    std::printf("arms.angle against the spherical law of cosines: %d pose pairs, largest difference %.2e deg\n", n, worst);
    CHECK(worst < 1e-6);
    // The extremes: parallel (0°) and opposite (180°) forearms.
    const ArmState north = armAt(0, 0, 0), south = armAt(0, 180, 45), up = armAt(90, 0, 0);
    CHECK(read("arms.angle", north, &north) == Approx(0.0).margin(1e-9));
    CHECK(read("arms.angle", north, &south) == Approx(180.0).margin(1e-9));
    CHECK(read("arms.angle", north, &up) == Approx(90.0).margin(1e-9));

    // Relative roll: left − right, wrapped to ±180 (170 and −170 are 20° apart, not 340°).
    const ArmState r170 = armAt(10, 30, 170), lm170 = armAt(-5, 200, -170);
    CHECK(read("arms.roll", r170, &lm170) == Approx(20.0).margin(1e-9));
    CHECK(read("arms.roll", lm170, &r170) == Approx(-20.0).margin(1e-9));
    const ArmState r30 = armAt(0, 0, 30), l_60 = armAt(0, 0, -60);
    CHECK(read("arms.roll", r30, &l_60) == Approx(-90.0).margin(1e-9));
    CHECK(read("arms.raised", r30, &lm170) == Approx(-5.0).margin(1e-9));   // the lower elevation
}

TEST_CASE("Two arms: 'both arms raised' is a gate with hysteresis", "[mapping][twoarms]")
{
    // Default: both elevations ≥ 30° → on; off once either is below 30 − 3 = 27°.
    TwoArmRig rig(R"({"version": 1, "mappings": [{"source": "arms.raised", "to": {"midi": "note", "channel": 1, "note": 40}}]})");
    double t = 0.0;
    auto both = [&](double right, double left) {
        const ArmState r = armAt(right, 0, 0), l = armAt(left, 180, 0);
        return rig.step(r, &l, t += 0.01);
    };
    CHECK(both(0, 0) == 0);
    CHECK(both(50, 29) == 0);    // one arm raised is not both
    CHECK(both(29, 50) == 0);
    REQUIRE(both(31, 30) == 1);  // both at or above 30°
    CHECK(rig.midi.back().bytes[0] == 0x90);
    CHECK(rig.midi.back().bytes[1] == 40);
    for (int i = 0; i < 100; ++i) CHECK(both(29.0 + 1.9 * std::sin(i * 0.7), 60.0) == 0);   // a wiggle down to 27.1°: still on
    REQUIRE(both(26.9, 60) == 1);   // below 27°: off
    CHECK(rig.midi.back().bytes[0] == 0x80);
    CHECK(both(29, 60) == 0);    // back above 27° but below 30°: not on again
    CHECK(both(60, 29.9) == 0);
    REQUIRE(both(30, 30) == 1);
    CHECK(rig.midi.back().bytes[0] == 0x90);
    REQUIRE(both(60, 26) == 1);  // the other arm falling ends it too
    CHECK(rig.midi.back().bytes[0] == 0x80);

    // A threshold and hysteresis of one's own; on a CC the gate sends the top and bottom of out.
    TwoArmRig cc(R"({"version": 1, "mappings": [{"source": "arms.raised", "threshold": 60, "hysteresis": 5, "to": {"midi": "cc", "cc": 7}}]})");
    const ArmState low = armAt(58, 0, 0), high = armAt(61, 0, 0), mid = armAt(56, 0, 0), lower = armAt(54.9, 0, 0);
    CHECK(cc.step(low, &high, 0.0) == 0);
    REQUIRE(cc.step(high, &high, 0.01) == 1);
    CHECK(cc.midi.back().bytes[2] == 127);
    CHECK(cc.step(mid, &high, 0.02) == 0);     // 56 ≥ 60 − 5
    REQUIRE(cc.step(lower, &high, 0.03) == 1);
    CHECK(cc.midi.back().bytes[2] == 0);
}

TEST_CASE("One arm: left-arm and relative sources have no value and their mappings send nothing", "[mapping][twoarms]")
{
    TwoArmRig rig(R"({"version": 1, "mappings": [
        {"source": "elevation", "to": {"midi": "cc", "cc": 1}},
        {"source": "left.elevation", "to": {"midi": "cc", "cc": 2}},
        {"source": "left.azimuth", "to": {"midi": "notes", "zones": [[0, 180, 60], [180, 360, 62]]}},
        {"source": "arms.angle", "to": {"midi": "cc", "cc": 3}},
        {"source": "arms.roll", "to": {"osc": "/r"}},
        {"source": "arms.raised", "to": {"midi": "note", "note": 40}}]})");
    double t = 0.0;
    for (int i = 0; i < 50; ++i) rig.step(armAt(-40.0 + 2.0 * i, 7.0 * i, 0), nullptr, t += 0.01);
    REQUIRE_FALSE(rig.midi.empty());
    for (const MidiEvent& m : rig.midi) {
        CHECK(m.bytes[0] == 0xB0);   // only the right arm's CC 1
        CHECK(m.bytes[1] == 1);
    }
    const ArmState right = armAt(40, 10, 0);
    for (const char* name : {"left.elevation", "left.qw", "left.speed", "arms.angle", "arms.roll", "arms.raised"})
        CHECK(std::isnan(read(name, right, nullptr)));
    ArmState untracked = armAt(40, 10, 0);
    untracked.valid = false;   // a second arm not tracked yet is no arm either
    CHECK(std::isnan(read("arms.angle", right, &untracked)));
    CHECK(std::isnan(read("left.roll", right, &untracked)));

    // The same mappings with a left arm given send from it.
    const ArmState left = armAt(50, 90, 0);
    rig.midi.clear();
    rig.step(armAt(60, 0, 0), &left, t += 0.01);
    bool cc2 = false, cc3 = false, note40 = false;
    for (const MidiEvent& m : rig.midi) {
        cc2 = cc2 || (m.bytes[0] == 0xB0 && m.bytes[1] == 2);
        cc3 = cc3 || (m.bytes[0] == 0xB0 && m.bytes[1] == 3);
        note40 = note40 || (m.bytes[0] == 0x90 && m.bytes[1] == 40);
    }
    CHECK(cc2);
    CHECK(cc3);
    CHECK(note40);
}
