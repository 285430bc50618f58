// Scores that follow the recording (docs/TACTILE.md, "Following the recording"), measured on the
// tactile rows the engine puts out while a synthesised performance comes in through the audio
// input — the same path as `armadillo render --audio-in`.
#define ARMADILLO_REALTIME_GUARD_IMPLEMENTATION
#include "Common/RealtimeGuard.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Engine/Engine.h"
#include "Engine/RenderSettings.h"
#include "Live/Session/RowClock.h"
#include "Performance.h"
#include "Tactile/Bounds.h"
#include "Tactile/ScoreFollower.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <random>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;
using armadillo::live::renderOffline;
using namespace armadillo::tactile;
using namespace armadillo::test;

namespace {
const std::string kResources = ARMADILLO_SOURCE_DIR "/Resources";

Score riteScore() { return loadScore(kResources + "/Scores/rite-of-spring.score"); }

std::vector<int> followedOf(const Score& s)
{
    std::vector<int> f;
    for (std::size_t i = 0; i < s.notes.size(); ++i)
        if (s.notes[i].part >= 0 && s.parts[static_cast<std::size_t>(s.notes[i].part)].followNotes) f.push_back(static_cast<int>(i));
    return f;
}

/// A still arm for `seconds` at 200 Hz (the control updates of a render).
CsvTable stillMotion(double seconds)
{
    std::string s = "t,elevation,azimuth,roll\n";
    for (int i = 0; i <= static_cast<int>(seconds * 200.0); ++i) s += std::to_string(i / 200.0) + ",0,0,0\n";
    return CsvTable::parse(s, "still.csv");
}

std::vector<TactileRow> renderFollowing(const Performance& perf, const std::string& score = "rite-of-spring")
{
    RenderSettings settings;
    settings.engine.scene = "score";
    settings.engine.sceneConfig.score = score;
    settings.engine.sceneConfig.resourceDir = kResources;
    settings.engine.sceneConfig.sampleRate = perf.audio.sampleRate;
    settings.audioIn = &perf.audio;
    const double seconds = static_cast<double>(perf.audio.frames()) / perf.audio.sampleRate;
    return renderOffline(stillMotion(seconds), settings).tactile;
}

int motorOf(const Score& s, int note)
{
    const auto mask = s.notes[static_cast<std::size_t>(note)].motors;
    for (int m = 0; m < kMaxMotors; ++m)
        if (mask & (1u << m)) return m;
    return -1;
}

struct OnsetErrors {
    std::vector<double> errors;   ///< s, motor onset − audio onset, per note (NaN: not found)
    double maxAbs = 0.0, meanAbs = 0.0;
    int missing = 0;
};

/// For every played note: the first row within [onset − 0.15 s, onset + 0.3 s] in which its motor
/// turns on (off in the row before).
OnsetErrors onsetErrors(const Score& s, const Performance& perf, const std::vector<TactileRow>& rows)
{
    OnsetErrors e;
    for (const PlayedNote& n : perf.notes) {
        const int m = motorOf(s, n.scoreNote);
        const double found = motorOnsetNear(rows, m, n.onset);
        e.errors.push_back(found);
        if (std::isnan(found)) {
            ++e.missing;
            continue;
        }
        e.maxAbs = std::max(e.maxAbs, std::fabs(found));
        e.meanAbs += std::fabs(found);
    }
    e.meanAbs /= std::max<std::size_t>(1, perf.notes.size() - static_cast<std::size_t>(e.missing));
    return e;
}

/// Pearson correlation of the opening note's motor level with the synthesised envelope, both
/// averaged over 50 ms (the motor is an integer-level, dithered device), from the motor's onset
/// to the next note.
double crescendoCorrelation(const Score& s, const Performance& perf, const std::vector<TactileRow>& rows)
{
    const int m = motorOf(s, perf.notes[0].scoreNote);
    const double from = perf.notes[0].onset + 0.06, to = perf.notes[1].onset;
    std::vector<double> a, b;
    for (double t = from; t + 0.05 <= to; t += 0.05) {
        double level = 0.0, env = 0.0;
        int n = 0;
        for (const auto& r : rows)
            if (r.t >= t && r.t < t + 0.05) {
                level += r.levels[static_cast<std::size_t>(m)];
                env += perf.envelopeAt(r.t);
                ++n;
            }
        if (n == 0) continue;
        a.push_back(level / n);
        b.push_back(env / n);
    }
    const double n = static_cast<double>(a.size());
    double ma = 0.0, mb = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        ma += a[i] / n;
        mb += b[i] / n;
    }
    double sab = 0.0, saa = 0.0, sbb = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        sab += (a[i] - ma) * (b[i] - mb);
        saa += (a[i] - ma) * (a[i] - ma);
        sbb += (b[i] - mb) * (b[i] - mb);
    }
    return saa > 0.0 && sbb > 0.0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

BoundsReport boundsOf(const std::vector<TactileRow>& rows)
{
    std::vector<MotorLevels> packets;
    std::vector<double> hold;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        packets.push_back(rows[i].levels);
        hold.push_back(i + 1 < rows.size() ? rows[i + 1].t - rows[i].t : 0.005);
    }
    return measureBounds(packets, hold);
}

/// Only one motor at a time, apart from handovers of one row.
int rowsWithTwoMotors(const std::vector<TactileRow>& rows)
{
    int n = 0;
    for (const auto& r : rows) {
        int on = 0;
        for (int m = 0; m < kGridMotors; ++m) on += r.levels[static_cast<std::size_t>(m)] > 0;
        n += on > 1;
    }
    return n;
}
} // namespace

TEST_CASE("follow: the Rite's solo with rubato, a longer fermata and a later start; every motor within 60 ms", "[follow][rite]")
{
    const Score score = riteScore();
    const std::vector<int> followed = followedOf(score);
    REQUIRE(followed.size() == 25);
    for (const double snr : {1000.0, 20.0}) {
        for (const double swing : {0.2, -0.2}) {
            PerformanceStyle style;
            style.snrDb = snr;
            style.tempoSwing = swing;
            style.start = swing > 0 ? 1.37 : 0.41;
            style.firstNoteSeconds = swing > 0 ? 6.9 : 3.6;   // the score's fermata is 4.8 s
            const Performance perf = perform(score, followed, style);
            const auto rows = renderFollowing(perf);
            const OnsetErrors e = onsetErrors(score, perf, rows);
            const double r = crescendoCorrelation(score, perf, rows);
            const BoundsReport bounds = boundsOf(rows);
            std::printf("follow rite: snr %s, tempo swing %+.0f%%, start %.2f s, fermata %.1f s: onset error max %.1f ms, mean %.1f ms, "
                        "missing %d of %zu; crescendo correlation %.3f\n",
                        snr > 200 ? "clean" : "20 dB", 100 * swing, style.start, style.firstNoteSeconds, 1e3 * e.maxAbs, 1e3 * e.meanAbs,
                        e.missing, perf.notes.size(), r);
            CAPTURE(snr, swing);
            for (std::size_t k = 0; k < e.errors.size(); ++k) {
                CAPTURE(k, perf.notes[k].onset, e.errors[k]);
                CHECK_FALSE(std::isnan(e.errors[k]));
                if (!std::isnan(e.errors[k])) CHECK(std::fabs(e.errors[k]) <= 0.060);
            }
            CHECK(r >= 0.9);
            CHECK(withinBounds(bounds));
            CHECK(rowsWithTwoMotors(rows) < 30);
            // Nothing before the recording's first sound: the score waits for the music.
            for (const auto& row : rows) {
                if (row.t >= perf.notes[0].onset - 0.01) break;
                for (int m = 0; m < kGridMotors; ++m) REQUIRE(row.levels[static_cast<std::size_t>(m)] == 0);
            }
            // The opening crescendo is a soft intent: never the jump-start spike.
            const int opening = motorOf(score, perf.notes[0].scoreNote);
            for (const auto& row : rows)
                if (row.t >= perf.notes[0].onset - 0.2 && row.t < perf.notes[1].onset) REQUIRE(row.levels[static_cast<std::size_t>(opening)] < 15);
        }
    }
}

TEST_CASE("follow: the clock places the score when no audio comes in", "[follow]")
{
    RenderSettings settings;
    settings.engine.scene = "score";
    settings.engine.sceneConfig.score = "rite-of-spring";
    settings.engine.sceneConfig.resourceDir = kResources;
    const auto rows = renderOffline(stillMotion(6.0), settings).tactile;
    // Without audio the first note starts at 0 s on its motor (the tempo map's time).
    const Score score = riteScore();
    const int m = motorOf(score, 0);
    int firstOn = -1;
    for (std::size_t i = 0; i < rows.size(); ++i)
        if (rows[i].levels[static_cast<std::size_t>(m)] > 0) {
            firstOn = static_cast<int>(i);
            break;
        }
    CHECK(firstOn >= 0);
    CHECK(firstOn <= 2);
}

TEST_CASE("follow: a scene that does not listen refuses audio input; a wrong sample rate is refused", "[follow]")
{
    PerformanceStyle style;
    const Score score = riteScore();
    const Performance perf = perform(score, followedOf(score), style);
    RenderSettings settings;
    settings.engine.scene = "theremin";
    settings.audioIn = &perf.audio;
    CHECK_THROWS_AS(renderOffline(stillMotion(1.0), settings), InputError);
    settings.engine.scene = "score";
    settings.engine.sceneConfig.score = "rite-of-spring";
    settings.engine.sceneConfig.resourceDir = kResources;
    settings.engine.sceneConfig.sampleRate = 44100.0;
    CHECK_THROWS_AS(renderOffline(stillMotion(1.0), settings), InputError);
}

TEST_CASE("follow: the follower allocates, locks and throws nothing on the audio thread", "[follow][realtime]")
{
    ARMADILLO_REQUIRE_GUARD();
    const Score score = riteScore();
    PerformanceStyle style;
    style.snrDb = 20.0;
    const Performance perf = perform(score, followedOf(score), style);
    for (const int block : {1, 64, 256, 512, 1024}) {
        CAPTURE(block);
        ScoreFollower f;
        f.prepare(score, perf.audio.sampleRate);
        EngineConfig config;
        config.scene = "score";
        config.sceneConfig.score = "rite-of-spring";
        config.sceneConfig.resourceDir = kResources;
        Engine engine(config);
        std::vector<float> l(static_cast<std::size_t>(block)), r(static_cast<std::size_t>(block));
        const std::size_t frames = std::min<std::size_t>(perf.audio.frames(), 48000 * 10);
        const std::vector<float> silence(static_cast<std::size_t>(block), 0.0f);
        RealtimeGuard guard;
        for (std::size_t at = 0; at + static_cast<std::size_t>(block) <= frames; at += static_cast<std::size_t>(block)) {
            const float* in[2] = {perf.audio.channels[0].data() + at, perf.audio.channels[1].data() + at};
            f.process(in, 2, block);
            engine.processInput(in, 2, block);
            engine.renderAudio(l.data(), r.data(), block);
            ArmState arm;
            arm.valid = true;
            if ((at / static_cast<std::size_t>(block)) % std::max<std::size_t>(1, 240 / static_cast<std::size_t>(block)) == 0)
                (void) engine.control(arm, Transport {}, 0.005);
            (void) f.state();
        }
        const FollowState heard = f.state();
        f.requestReset();
        const float* in[1] = {silence.data()};
        f.process(in, 1, block);
        CHECK(guard.allocations() == 0);
        CHECK(guard.deallocations() == 0);
        CHECK(guard.locks() == 0);
        CHECK(guard.throws() == 0);
        CHECK(heard.heard);   // it did follow: the first notes were found
        CHECK(heard.note >= 3);
        CHECK_FALSE(f.state().heard);   // and the reset took it back to before the first note
    }
}

TEST_CASE("follow: garbage input (NaN, infinities, full-scale clicks, no channels) changes nothing dangerous", "[follow]")
{
    const Score score = riteScore();
    ScoreFollower f;
    f.prepare(score, 48000.0);
    std::vector<float> x(4800, 0.0f);
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = (i % 7 == 0) ? std::nanf("") : (i % 11 == 0 ? INFINITY : ((i % 2) ? 1.0f : -1.0f));
    const float* in[1] = {x.data()};
    f.process(in, 1, static_cast<int>(x.size()));
    f.process(nullptr, 1, 64);
    f.process(in, 0, 64);
    const float* nulls[2] = {x.data(), nullptr};
    f.process(nulls, 2, 64);
    const FollowState s = f.state();
    for (float e : s.envelope) CHECK(std::isfinite(e));
    CHECK(std::isfinite(s.sinceOnset));
    CHECK_THROWS_AS(ScoreFollower().prepare(score, 1000.0), InputError);
}

namespace {
/// A texture recording: wind (noise) from `start`, crackles (5 ms clicks, 4 a second) from
/// `crackleAt`, both in s of the recording.
AudioBuffer windAndGlass(double start, double crackleAt, double total)
{
    AudioBuffer a;
    a.sampleRate = 48000.0;
    const auto frames = static_cast<std::size_t>(total * a.sampleRate);
    a.channels.assign(1, std::vector<float>(frames, 0.0f));
    std::mt19937_64 rng(5);
    std::normal_distribution<float> noise(0.0f, 0.03f);
    for (std::size_t i = static_cast<std::size_t>(start * a.sampleRate); i < frames; ++i) {
        const double t = static_cast<double>(i) / a.sampleRate;
        float x = noise(rng);
        if (t >= crackleAt && std::fmod(t - crackleAt, 0.25) < 0.005) x += (i % 2 ? 0.5f : -0.5f);
        a.channels[0][i] = x;
    }
    return a;
}

/// First row at or after `from` with exactly one grid motor on (a broken-glass event).
double firstSingleMotor(const std::vector<TactileRow>& rows, double from)
{
    for (const auto& r : rows) {
        if (r.t < from) continue;
        int on = 0;
        for (int m = 0; m < kGridMotors; ++m) on += r.levels[static_cast<std::size_t>(m)] > 0;
        if (on == 1) return r.t;
    }
    return std::nan("");
}
} // namespace

TEST_CASE("follow: Polytope's glass section starts at the recording's crackles, early or late", "[follow][cues]")
{
    // The score says glass at 40 s; the recording starts 2 s in and its crackles come 2 s early
    // or 3 s late (inside the cue's 4 s window).
    for (const double lateness : {-2.0, 3.0}) {
        CAPTURE(lateness);
        const double start = 2.0, crackles = start + 40.0 + lateness;
        const AudioBuffer audio = windAndGlass(start, crackles, crackles + 3.0);
        RenderSettings settings;
        settings.engine.scene = "score";
        settings.engine.sceneConfig.score = "polytope";
        settings.engine.sceneConfig.resourceDir = kResources;
        settings.audioIn = &audio;
        const auto rows = renderOffline(stillMotion(crackles + 3.0), settings).tactile;
        const double glass = firstSingleMotor(rows, crackles - 1.0);
        std::printf("follow polytope: crackles %+.0f s from the score's time: glass starts %.1f ms after them\n", lateness,
                    1e3 * (glass - crackles));
        REQUIRE_FALSE(std::isnan(glass));
        CHECK(std::fabs(glass - crackles) <= 0.060);
        CHECK(withinBounds(boundsOf(rows)));
        // Nothing before the recording's first sound.
        for (const auto& row : rows)
            if (row.t < start - 0.01)
                for (int m = 0; m < kGridMotors; ++m) REQUIRE(row.levels[static_cast<std::size_t>(m)] == 0);
    }
}
