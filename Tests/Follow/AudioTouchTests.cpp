// The audio-to-touch scene: a drum-and-bass test signal through the engine's audio input, measured
// on the tactile rows (kick on the elbow row, bass on the middle row, hi-hat accents on the wrist
// row, kicks as accents too), inside the safety bounds, real-time on the audio thread.
#include "Common/RealtimeGuard.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Engine/Engine.h"
#include "Engine/RenderSettings.h"
#include "Live/Session/RowClock.h"
#include "Tactile/Bounds.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <random>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;
using armadillo::live::renderOffline;
using namespace armadillo::test;

namespace {
struct Groove {
    AudioBuffer audio;
    std::vector<double> kicks, hats;   ///< onsets, s
    double bassFrom = 1.0, bassTo = 3.0;
};

/// 4 s at 48 kHz: a kick every 0.5 s (80 → 45 Hz sweep, 120 ms decay), a hi-hat on every
/// off-beat (30 ms of high-passed noise), a bass line (C3, E3, G3, A3 sixteenths at 120 bpm,
/// a sawtooth low-passed at 400 Hz) only from 1 s to 3 s.
Groove groove()
{
    Groove g;
    const double fs = 48000.0, total = 4.0;
    const auto frames = static_cast<std::size_t>(total * fs);
    std::vector<double> x(frames, 0.0);
    for (double t0 = 0.05; t0 < total - 0.3; t0 += 0.5) {
        g.kicks.push_back(t0);
        double phase = 0.0;
        for (std::size_t i = static_cast<std::size_t>(t0 * fs); i < static_cast<std::size_t>((t0 + 0.4) * fs); ++i) {
            const double u = static_cast<double>(i) / fs - t0;
            const double f = 45.0 + 35.0 * std::exp(-u / 0.04);
            phase += 2.0 * 3.14159265358979 * f / fs;
            x[i] += 0.6 * std::min(1.0, u / 0.002) * std::exp(-u / 0.12) * std::sin(phase);
        }
    }
    std::mt19937_64 rng(3);
    std::normal_distribution<double> noise(0.0, 1.0);
    for (double t0 = 0.3; t0 < total - 0.1; t0 += 0.5) {
        g.hats.push_back(t0);
        double prev = 0.0;
        for (std::size_t i = static_cast<std::size_t>(t0 * fs); i < static_cast<std::size_t>((t0 + 0.03) * fs); ++i) {
            const double u = static_cast<double>(i) / fs - t0;
            const double n = noise(rng);
            x[i] += 0.25 * std::exp(-u / 0.01) * (n - prev);   // first difference: high-passed noise
            prev = n;
        }
    }
    static constexpr double kNotes[] = {130.81, 164.81, 196.0, 220.0};
    double phase = 0.0, lp = 0.0;
    const double a = 1.0 - std::exp(-2.0 * 3.14159265358979 * 400.0 / fs);
    for (std::size_t i = static_cast<std::size_t>(g.bassFrom * fs); i < static_cast<std::size_t>(g.bassTo * fs); ++i) {
        const double t = static_cast<double>(i) / fs;
        const double f = kNotes[static_cast<std::size_t>((t - g.bassFrom) / 0.25) % 4];
        phase += f / fs;
        phase -= std::floor(phase);
        lp += a * ((2.0 * phase - 1.0) - lp);
        const double edge = std::min({1.0, (t - g.bassFrom) / 0.01, (g.bassTo - t) / 0.01});
        x[i] += 0.35 * edge * lp;
    }
    g.audio.sampleRate = fs;
    g.audio.channels.assign(2, std::vector<float>(frames));
    for (std::size_t i = 0; i < frames; ++i) g.audio.channels[0][i] = g.audio.channels[1][i] = static_cast<float>(x[i]);
    return g;
}

CsvTable stillMotion(double seconds)
{
    std::string s = "t,elevation,azimuth,roll\n";
    for (int i = 0; i <= static_cast<int>(seconds * 200.0); ++i) s += std::to_string(i / 200.0) + ",0,0,0\n";
    return CsvTable::parse(s, "still.csv");
}

double rowMean(const std::vector<TactileRow>& rows, int row, double from, double to)
{
    double sum = 0.0;
    int n = 0;
    for (const auto& r : rows)
        if (r.t >= from && r.t < to) {
            for (int c = 0; c < 3; ++c) sum += r.levels[static_cast<std::size_t>(motorIndex(row, c))];
            n += 3;
        }
    return n ? sum / n : 0.0;
}

/// Times a row's level rises to an accent (above the rating) from at most the rating.
std::vector<double> accents(const std::vector<TactileRow>& rows, int row)
{
    std::vector<double> t;
    for (std::size_t i = 1; i < rows.size(); ++i) {
        const int now = rows[i].levels[static_cast<std::size_t>(motorIndex(row, 1))];
        const int before = rows[i - 1].levels[static_cast<std::size_t>(motorIndex(row, 1))];
        if (now > kRatedLevel && before <= kRatedLevel) t.push_back(rows[i].t);
    }
    return t;
}

/// For each expected onset, the delay to the nearest accent within [−10, +60] ms (NaN: none);
/// `extra` counts accents that belong to no onset.
std::vector<double> matchAccents(const std::vector<double>& onsets, const std::vector<double>& felt, int& extra)
{
    std::vector<double> d;
    std::vector<bool> used(felt.size(), false);
    for (double o : onsets) {
        double best = std::nan("");
        for (std::size_t k = 0; k < felt.size(); ++k)
            if (!used[k] && felt[k] >= o - 0.010 && felt[k] <= o + 0.060) {
                best = felt[k] - o;
                used[k] = true;
                break;
            }
        d.push_back(best);
    }
    extra = 0;
    for (bool u : used) extra += u ? 0 : 1;
    return d;
}
} // namespace

TEST_CASE("audio-touch: kick on the elbow row, bass on the middle row, hits as accents, inside the safety bounds", "[audio-touch]")
{
    const Groove g = groove();
    RenderSettings settings;
    settings.engine.scene = "audio-touch";
    settings.audioIn = &g.audio;
    const auto rows = renderOffline(stillMotion(4.0), settings).tactile;
    constexpr int kElbow = 2, kMiddle = 1, kWrist = 0;

    // Kick: the elbow row swells with each kick and falls between them.
    double during = 0.0, between = 0.0;
    for (double k : g.kicks) {
        during += rowMean(rows, kElbow, k + 0.03, k + 0.15) / static_cast<double>(g.kicks.size());
        between += rowMean(rows, kElbow, k + 0.40, k + 0.48) / static_cast<double>(g.kicks.size());
    }
    // Bass: the middle row is on while the bass line plays, (nearly) off without it.
    const double bassOn = rowMean(rows, kMiddle, g.bassFrom + 0.2, g.bassTo - 0.2);
    const double bassOff = 0.5 * (rowMean(rows, kMiddle, 0.1, g.bassFrom - 0.1) + rowMean(rows, kMiddle, g.bassTo + 0.2, 3.9));
    // Neither lands on the wrong row: no bass on the elbow row between kicks, no kick on the wrist row.
    const double wristDuringKicks = [&] {
        double s = 0.0;
        for (double k : g.kicks) s += rowMean(rows, kWrist, k + 0.03, k + 0.15) / static_cast<double>(g.kicks.size());
        return s;
    }();
    int extraHats = 0, extraKicks = 0;
    const auto hatDelays = matchAccents(g.hats, accents(rows, kWrist), extraHats);
    const auto kickDelays = matchAccents(g.kicks, accents(rows, kElbow), extraKicks);
    double worstHat = 0.0, worstKick = 0.0;
    int missedHats = 0, missedKicks = 0;
    for (double d : hatDelays) std::isnan(d) ? ++missedHats : (worstHat = std::max(worstHat, d), 0);
    for (double d : kickDelays) std::isnan(d) ? ++missedKicks : (worstKick = std::max(worstKick, d), 0);
    std::printf("audio-touch: elbow row %.2f during kicks vs %.2f between; middle row %.2f with bass vs %.2f without; wrist row %.2f during "
                "kicks; hi-hat accents %zu/%zu (worst delay %.0f ms, %d extra), kick accents %zu/%zu (worst %.0f ms, %d extra)\n",
                during, between, bassOn, bassOff, wristDuringKicks, hatDelays.size() - static_cast<std::size_t>(missedHats), hatDelays.size(),
                1e3 * worstHat, extraHats, kickDelays.size() - static_cast<std::size_t>(missedKicks), kickDelays.size(), 1e3 * worstKick, extraKicks);
    CHECK(during > 1.5);
    CHECK(during > 3.0 * between);
    CHECK(bassOn > 1.0);
    CHECK(bassOn > 4.0 * bassOff);
    CHECK(wristDuringKicks < 0.5);
    CHECK(missedHats == 0);
    CHECK(extraHats == 0);
    CHECK(missedKicks == 0);
    CHECK(extraKicks <= 1);
    // Safety: the whole render inside the bounds; sustained levels never above the rating.
    std::vector<MotorLevels> packets;
    std::vector<double> hold;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        packets.push_back(rows[i].levels);
        hold.push_back(i + 1 < rows.size() ? rows[i + 1].t - rows[i].t : 0.005);
    }
    CHECK(withinBounds(measureBounds(packets, hold)));
}

TEST_CASE("audio-touch: silence is felt as nothing; the parameters are the listener's few", "[audio-touch]")
{
    AudioBuffer silence;
    silence.sampleRate = 48000.0;
    silence.channels.assign(1, std::vector<float>(48000, 0.0f));
    RenderSettings settings;
    settings.engine.scene = "audio-touch";
    settings.audioIn = &silence;
    for (const auto& row : renderOffline(stillMotion(1.0), settings).tactile)
        for (int m = 0; m < kMaxMotors; ++m) REQUIRE(row.levels[static_cast<std::size_t>(m)] == 0);
    const auto specs = createScene("audio-touch")->parameters();
    REQUIRE(specs.size() == 4);
    CHECK(specs[0].id == "audio-touch.intensity");
    CHECK(specs[1].id == "audio-touch.sensitivity");
    CHECK(specs[2].id == "audio-touch.accents");
    CHECK(specs[3].id == "audio-touch.stems");   // appended in issue 27: the IDs before it keep their places
    CHECK(specs[3].choices == std::vector<std::string> {"apart", "mixed"});
    CHECK(specs[3].defaultValue == 0.0f);
    // Intensity 0: nothing sustained; accents 0: no accents.
    const Groove g = groove();
    settings.audioIn = &g.audio;
    settings.engine.parameters = {"audio-touch.intensity=0", "audio-touch.accents=0"};
    for (const auto& row : renderOffline(stillMotion(4.0), settings).tactile)
        for (int m = 0; m < kMaxMotors; ++m) REQUIRE(row.levels[static_cast<std::size_t>(m)] == 0);
}

TEST_CASE("audio-touch: the audio input allocates, locks and throws nothing", "[audio-touch][realtime]")
{
    ARMADILLO_REQUIRE_GUARD();
    const Groove g = groove();
    for (const int block : {1, 64, 512}) {
        EngineConfig config;
        config.scene = "audio-touch";
        Engine engine(config);
        std::vector<float> l(static_cast<std::size_t>(block)), r(static_cast<std::size_t>(block));
        RealtimeGuard guard;
        for (std::size_t at = 0; at + static_cast<std::size_t>(block) <= g.audio.frames(); at += static_cast<std::size_t>(block)) {
            const float* in[2] = {g.audio.channels[0].data() + at, g.audio.channels[1].data() + at};
            engine.processInput(in, 2, block);
            engine.renderAudio(l.data(), r.data(), block);
            ArmState arm;
            arm.valid = true;
            (void) engine.control(arm, Transport {}, static_cast<double>(block) / 48000.0);
        }
        CHECK(guard.allocations() == 0);
        CHECK(guard.deallocations() == 0);
        CHECK(guard.locks() == 0);
        CHECK(guard.throws() == 0);
    }
}

namespace {
struct Stems {
    AudioBuffer audio;              ///< channels: drums, bass, vocals
    std::vector<double> kicks;
};

/// 4 s at 48 kHz, three stems: drums (a kick every 0.5 s and off-beat hi-hats), bass (a low-passed
/// sawtooth, A1..E2, only from 1 s to 3 s, loud) and vocals (a sung A3..E4 with vibrato, harmonics
/// to 3 kHz, only from 2.2 s to 3.6 s, quiet).
Stems stems()
{
    Stems s;
    const double fs = 48000.0, total = 4.0;
    const auto frames = static_cast<std::size_t>(total * fs);
    s.audio.sampleRate = fs;
    s.audio.channels.assign(3, std::vector<float>(frames, 0.0f));
    auto& drums = s.audio.channels[0];
    auto& bass = s.audio.channels[1];
    auto& voice = s.audio.channels[2];
    for (double t0 = 0.05; t0 < total - 0.3; t0 += 0.5) {
        s.kicks.push_back(t0);
        double phase = 0.0;
        for (std::size_t i = static_cast<std::size_t>(t0 * fs); i < static_cast<std::size_t>((t0 + 0.4) * fs); ++i) {
            const double u = static_cast<double>(i) / fs - t0;
            phase += 2.0 * 3.14159265358979 * (45.0 + 35.0 * std::exp(-u / 0.04)) / fs;
            drums[i] += static_cast<float>(0.6 * std::min(1.0, u / 0.002) * std::exp(-u / 0.12) * std::sin(phase));
        }
    }
    std::mt19937_64 rng(9);
    std::normal_distribution<double> noise(0.0, 1.0);
    for (double t0 = 0.3; t0 < total - 0.1; t0 += 0.5) {
        double prev = 0.0;
        for (std::size_t i = static_cast<std::size_t>(t0 * fs); i < static_cast<std::size_t>((t0 + 0.03) * fs); ++i) {
            const double n = noise(rng);
            drums[i] += static_cast<float>(0.25 * std::exp(-(static_cast<double>(i) / fs - t0) / 0.01) * (n - prev));
            prev = n;
        }
    }
    double phase = 0.0, lp = 0.0;
    const double a = 1.0 - std::exp(-2.0 * 3.14159265358979 * 400.0 / fs);
    static constexpr double kBass[] = {55.0, 65.41, 73.42, 82.41};
    for (std::size_t i = static_cast<std::size_t>(1.0 * fs); i < static_cast<std::size_t>(3.0 * fs); ++i) {
        const double t = static_cast<double>(i) / fs;
        phase += kBass[static_cast<std::size_t>((t - 1.0) / 0.25) % 4] / fs;
        phase -= std::floor(phase);
        lp += a * ((2.0 * phase - 1.0) - lp);
        bass[i] = static_cast<float>(0.5 * std::min({1.0, (t - 1.0) / 0.01, (3.0 - t) / 0.01}) * lp);
    }
    double vp = 0.0;
    static constexpr double kSung[] = {220.0, 261.63, 329.63};
    for (std::size_t i = static_cast<std::size_t>(2.2 * fs); i < static_cast<std::size_t>(3.6 * fs); ++i) {
        const double t = static_cast<double>(i) / fs;
        const double f = kSung[static_cast<std::size_t>((t - 2.2) / 0.5) % 3] * (1.0 + 0.01 * std::sin(2.0 * 3.14159265358979 * 5.5 * t));
        vp += f / fs;
        double x = 0.0;
        for (int h = 1; h * f < 3000.0; ++h) x += std::sin(2.0 * 3.14159265358979 * h * vp) / h;
        voice[i] = static_cast<float>(0.08 * std::min({1.0, (t - 2.2) / 0.03, (3.6 - t) / 0.03}) * x);
    }
    return s;
}

double motorsMean(const std::vector<TactileRow>& rows, std::initializer_list<int> motors, double from, double to)
{
    double sum = 0.0;
    int n = 0;
    for (const auto& r : rows)
        if (r.t >= from && r.t < to)
            for (int k : motors) {
                sum += r.levels[static_cast<std::size_t>(k - 1)];
                ++n;
            }
    return n ? sum / n : 0.0;
}
} // namespace

TEST_CASE("audio-touch: stems felt apart — bass at the elbow, the voice at the wrist, the beat on the underside", "[audio-touch][stems]")
{
    const Stems s = stems();
    RenderSettings settings;
    settings.engine.scene = "audio-touch";
    settings.engine.sceneConfig.stems = {"drums", "bass", "vocals"};
    settings.audioIn = &s.audio;
    const auto rows = renderOffline(stillMotion(4.0), settings).tactile;
    // Bass (motors 7, 9): on while it plays, off before and after.
    const double bassOn = motorsMean(rows, {7, 9}, 1.2, 2.9), bassOff = motorsMean(rows, {7, 9}, 0.2, 0.9);
    // Vocals (motors 1, 3): quiet as they are, on while sung; nothing while only bass and drums play.
    const double voiceOn = motorsMean(rows, {1, 3}, 2.4, 3.5), voiceOff = motorsMean(rows, {1, 3}, 1.2, 2.1);
    // Nothing on "other" (motors 4, 6): there is no such stem.
    const double other = motorsMean(rows, {4, 6}, 0.0, 4.0);
    // Kicks as accents on the drums' motors (2, 5, 8).
    int found = 0;
    for (double k : s.kicks) {
        bool hit = false;
        for (const auto& r : rows)
            if (r.t >= k - 0.01 && r.t <= k + 0.06 && r.levels[4] > kRatedLevel) hit = true;
        found += hit;
    }
    std::printf("audio-touch stems: bass motors %.2f while it plays vs %.2f before; voice motors %.2f sung vs %.2f under the bass; "
                "other %.2f; kick accents %d/%zu\n", bassOn, bassOff, voiceOn, voiceOff, other, found, s.kicks.size());
    CHECK(bassOn > 2.0);
    CHECK(bassOff < 0.3);
    CHECK(voiceOn > 1.0);
    CHECK(voiceOff < 0.2);
    CHECK(other == 0.0);
    CHECK(found >= static_cast<int>(s.kicks.size()) - 1);
    std::vector<MotorLevels> packets;
    std::vector<double> hold;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        packets.push_back(rows[i].levels);
        hold.push_back(i + 1 < rows.size() ? rows[i + 1].t - rows[i].t : 0.005);
    }
    CHECK(withinBounds(measureBounds(packets, hold)));

    // The same three stems mixed into one input: the bass leaks into what the voice's motors feel
    // in the mixed scene's middle band (the reason for stems): measured for the record.
    settings.engine.sceneConfig.stems.clear();
    AudioBuffer mix;
    mix.sampleRate = s.audio.sampleRate;
    mix.channels.assign(1, std::vector<float>(s.audio.frames()));
    for (std::size_t i = 0; i < s.audio.frames(); ++i) mix.channels[0][i] = s.audio.channels[0][i] + s.audio.channels[1][i] + s.audio.channels[2][i];
    settings.audioIn = &mix;
    const auto mixed = renderOffline(stillMotion(4.0), settings).tactile;
    std::printf("audio-touch mixed: middle row %.2f under the bass alone vs %.2f with the voice\n", motorsMean(mixed, {4, 5, 6}, 1.2, 2.1),
                motorsMean(mixed, {4, 5, 6}, 2.4, 2.9));

    settings.engine.sceneConfig.stems = {"drums", "guitar"};
    CHECK_THROWS_AS(renderOffline(stillMotion(0.1), settings), InputError);
}

TEST_CASE("audio-touch: audio-touch.stems mixes the stems; the main input after the stems is felt while they are silent", "[audio-touch][stems]")
{
    const Stems s = stems();
    // Mixed, without a main input (the command line): the stems' sum through the three bands, as
    // the mixed input: the bass and the voice in the middle band, felt on motors 4 and 6 that
    // no stem here drives apart (there is no `other` stem).
    RenderSettings settings;
    settings.engine.scene = "audio-touch";
    settings.engine.sceneConfig.stems = {"drums", "bass", "vocals"};
    settings.audioIn = &s.audio;
    const auto apart = renderOffline(stillMotion(4.0), settings).tactile;
    settings.engine.parameters = {"audio-touch.stems=mixed"};
    const auto mixed = renderOffline(stillMotion(4.0), settings).tactile;
    std::printf("audio-touch.stems: m4 m6 under the bass and voice %.2f apart, %.2f mixed\n", motorsMean(apart, {4, 6}, 1.2, 3.5),
                motorsMean(mixed, {4, 6}, 1.2, 3.5));
    CHECK(motorsMean(apart, {4, 6}, 0.0, 4.0) == 0.0);
    CHECK(motorsMean(mixed, {4, 6}, 1.2, 3.5) > 1.0);

    // The plugin's layout: the stems (bass, vocals), then its main input (here a 50 Hz tone
    // throughout, 7 s). Apart: the main input is felt (the mixed path: the elbow row, m8 too)
    // until a stem sounds, the stems alone while one does, and the main input again once they
    // have all been under the floor for 1 s.
    AudioBuffer plugin;
    plugin.sampleRate = s.audio.sampleRate;
    const auto frames = static_cast<std::size_t>(7.0 * plugin.sampleRate);
    plugin.channels.assign(3, std::vector<float>(frames, 0.0f));
    for (std::size_t i = 0; i < s.audio.frames(); ++i) {
        plugin.channels[0][i] = s.audio.channels[1][i];   // bass, 1–3 s
        plugin.channels[1][i] = s.audio.channels[2][i];   // vocals, 2.2–3.6 s
    }
    for (std::size_t i = 0; i < frames; ++i)
        plugin.channels[2][i] = static_cast<float>(0.3 * std::sin(2.0 * 3.14159265358979 * 50.0 * static_cast<double>(i) / plugin.sampleRate));
    settings.engine.sceneConfig.stems = {"bass", "vocals"};
    settings.engine.parameters.clear();
    settings.audioIn = &plugin;
    const auto rows = renderOffline(stillMotion(7.0), settings).tactile;
    // The voice (quiet, 250 ms release) is under the floor by about 4.75 s; the main input is
    // back 1 s later (measured: m8 0 up to 5.75 s, 3.58 from 6 s).
    const double before = motorsMean(rows, {8}, 0.3, 0.95), during = motorsMean(rows, {8}, 1.3, 3.5), after = motorsMean(rows, {8}, 6.0, 7.0);
    std::printf("audio-touch stems + main: m8 (main only) %.2f before the stems, %.2f while they sound, %.2f after\n", before, during, after);
    CHECK(before > 1.0);
    CHECK(during == 0.0);
    CHECK(motorsMean(rows, {7, 9}, 1.3, 2.9) > 2.0);   // the bass stem's own motors
    CHECK(after > 1.0);
    // Mixed: the main input throughout, the stems not apart (the wrist stays still under the voice).
    settings.engine.parameters = {"audio-touch.stems=mixed"};
    const auto main = renderOffline(stillMotion(7.0), settings).tactile;
    CHECK(motorsMean(main, {8}, 1.3, 3.5) > 1.0);
    CHECK(motorsMean(main, {1, 3}, 2.4, 3.5) == 0.0);
}

TEST_CASE("audio-touch: stems on the audio thread allocate, lock and throw nothing", "[audio-touch][stems][realtime]")
{
    ARMADILLO_REQUIRE_GUARD();
    const Stems s = stems();
    for (const int block : {1, 64, 1024}) {
        CAPTURE(block);
        EngineConfig config;
        config.scene = "audio-touch";
        config.sceneConfig.stems = {"drums", "bass", "vocals"};
        Engine engine(config);
        std::vector<float> l(static_cast<std::size_t>(block)), r(static_cast<std::size_t>(block));
        RealtimeGuard guard;
        for (std::size_t at = 0; at + static_cast<std::size_t>(block) <= s.audio.frames(); at += static_cast<std::size_t>(block)) {
            const float* in[3] = {s.audio.channels[0].data() + at, s.audio.channels[1].data() + at, s.audio.channels[2].data() + at};
            engine.processInput(in, 3, block);
            engine.renderAudio(l.data(), r.data(), block);
            ArmState arm;
            arm.valid = true;
            (void) engine.control(arm, Transport {}, static_cast<double>(block) / 48000.0);
        }
        CHECK(guard.allocations() == 0);
        CHECK(guard.deallocations() == 0);
        CHECK(guard.locks() == 0);
        CHECK(guard.throws() == 0);
    }
}
