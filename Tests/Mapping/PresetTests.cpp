// The built-in presets against the systems they speak to:
//  - scenerotator: IEM SceneRotator's MrHeadTracker MIDI scheme, decoded here with SceneRotator's
//    own arithmetic (IEM plug-in suite, SceneRotator/Source/PluginProcessor.cpp, processBlock:
//    CC 48/49/50 store the LSB, CC 16/17/18 then set yaw/pitch/roll to (128·MSB + LSB)/16384 of
//    their −180…180° range; so the LSB must arrive first);
//  - scenerotator-osc: /SceneRotator/ypr (yaw, pitch, roll in degrees) and
//    /SceneRotator/quaternions (w, x, y, z) (the same file, interceptOSCMessage);
//  - classic: the plugin's MIDI out as docs/PLUGIN.md "MIDI out" describes it.
#include "Core/Errors.h"
#include "Osc/Osc.h"
#include "Mapping/MappingHelpers.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <random>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::mapping;
using namespace armadillo::mapping::test;

namespace {

/// SceneRotator's receiving side, as its processBlock does it.
struct SceneRotatorMidi {
    int lsb[3] {0, 0, 0};
    double angle[3] {kNaN, kNaN, kNaN};   // yaw, pitch, roll
    int lsbBeforeMsb = 0, msbWithoutFreshLsb = 0;
    bool fresh[3] {false, false, false};
    void apply(const MidiEvent& e)
    {
        if (e.size != 3 || (e.bytes[0] & 0xF0) != 0xB0) return;
        const int cc = e.bytes[1], v = e.bytes[2];
        if (cc >= 48 && cc <= 50) {
            lsb[cc - 48] = v;
            fresh[cc - 48] = true;
        } else if (cc >= 16 && cc <= 18) {
            const int k = cc - 16;
            (fresh[k] ? lsbBeforeMsb : msbWithoutFreshLsb) += 1;
            fresh[k] = false;
            const double normalised = (128 * v + lsb[k]) * (1.0 / 16384);
            angle[k] = -180.0 + 360.0 * normalised;   // the parameters' range −180…180°
        }
    }
};

double angleDiff(double a, double b) { return std::fabs(std::remainder(a - b, 360.0)); }

} // namespace

TEST_CASE("Presets: the built-in ones are listed and load", "[mapping][presets]")
{
    const std::vector<std::string> names = presetNames();
    for (const char* n : {"classic", "mpe", "scenerotator", "scenerotator-osc"}) {
        CHECK(std::find(names.begin(), names.end(), n) != names.end());
        const MappingDocument doc = loadMapping(n);
        CHECK(doc.name == n);
        CHECK_NOTHROW(MappingSet::build(doc));
    }
    CHECK_THROWS_AS(loadMapping("no-such-preset"), IoError);
    CHECK_THROWS_WITH(loadMapping("no-such-preset"), Catch::Contains("scenerotator"));
    CHECK_THROWS_AS(loadMapping("/nonexistent/map.json"), IoError);
}

TEST_CASE("scenerotator: SceneRotator's own decoding gives yaw, pitch, roll within 0.05°, LSB first", "[mapping][presets]")
{
    Rig rig(loadMapping("scenerotator"));
    SceneRotatorMidi sr;
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> el(-89.0, 89.0), az(0.0, 360.0), roll(-179.9, 179.9);
    double t = 0.0;
    for (int i = 0; i < 2000; ++i, t += 0.005) {
        const double e = el(rng), a = az(rng), r = roll(rng);
        const std::size_t first = rig.midi.size();
        rig.pose(e, a, r, t);
        for (std::size_t k = first; k < rig.midi.size(); ++k) sr.apply(rig.midi[k]);
        // The documented convention: yaw = −(azimuth − forward) wrapped to ±180, pitch = elevation, roll = roll.
        const double yaw = -std::remainder(a - 0.0, 360.0);
        CHECK(angleDiff(sr.angle[0], yaw) <= 0.05);
        CHECK(std::fabs(sr.angle[1] - e) <= 0.05);
        CHECK(angleDiff(sr.angle[2], r) <= 0.05);
    }
    CHECK(sr.lsbBeforeMsb > 0);
    CHECK(sr.msbWithoutFreshLsb == 0);
    // Only controllers: SceneRotator stops reading a block at the first non-controller message.
    for (const MidiEvent& e : rig.midi) CHECK((e.bytes[0] & 0xF0) == 0xB0);
}

TEST_CASE("scenerotator-osc: /SceneRotator/ypr carries the same angles; /quaternions the rotation", "[mapping][presets]")
{
    Rig rig(loadMapping("scenerotator-osc"));
    const double e = 25.0, a = 310.0, r = -40.0;
    rig.pose(e, a, r, 0.0);
    REQUIRE(rig.osc.size() == 2);
    int seen = 0;
    for (const auto& p : rig.osc) {
        REQUIRE(osc::decodeOscPacket(p.data(), p.size(), [&](const osc::OscMessage& m) {
            if (m.address == "/SceneRotator/ypr") {
                REQUIRE(m.types == "fff");
                CHECK(m.args[0].f == Approx(-std::remainder(a, 360.0)).margin(1e-4));
                CHECK(m.args[1].f == Approx(e).margin(1e-4));
                CHECK(m.args[2].f == Approx(r).margin(1e-4));
                ++seen;
            } else if (m.address == "/SceneRotator/quaternions") {
                REQUIRE(m.types == "ffff");
                // SceneRotator's own yaw/pitch/roll → quaternion for its default sequence
                // (roll → pitch → yaw, updateQuaternions()): half-angle products.
                const double ya = degToRad(-std::remainder(a, 360.0)) / 2, pb = degToRad(e) / 2, rc = degToRad(r) / 2;
                const double wa = std::cos(ya), za = std::sin(ya), wb = std::cos(pb), yb = std::sin(pb), wc = std::cos(rc), xc = std::sin(rc);
                CHECK(m.args[0].f == Approx(wa * wc * wb + za * xc * yb).margin(1e-5));
                CHECK(m.args[1].f == Approx(wa * xc * wb - za * wc * yb).margin(1e-5));
                CHECK(m.args[2].f == Approx(wa * wc * yb + za * xc * wb).margin(1e-5));
                CHECK(m.args[3].f == Approx(za * wc * wb - wa * xc * yb).margin(1e-5));
                ++seen;
            }
        }));
    }
    CHECK(seen == 2);
    // Still arm: nothing more.
    rig.osc.clear();
    rig.pose(e, a, r, 0.005);
    CHECK(rig.osc.empty());
}

TEST_CASE("classic: today's plugin wiring, CC 16/17/18 and the four gesture notes on channel 1", "[mapping][presets]")
{
    Rig rig(loadMapping("classic"));
    rig.pose(30.0, 90.0, -45.0, 0.0);
    CcState cc;
    for (const MidiEvent& e : rig.midi) cc.apply(e);
    // docs/PLUGIN.md: CC 16 0 = −90°, 127 = +90°; CC 17 0 = 0°, 127 = 360°; CC 18 0 = −180°, 127 = +180°.
    CHECK(cc.get(1, 16) == std::lround((30.0 + 90.0) / 180.0 * 127.0));
    CHECK(cc.get(1, 17) == std::lround(90.0 / 360.0 * 127.0));
    CHECK(cc.get(1, 18) == std::lround((-45.0 + 180.0) / 360.0 * 127.0));
    const struct { const char* name; int note; float value; } gestures[] {
        {"roll", 60, 1.0f}, {"punch", 62, 0.25f}, {"strike", 64, 300.0f}, {"fret", 67, 2.0f}, {"select", 67, -1.0f}};
    double t = 1.0;
    for (const auto& g : gestures) {
        rig.midi.clear();
        rig.gesture(g.name, g.value, t, armAt(30.0, 90.0, -45.0));
        REQUIRE(rig.midi.size() == 1);
        CHECK(rig.midi[0].bytes[0] == 0x90);
        CHECK(rig.midi[0].bytes[1] == g.note);
        // velocity = |value| × 127, at least 1 (and at most 127)
        CHECK(rig.midi[0].bytes[2] == std::clamp<long>(std::lround(std::fabs(g.value) * 127.0f), 1, 127));
        rig.pose(30.0, 90.0, -45.0, t + 0.049);
        CHECK(rig.midi.size() == 1);
        rig.pose(30.0, 90.0, -45.0, t + 0.051);
        REQUIRE(rig.midi.size() == 2);   // 50 ms long
        CHECK(rig.midi[1].bytes[0] == 0x80);
        CHECK(rig.midi[1].t == Approx(t + 0.05));
        t += 1.0;
    }
}

TEST_CASE("mpe preset: compass zones play notes on member channels", "[mapping][presets]")
{
    Rig rig(loadMapping("mpe"));
    rig.pose(10.0, 100.0, 0.0, 0.0);
    REQUIRE(!rig.midi.empty());
    CHECK((rig.midi.back().bytes[0] & 0xF0) == 0x90);
    CHECK((rig.midi.back().bytes[0] & 0x0F) >= 1);   // a member channel, not the master
    CHECK(rig.midi.back().bytes[1] == 64);           // 90…135° → E4
}
