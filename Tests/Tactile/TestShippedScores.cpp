// The two shipped scores, played through the Scene API and the TactileEngine as the engine does:
// Stravinsky is one bone-anchored motor at a time with its crescendo, Xenakis is texture; both
// keep every safety bound at any packet rate.
#include "Bounds.h"
#include "Core/Errors.h"
#include "Tactile/ScoreScene.h"
#include "Tactile/TactileEngine.h"
#include <catch2/catch.hpp>
#include <set>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::tactile;
using armadillo::test::measureBounds;
using armadillo::test::withinBounds;

namespace {

struct NullEvents final : EventSink {
    void emit(const char*, float) override {}
};

struct Played {
    std::vector<double> t;            ///< s: start of each packet
    std::vector<MotorLevels> levels;
    std::vector<double> hold;
    std::vector<std::uint16_t> active() const
    {
        std::vector<std::uint16_t> a;
        for (const auto& l : levels) {
            std::uint16_t m = 0;
            for (int i = 0; i < kMaxMotors; ++i)
                if (l[static_cast<std::size_t>(i)]) m = static_cast<std::uint16_t>(m | (1u << i));
            a.push_back(m);
        }
        return a;
    }
};

int bits(std::uint16_t m)
{
    int n = 0;
    for (; m; m = static_cast<std::uint16_t>(m & (m - 1))) ++n;
    return n;
}

Played play(const std::string& score, double dt, bool transport, std::string resources = ARMADILLO_SOURCE_DIR "/Resources",
            float intensityPercent = 100.0f)
{
    auto scene = makeScoreScene();
    REQUIRE(scene);
    CHECK(scene->name() == "score");
    SceneConfig config;
    config.score = score;
    config.resourceDir = std::move(resources);
    scene->prepare(config);
    scene->setParameter(0, intensityPercent);
    TactileEngine engine;
    engine.prepare(TactileConfig {});
    NullEvents events;
    SceneOutput out {engine, events};
    Played p;
    for (int i = 0; i * dt < 75.0; ++i) {
        ControlInput in;
        in.dt = i == 0 ? 0.0 : dt;
        in.transport.valid = transport;
        in.transport.playing = true;
        in.transport.seconds = i * dt;
        scene->control(in, out);
        p.levels.push_back(engine.tick(in.dt));
        p.t.push_back(i * dt);
        p.hold.push_back(dt);
    }
    return p;
}

double meanLevel(const Played& p, int motor, double from, double to)
{
    double sum = 0.0;
    int n = 0;
    for (std::size_t i = 0; i < p.t.size(); ++i)
        if (p.t[i] >= from && p.t[i] < to) {
            sum += p.levels[i][static_cast<std::size_t>(motor)];
            ++n;
        }
    return n ? sum / n : 0.0;
}

} // namespace

TEST_CASE("Rite of Spring: one bone-anchored motor at a time, the melody's line, the crescendo", "[scores]")
{
    for (double dt : {1.0 / 200.0, 1.0 / 285.0}) {
        const Played p = play("rite-of-spring", dt, true);
        const auto active = p.active();
        std::set<int> used;
        std::vector<int> sequence;   // motors in the order they sound
        for (std::uint16_t a : active) {
            CHECK(bits(a) <= 1);   // one motor at a time, always
            for (int m = 0; m < kMaxMotors; ++m)
                if (a & (1u << m)) {
                    used.insert(m);
                    if (sequence.empty() || sequence.back() != m) sequence.push_back(m);
                }
        }
        // Only the wrist row and the right (bone) column: the line hand → wrist → forearm bone.
        CHECK(used == std::set<int> {0, 1, 2, 5, 8});
        // Phrase 1: held C, the ornament C–B–C–B, G, E, B, A (wrist → down the bone).
        const std::vector<int> phrase1 {1, 2, 1, 2, 5, 8, 2, 5};
        REQUIRE(sequence.size() > phrase1.size());
        CHECK(std::vector<int>(sequence.begin(), sequence.begin() + 8) == phrase1);
        // The opening note grows: 0–4 beats at 50 bpm = 0–4.8 s.
        const double early = meanLevel(p, 1, 0.2, 1.6), middle = meanLevel(p, 1, 1.6, 3.2), late = meanLevel(p, 1, 3.2, 4.7);
        INFO("crescendo " << early << " " << middle << " " << late);
        CHECK(early < middle);
        CHECK(middle < late);
        CHECK(late >= 4.0);
        const auto report = measureBounds(p.levels, p.hold);
        CHECK(withinBounds(report));
        // The score ends: silence after 24 beats (28.8 s and a little for the tempo change).
        CHECK(meanLevel(p, 5, 30.0, 75.0) == 0.0);
    }
}

TEST_CASE("Polytope de Cluny: breathing and twisting textures, then broken glass growing to accents", "[scores]")
{
    for (double dt : {1.0 / 200.0, 1.0 / 285.0}) {
        const Played p = play("polytope", dt, true);
        const auto active = p.active();
        int maxTogether[4] = {0, 0, 0, 0};   // breathing, twist, glass, accents
        std::uint16_t twistCover = 0;
        std::vector<int> glass;              // motors of the broken glass, in order
        for (std::size_t i = 0; i < active.size(); ++i) {
            const double t = p.t[i];
            const int n = bits(active[i]);
            if (t > 2 && t < 20) maxTogether[0] = std::max(maxTogether[0], n);
            if (t > 31 && t < 39.9) {
                maxTogether[1] = std::max(maxTogether[1], n);
                twistCover = static_cast<std::uint16_t>(twistCover | active[i]);
            }
            if (t > 40 && t < 56.7) {
                maxTogether[2] = std::max(maxTogether[2], n);
                for (int m = 0; m < 9; ++m)
                    if ((active[i] & (1u << m)) && (glass.empty() || glass.back() != m)) glass.push_back(m);
            }
            if (t > 56.8 && t < 70) maxTogether[3] = std::max(maxTogether[3], n);
        }
        CHECK(maxTogether[0] == 9);          // every motor breathes together: texture
        CHECK(maxTogether[1] >= 4);          // two stripes crossfading
        CHECK(twistCover == motors::kGrid);  // the stripe turns all the way around
        CHECK(maxTogether[2] == 1);          // glass: single shards...
        CHECK(maxTogether[3] >= 3);          // ... until the accents hit the elbow row
        // Elbow → wrist, then mirrored, repeating.
        const std::vector<int> cycle {8, 7, 4, 3, 0, 6, 7, 4, 5, 2};
        REQUIRE(glass.size() >= 20);
        CHECK(std::vector<int>(glass.begin(), glass.begin() + 10) == cycle);
        CHECK(std::vector<int>(glass.begin() + 10, glass.begin() + 20) == cycle);
        // Intensifying: the wrist arrival is stronger at the end than at the start.
        CHECK(meanLevel(p, 0, 65.2, 70.0) > meanLevel(p, 0, 40.0, 48.0));
        const auto report = measureBounds(p.levels, p.hold);
        INFO("run " << report.maxAboveRun << " above " << report.maxAboveInWindow << " power " << report.maxMeanPower);
        CHECK(withinBounds(report));
        CHECK(meanLevel(p, 4, 71.0, 75.0) == 0.0);
    }
}

TEST_CASE("Score scene: own clock, resource fallback, intensity, bad names", "[scores]")
{
    // Without a transport the scene runs on its own clock, and an empty resourceDir falls back
    // to the usual search, which ends with the copy built into the core (Core/Resources.h).
    const Played own = play("rite-of-spring", 0.005, false, "");
    const Played host = play("rite-of-spring", 0.005, true);
    // The own clock sums dt, the host gives i·dt: they may part by a rounding error at a note
    // boundary, so allow a few packets out of 15000 to differ.
    REQUIRE(own.levels.size() == host.levels.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < own.levels.size(); ++i) differ += own.levels[i] != host.levels[i];
    CHECK(differ < own.levels.size() / 200);
    // Half intensity: the held note is weaker.
    const Played half = play("rite-of-spring", 0.005, true, ARMADILLO_SOURCE_DIR "/Resources", 50.0f);
    CHECK(meanLevel(half, 1, 3.2, 4.7) < meanLevel(host, 1, 3.2, 4.7) - 1.0);
    // A path works too.
    const Played path = play(ARMADILLO_SOURCE_DIR "/Resources/Scores/polytope.score", 0.005, true);
    CHECK(path.levels == play("polytope", 0.005, true).levels);

    auto scene = makeScoreScene();
    SceneConfig config;
    config.resourceDir = ARMADILLO_SOURCE_DIR "/Resources";
    config.score = "no-such-score";
    CHECK_THROWS_AS(scene->prepare(config), InputError);
    config.score = "";
    CHECK_THROWS_AS(scene->prepare(config), InputError);
    CHECK_FALSE(scene->producesAudio());
    REQUIRE(scene->parameters().size() == 3);
    CHECK(scene->parameters()[0].id == "score.intensity");
    CHECK(scene->parameters()[2].id == "score.listen");
}
