// Compass, control panel and gesture sound design through the Scene API (thesis §4.1, §3.4, §3.7).
#include "Instruments/Scenes.h"
#include "SceneHarness.h"
#include <catch2/catch.hpp>
#include <cmath>

using namespace armadillo;
using namespace armadillo::instruments;
using namespace armadillo::core;
using namespace armadillo::test;

namespace {
/// A quick roll: +60° about the forearm in 0.1 s (≈ 10 rad/s), then back slowly.
void quickRoll(SceneHarness& h)
{
    const Pose p = h.lastPose;
    h.move(p, {p.elevationDeg, p.azimuthDeg, p.rollDeg + 60.0}, 0.1);
    h.move({p.elevationDeg, p.azimuthDeg, p.rollDeg + 60.0}, p, 1.0);
}

double lastGeigerRate(const SceneHarness& h, int* motorMask = nullptr)
{
    const auto g = h.canvas.triggers(PatternKind::Geiger);
    if (g.empty()) return 0.0;
    if (motorMask) *motorMask = g.back().request.motors;
    return g.back().request.rate;
}
} // namespace

TEST_CASE("compass: the turn-side motor clicks faster nearer the target; on target both hold", "[compass]")
{
    auto scene = makeCompassScene();
    REQUIRE(scene);
    SceneHarness h(std::move(scene));
    h.set("compass.target", 90.0f);   // the thumb should point east
    // Right arm, palm down: the thumb points 90° left of the forearm. Forearm 220° → thumb 130°:
    // 40° too far clockwise → turn left (left column).
    h.hold({0.0, 220.0, 0.0}, 0.2);
    int mask = 0;
    const double rate40 = lastGeigerRate(h, &mask);
    CHECK(mask == (1 << motorIndex(1, 0)));
    // Forearm 140° → thumb 50°: turn right (right column).
    h.hold({0.0, 140.0, 0.0}, 0.2);
    CHECK(lastGeigerRate(h, &mask) == Approx(rate40));
    CHECK(mask == (1 << motorIndex(1, 2)));
    // Facing away (thumb 270°): slow clicks; closer (thumb 75°): fast.
    h.hold({0.0, 0.0, 0.0}, 0.2);
    const double rateFar = lastGeigerRate(h);
    h.hold({0.0, 165.0, 0.0}, 0.2);
    const double rateNear = lastGeigerRate(h);
    CHECK(rateFar < rate40);
    CHECK(rate40 < rateNear);
    // Facing away and wobbling across the far point: the side does not flip back and forth.
    h.hold({0.0, 0.0, 0.0}, 0.1);   // thumb 270°: error −180 → whichever side, then it stays
    int firstMask = 0;
    lastGeigerRate(h, &firstMask);
    for (int i = 0; i < 200; ++i) h.step({0.0, 3.0 * std::sin(i * 0.5), 0.0});
    int finalMask = 0;
    lastGeigerRate(h, &finalMask);
    CHECK(finalMask == firstMask);
    // Within ±5°: both side motors steady, no clicks, one onTarget event.
    const std::size_t clicks = h.canvas.triggers(PatternKind::Geiger).size();
    h.hold({0.0, 183.0, 0.0}, 0.3);
    CHECK(h.canvas.triggers(PatternKind::Geiger).size() == clicks);
    CHECK(h.canvas.levels[static_cast<std::size_t>(motorIndex(1, 0))] > 0.0f);
    CHECK(h.canvas.levels[static_cast<std::size_t>(motorIndex(1, 2))] > 0.0f);
    CHECK(h.events.count("onTarget") == 1);
    // Palm up reverses the thumb: forearm 0° then points the thumb east (after looking away).
    h.hold({0.0, 0.0, 0.0}, 0.2);
    CHECK(h.events.count("onTarget") == 1);
    h.hold({0.0, 2.0, 180.0}, 0.2);
    CHECK(h.events.count("onTarget") == 2);
}

TEST_CASE("panel: two levels with a hysteresis band, nine dial positions, roll selects", "[panel]")
{
    auto scene = makePanelScene();
    REQUIRE(scene);
    SceneHarness h(std::move(scene));
    // The panel's state as mapping sources (panel.knob, panel.level, panel.selected): none yet.
    CHECK(std::isnan(h.scene().values().panelKnob));
    CHECK(std::isnan(h.scene().values().panelSelected));
    h.hold({45.0, 100.0, 0.0}, 0.2);   // upper level, entry heading = the middle knob (5 on a keypad)
    auto pulses = [&](PatternKind k) { return h.canvas.triggers(k); };
    REQUIRE_FALSE(pulses(PatternKind::FadeInPulse).empty());
    CHECK(pulses(PatternKind::FadeInPulse).back().request.motors == (1 << 4));
    CHECK(h.scene().values().panelKnob == 4.0f);
    CHECK(h.scene().values().panelLevel == 1.0f);
    CHECK(std::isnan(h.scene().values().panelSelected));   // nothing selected before a roll
    // Dial two knobs left (15° each): knob 3 on the keypad → motor 2.
    h.move({45.0, 100.0, 0.0}, {45.0, 70.0, 0.0}, 0.5);
    CHECK(pulses(PatternKind::FadeInPulse).back().request.motors == (1 << 2));
    CHECK(h.scene().values().panelKnob == 2.0f);
    CHECK(h.events.count("select") == 0);   // dialling does not select
    REQUIRE(rms(h.audio.left, 0, h.audio.left.size()) == 0.0);
    quickRoll(h);
    REQUIRE(h.events.count("select") == 1);
    float selected = -1.0f;
    for (const auto& e : h.events.events)
        if (e.name == "select") selected = e.value;
    CHECK(selected == 2.0f);
    CHECK(h.scene().values().panelSelected == 2.0f);
    CHECK(rms(h.audio.left, 0, h.audio.left.size()) > 0.01);   // the knob's sample played
    // Into the band between ±30°: still upper, no jolt.
    h.move(h.lastPose, {0.0, 70.0, 0.0}, 0.5);
    CHECK(h.canvas.triggers(PatternKind::Jolt).empty());
    // Below −30°: lower level, a jolt, fading-out pulses; roll selects knob 2 + 9.
    h.move(h.lastPose, {-45.0, 70.0, 0.0}, 0.5);
    CHECK(h.canvas.triggers(PatternKind::Jolt).size() == 1);
    REQUIRE_FALSE(pulses(PatternKind::FadeOutPulse).empty());
    CHECK(pulses(PatternKind::FadeOutPulse).back().request.motors == (1 << 2));
    CHECK(h.scene().values().panelKnob == 11.0f);   // the lower level's knobs are 9..17
    CHECK(h.scene().values().panelLevel == 0.0f);
    CHECK(h.scene().values().panelSelected == 2.0f);   // the selection stays until the next roll
    // Back up to the band: stays lower.
    h.move(h.lastPose, {20.0, 70.0, 0.0}, 0.5);
    CHECK(h.canvas.triggers(PatternKind::Jolt).size() == 1);
    quickRoll(h);
    for (const auto& e : h.events.events)
        if (e.name == "select") selected = e.value;
    CHECK(selected == 11.0f);
    CHECK(h.scene().values().panelSelected == 11.0f);
    // Far right: clamps at the last knob.
    h.move(h.lastPose, {20.0, 170.0, 0.0}, 1.0);
    CHECK(pulses(PatternKind::FadeOutPulse).back().request.motors == (1 << 8));
}

TEST_CASE("sound design: elevation/azimuth move the sound, a roll selects, zooms in and jolts", "[sound-design]")
{
    auto scene = makeSoundDesignScene();
    REQUIRE(scene);
    SceneHarness h(std::move(scene));
    // Page 0: elevation → pitch (110·2^(3u)), azimuth → FM index (left edge: 0, a pure sine).
    auto pitchAt = [&](const Pose& p) {
        h.hold(p, 0.3);
        const std::size_t from = h.audio.left.size();
        h.hold(p, 0.5);
        return estimateFrequency(h.audio.left, from, h.audio.left.size(), h.audio.sampleRate);
    };
    h.hold({0.0, 0.0, 0.0}, 0.05);   // entry heading
    const double f0 = pitchAt({0.0, -60.0, 0.0});
    CHECK(std::fabs(cents(f0, 110.0 * std::exp2(1.5))) < 5.0);
    const double f30 = pitchAt({30.0, -60.0, 0.0});
    CHECK(std::fabs(cents(f30, 110.0 * std::exp2(2.25))) < 5.0);
    // Select: jolt + events; page 1 now: elevation moves harmonicity, not pitch.
    quickRoll(h);
    CHECK(h.events.count("select") == 1);
    CHECK(h.canvas.triggers(PatternKind::Jolt).size() == 1);
    // After the zoom the heading is re-centred at −60°; −120° is the new left edge (no vibrato).
    const double fAfter = pitchAt({-20.0, -120.0, 0.0});
    CHECK(std::fabs(cents(fAfter, f30)) < 5.0);
}
