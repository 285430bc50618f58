// The pattern library (thesis §3.2.6, §3.3.2): every pattern's motor sets and timing.
#include "Tactile/Patterns.h"
#include "Tactile/TactileEngine.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::tactile;

namespace {
const PatternParams P = kDefaultPatternParams;

PatternRequest req(PatternKind kind, std::uint16_t mask = motors::kGrid, float level = 10.0f, double duration = 0.0,
                   double rate = 0.0)
{
    PatternRequest r;
    r.kind = kind;
    r.motors = mask;
    r.level = level;
    r.duration = duration;
    r.rate = rate;
    return r;
}

PatternSample at(const PatternRequest& r, double t, std::uint64_t seed = 1) { return evaluatePattern(r, P, t, seed); }

std::uint16_t set(std::initializer_list<int> indices)
{
    std::uint16_t m = 0;
    for (int i : indices) m = static_cast<std::uint16_t>(m | (1u << i));
    return m;
}
} // namespace

TEST_CASE("Patterns: names round-trip and are stable", "[patterns]")
{
    for (int k = 0; k < kPatternKinds; ++k) {
        const auto kind = static_cast<PatternKind>(k);
        CHECK(patternKindFromName(patternName(kind)) == kind);
    }
    CHECK(patternName(PatternKind::BrokenGlass) == "broken-glass");
    CHECK(patternName(PatternKind::GearPull) == "gear-pull");
    CHECK_FALSE(patternKindFromName("glass").has_value());
}

TEST_CASE("Patterns: anchors are the bone motors", "[patterns]")
{
    CHECK(motors::kWristAnchors == set({0, 2}));
    CHECK(motors::kBoneAnchors == set({0, 3, 6, 2, 5, 8}));
    CHECK(motors::kWristRow == set({0, 1, 2}));
    CHECK(motors::kElbowRow == set({6, 7, 8}));
    CHECK(motors::kUndersideColumn == set({1, 4, 7}));
}

TEST_CASE("Patterns: point, jolt and accent hold their motors for their length", "[patterns]")
{
    struct Case {
        PatternKind kind;
        double length;
    };
    for (const Case c : {Case {PatternKind::Point, P.pointTime}, Case {PatternKind::Jolt, P.joltTime},
                         Case {PatternKind::Accent, P.accentTime}}) {
        const auto r = req(c.kind, motors::kWristAnchors, 7.0f);
        CHECK(patternLength(r, P) == c.length);
        const auto s = at(r, 0.5 * c.length);
        CHECK(s.active == motors::kWristAnchors);
        CHECK(s.level[0] == 7.0f);
        CHECK(s.level[2] == 7.0f);
        CHECK(s.level[1] == 0.0f);
        CHECK(s.smooth == 0);
        CHECK(at(r, c.length).active == 0);
        CHECK(at(r, c.length - 1e-6).active == motors::kWristAnchors);
    }
    // An explicit duration wins; a negative one runs until stopped.
    CHECK(patternLength(req(PatternKind::Point, 1, 5, 1.5), P) == 1.5);
    CHECK(std::isinf(patternLength(req(PatternKind::Point, 1, 5, -1.0), P)));
}

TEST_CASE("Patterns: pulse and fade pulses have their shapes", "[patterns]")
{
    const auto pulse = req(PatternKind::Pulse, set({4}), 12.0f);
    CHECK(at(pulse, P.pulseAttack).level[4] == Approx(12.0f));
    CHECK(at(pulse, 0.5 * P.pulseAttack).level[4] == Approx(6.0f));
    CHECK(at(pulse, 0.08).level[4] < at(pulse, 0.04).level[4]);
    CHECK(at(pulse, P.pulseTime).active == 0);

    const auto in = req(PatternKind::FadeInPulse, set({1, 4}), 9.0f);
    CHECK(at(in, 0.1).level[1] == Approx(3.0f));
    CHECK(at(in, 0.2).level[4] == Approx(6.0f));
    CHECK(at(in, 0.1).smooth == set({1, 4}));   // a fade: no jump-start
    CHECK(at(in, P.fadeTime).active == 0);      // then cut

    const auto out = req(PatternKind::FadeOutPulse, set({7}), 9.0f);
    CHECK(at(out, 0.0).level[7] == Approx(9.0f));
    CHECK(at(out, 0.2).level[7] == Approx(3.0f));
    CHECK(at(out, 0.0).smooth == set({7}));   // a fade too: it cuts in at its level, no jump-start
}

TEST_CASE("Patterns: breathing moves every motor together at its rate", "[patterns]")
{
    const auto r = req(PatternKind::Breathing, motors::kGrid, 6.0f, 0.0, 0.25);
    CHECK(std::isinf(patternLength(r, P)));
    CHECK(at(r, 0.0).active == 0);                         // the bottom of a breath (floor 0)
    const auto top = at(r, 2.0);                           // half of a 4 s breath
    CHECK(top.active == motors::kGrid);
    for (int m = 0; m < 9; ++m) CHECK(top.level[static_cast<std::size_t>(m)] == Approx(6.0f));
    CHECK(at(r, 1.0).level[3] == Approx(3.0f));
    CHECK(at(r, 5.0).level[8] == Approx(at(r, 1.0).level[8]));   // periodic
    CHECK(top.smooth == motors::kGrid);
}

TEST_CASE("Patterns: tickle touches one random motor of the set at a time", "[patterns]")
{
    const auto r = req(PatternKind::Tickle, motors::kGrid, 10.0f);
    std::set<int> touched;
    std::vector<int> sequence;
    for (double t = 0.0; t < 4.0; t += 0.001) {
        const auto s = at(r, t, 42);
        if (s.active == 0) continue;
        CHECK((s.active & (s.active - 1)) == 0);   // one motor
        CHECK((s.active & ~motors::kGrid) == 0);
        for (int m = 0; m < 16; ++m)
            if (s.active & (1u << m)) {
                touched.insert(m);
                CHECK(s.level[static_cast<std::size_t>(m)] == Approx(10.0f * P.tickleScale));
                if (sequence.empty() || sequence.back() != m) sequence.push_back(m);
            }
    }
    CHECK(touched.size() == 9);
    // Touches last tickleTouch of every tickleStep.
    CHECK(at(r, 0.010, 42).active != 0);
    CHECK(at(r, P.tickleTouch + 0.005, 42).active == 0);
    // The same seed gives the same touches; another seed others.
    int differ = 0;
    for (int k = 0; k < 50; ++k) {
        const double t = k * P.tickleStep + 0.001;
        CHECK(at(r, t, 42).active == at(r, t, 42).active);
        differ += at(r, t, 42).active != at(r, t, 43).active;
    }
    CHECK(differ > 10);
}

TEST_CASE("Patterns: massage swells travel around the arm, overlapping", "[patterns]")
{
    const auto r = req(PatternKind::Massage, motors::kGrid, 8.0f, 0.0, 0.5);
    // Ring order: 0 1 2 5 8 7 6 3, then the centre 4; 9 motors per 2 s trip.
    const int ring[] = {0, 1, 2, 5, 8, 7, 6, 3, 4};
    for (int i = 0; i < 9; ++i) {
        const auto s = at(r, i * 2.0 / 9.0);
        CHECK(s.level[static_cast<std::size_t>(ring[i])] == Approx(8.0f));
        int count = 0;
        for (int m = 0; m < 9; ++m) count += (s.active >> m) & 1;
        CHECK(count == 3);   // the peak and its two neighbours, fading
        CHECK(s.level[static_cast<std::size_t>(ring[(i + 1) % 9])] == Approx(2.0f).margin(1e-4));
    }
}

TEST_CASE("Patterns: twist fades helical stripes into each other around the arm", "[patterns]")
{
    const auto r = req(PatternKind::Twist, motors::kGrid, 6.0f, 0.0, 1.0);
    CHECK(at(r, 0.0).active == set({0, 4, 8}));
    CHECK(at(r, 1.0).active == set({1, 5, 6}));
    CHECK(at(r, 2.0).active == set({2, 3, 7}));
    CHECK(at(r, 3.0).active == set({0, 4, 8}));
    const auto half = at(r, 0.5);
    CHECK(half.active == (set({0, 4, 8}) | set({1, 5, 6})));
    CHECK(half.level[0] == Approx(half.level[1]));
    CHECK(at(r, 0.25).level[0] > at(r, 0.25).level[1]);
    CHECK(half.smooth == half.active);
}

TEST_CASE("Patterns: broken glass runs elbow → wrist, mirrored, the arrival longer and stronger", "[patterns]")
{
    const auto r = req(PatternKind::BrokenGlass, motors::kGrid, 6.0f);
    const double e = P.glassEvent, arrival = P.glassEvent * P.glassArrivalStretch;
    const double cycle = brokenGlassCycle(P);
    CHECK(cycle == Approx(2.0 * (4.0 * e + arrival)));
    const auto single = [&](double t) {
        const auto s = at(r, t);
        REQUIRE((s.active & (s.active - 1)) == 0);
        for (int m = 0; m < 16; ++m)
            if (s.active & (1u << m)) return m;
        return -1;
    };
    const int shown[] = {8, 7, 4, 3, 0}, mirrored[] = {6, 7, 4, 5, 2};
    for (int k = 0; k < 5; ++k) {
        CHECK(single(k * e + 0.01) == shown[k]);
        CHECK(single(0.5 * cycle + k * e + 0.01) == mirrored[k]);
    }
    // The arrival (wrist) lasts longer and is stronger.
    CHECK(single(4 * e + arrival - 0.01) == 0);
    CHECK(at(r, 4 * e + 0.01).level[0] == Approx(6.0f + P.glassArrivalBoost));
    CHECK(at(r, 0.01).level[8] == Approx(6.0f));
    CHECK(single(0.5 * cycle + 0.01) == 6);
    // It repeats.
    CHECK(single(cycle + 0.01) == 8);
    // First event starts at the elbow row, the last arrives at the wrist row.
    CHECK((motors::kElbowRow >> shown[0]) & 1);
    CHECK((motors::kWristRow >> shown[4]) & 1);
}

TEST_CASE("Patterns: gear pull alternates outer rows and the middle row", "[patterns]")
{
    const auto r = req(PatternKind::GearPull, motors::kGrid, 8.0f, 0.0, 4.0);   // 4 steps/s
    CHECK(at(r, 0.05).active == (motors::kWristRow | motors::kElbowRow));
    CHECK(at(r, 0.30).active == motors::kMiddleRow);
    CHECK(at(r, 0.55).active == (motors::kWristRow | motors::kElbowRow));
    CHECK(at(r, 0.25 * P.gearDuty + 0.01).active == 0);   // the off part of a step
    // Only the requested motors.
    CHECK(at(req(PatternKind::GearPull, motors::kUndersideColumn, 8, 0, 4), 0.3).active == set({4}));
}

TEST_CASE("Patterns: geiger clicks at its rate", "[patterns]")
{
    for (double rate : {2.0, 4.0, 10.0}) {
        const auto r = req(PatternKind::Geiger, set({3}), 9.0f, 0.0, rate);
        int clicks = 0;
        bool was = false;
        double onTime = 0.0;
        for (double t = 0.0; t < 3.0 - 1e-9; t += 0.0005) {
            const bool on = at(r, t).active != 0;
            clicks += on && !was;
            onTime += on ? 0.0005 : 0.0;
            was = on;
        }
        INFO("rate " << rate);
        CHECK(clicks == static_cast<int>(3.0 * rate));
        CHECK(onTime == Approx(3.0 * rate * P.geigerClick).margin(0.002 * rate * 3));
    }
}

TEST_CASE("Patterns through the engine: a re-triggered texture keeps its phase", "[patterns]")
{
    TactileEngine e;
    e.prepare(TactileConfig {});
    PatternRequest r = req(PatternKind::Geiger, set({4}), 9.0f, 0.0, 4.0);
    r.voice = 2;
    int clicks = 0;
    bool was = false;
    for (int i = 0; i < 600; ++i) {   // 3 s at 200 Hz, the request repeated every step (a compass)
        e.trigger(r);
        const bool on = e.tick(0.005)[4] > 0;
        clicks += on && !was;
        was = on;
    }
    CHECK(clicks == 12);
    // Another kind in the same voice replaces it; stopVoice ends it.
    e.trigger(req(PatternKind::Breathing));
    CHECK(e.voiceActive(0));
    e.stopVoice(0);
    CHECK_FALSE(e.voiceActive(0));
}

TEST_CASE("Patterns: any request, however odd, gives levels within 0..15 on the requested motors", "[patterns][fuzz]")
{
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double odd[] = {0.0, -1.0, 1e-9, 1e9, std::nan(""), std::numeric_limits<double>::infinity(), -0.0};
    for (int i = 0; i < 20000; ++i) {
        PatternRequest r;
        r.kind = static_cast<PatternKind>(rng() % kPatternKinds);
        r.motors = static_cast<std::uint16_t>(rng());
        r.level = unit(rng) < 0.2 ? static_cast<float>(odd[rng() % std::size(odd)]) : static_cast<float>(unit(rng) * 20.0 - 2.0);
        r.duration = unit(rng) < 0.3 ? odd[rng() % std::size(odd)] : unit(rng) * 5.0;
        r.rate = unit(rng) < 0.3 ? odd[rng() % std::size(odd)] : unit(rng) * 50.0;
        const double t = unit(rng) < 0.1 ? odd[rng() % std::size(odd)] : unit(rng) * 100.0;
        const PatternSample s = evaluatePattern(r, kDefaultPatternParams, t, rng());
        CHECK((s.active & ~r.motors) == 0);
        CHECK((s.smooth & ~s.active) == 0);
        for (int m = 0; m < kMaxMotors; ++m) {
            const float l = s.level[static_cast<std::size_t>(m)];
            CHECK((l >= 0.0f && l <= 15.0f));
            CHECK((l > 0.0f) == (((s.active >> m) & 1) != 0));
        }
    }
}
