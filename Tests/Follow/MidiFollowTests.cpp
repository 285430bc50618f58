// A MIDI file the project has never seen, imported (docs/FORMATS.md) and rendered with a
// synthesised rubato performance of the same notes coming in through the audio input (the path
// of `armadillo render --score PIECE.mid --audio-in PERFORMANCE.wav`): each note's motor must start
// when the note sounds. The file is written by the test's own writer (MidiWriter.h), the
// performance's onsets come from the synthesis, the expected motors from the imported score.
#include "Core/Csv.h"
#include "Engine/RenderSettings.h"
#include "Live/Session/RowClock.h"
#include "Formats/ScoreImport.h"
#include "Common/MidiWriter.h"
#include "Performance.h"
#include "Tactile/Bounds.h"
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <random>
#include <unistd.h>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;
using armadillo::live::renderOffline;
using namespace armadillo::formats;
using namespace armadillo::tactile;
using namespace armadillo::test;

namespace {

/// Four bars in C: a melody over a held bass, a tempo change at bar 3, a four-note chord at the end.
std::vector<WrittenNote> piece()
{
    std::vector<WrittenNote> n;
    const auto mel = [&](double beat, double beats, int key, int vel) { n.push_back({beat, beats, key, vel, 0, 0}); };
    const auto bass = [&](double beat, double beats, int key) { n.push_back({beat, beats, key, 70, 1, 0}); };
    mel(0, 1, 76, 80); mel(1, 1, 74, 72); mel(2, 1, 72, 76); mel(3, 1, 74, 84);
    bass(0, 2, 48); bass(2, 2, 43);
    mel(4, 1, 76, 90); mel(5, 1, 79, 100); mel(6, 0.5, 76, 80); mel(6.5, 0.5, 74, 70); mel(7, 1, 72, 76);
    bass(4, 2, 45); bass(6, 2, 41);
    mel(8, 1, 74, 80); mel(9, 1, 71, 70); mel(10, 1, 72, 86); mel(11, 1, 69, 60);
    bass(8, 4, 43);
    // The final chord: C3 E4 G4 C5 together.
    bass(12, 4, 48); mel(12, 4, 64, 80); mel(12, 4, 67, 80); mel(12, 4, 72, 90);
    return n;
}

const std::vector<WrittenTempo> kTempo {{0.0, 100.0}, {8.0, 84.0}};

/// Score seconds of a beat under kTempo (computed here, independently of the importer).
double secondsOf(double beat)
{
    return beat <= 8.0 ? beat * 60.0 / 100.0 : 8.0 * 60.0 / 100.0 + (beat - 8.0) * 60.0 / 84.0;
}

struct Rendition {
    AudioBuffer audio;
    std::map<double, double> onsetOf;   ///< score beat of an onset → s in the recording
    double at(double beat) const
    {
        auto hi = onsetOf.lower_bound(beat);
        if (hi != onsetOf.end() && hi->first == beat) return hi->second;
        if (hi == onsetOf.end()) return std::prev(hi)->second + (secondsOf(beat) - secondsOf(std::prev(hi)->first)) * 1.3;   // the last chord held longer
        auto lo = std::prev(hi);
        return lo->second + (hi->second - lo->second) * (beat - lo->first) / (hi->first - lo->first);
    }
};

/// Plucked harmonic tones (8 partials, 1/h, decaying) at rubato times: the local tempo swings
/// by ±`swing` around the written one; the recording starts `lead` s in.
Rendition perform(const std::vector<WrittenNote>& notes, double swing, double lead, double snrDb, std::uint64_t seed)
{
    Rendition r;
    std::vector<double> beats;
    for (const auto& n : notes) beats.push_back(n.beat);
    std::sort(beats.begin(), beats.end());
    beats.erase(std::unique(beats.begin(), beats.end()), beats.end());
    double t = lead;
    for (std::size_t i = 0; i < beats.size(); ++i) {
        if (i > 0) {
            const double factor = 1.0 + swing * std::sin(2.0 * 3.14159265358979 * beats[i - 1] / 5.0);
            t += (secondsOf(beats[i]) - secondsOf(beats[i - 1])) / factor;
        }
        r.onsetOf[beats[i]] = t;
    }
    const double fs = 48000.0;
    const double total = r.at(16.0) + 1.0;
    std::vector<double> x(static_cast<std::size_t>(total * fs), 0.0);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> phase(0.0, 6.283185307179586);
    for (const auto& n : notes) {
        const double on = r.at(n.beat), off = r.at(n.beat + n.beats);
        const double f0 = 440.0 * std::pow(2.0, (n.key - 69) / 12.0);
        const double amp = 0.05 + 0.10 * n.velocity / 127.0;
        double ph[8];
        for (double& p : ph) p = phase(rng);
        for (auto i = static_cast<std::size_t>(on * fs); i < static_cast<std::size_t>(off * fs) && i < x.size(); ++i) {
            const double u = static_cast<double>(i) / fs - on, left = off - static_cast<double>(i) / fs;
            double a = amp * std::exp(-u / 1.2) * std::min(1.0, u / 0.004) * std::min(1.0, left / 0.03);
            double s = 0.0;
            for (int h = 1; h <= 8; ++h) s += std::sin(6.283185307179586 * f0 * h * u + ph[h - 1]) / h;
            x[i] += a * s;
        }
    }
    if (snrDb < 200.0) {
        double e = 0.0;
        for (double v : x) e += v * v;
        std::normal_distribution<double> noise(0.0, std::sqrt(e / static_cast<double>(x.size())) * std::pow(10.0, -snrDb / 20.0));
        for (double& v : x) v += noise(rng);
    }
    r.audio.sampleRate = fs;
    r.audio.channels.assign(1, std::vector<float>(x.size()));
    for (std::size_t i = 0; i < x.size(); ++i) r.audio.channels[0][i] = static_cast<float>(x[i]);
    return r;
}

CsvTable stillMotion(double seconds)
{
    std::string s = "t,elevation,azimuth,roll\n";
    for (int i = 0; i <= static_cast<int>(seconds * 200.0); ++i) s += std::to_string(i / 200.0) + ",0,0,0\n";
    return CsvTable::parse(s, "still.csv");
}

BoundsReport boundsOfRows(const std::vector<TactileRow>& rows)
{
    std::vector<MotorLevels> packets;
    std::vector<double> hold;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        packets.push_back(rows[i].levels);
        hold.push_back(i + 1 < rows.size() ? rows[i + 1].t - rows[i].t : 0.005);
    }
    return measureBounds(packets, hold);
}

double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    return v.empty() ? std::nan("") : (v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]));
}

} // namespace

TEST_CASE("follow: an unseen MIDI file, imported, follows a rubato performance of its notes", "[follow][midi]")
{
    const std::vector<WrittenNote> notes = piece();
    const std::string path = (std::filesystem::temp_directory_path() / ("armadillo-follow-" + std::to_string(::getpid()) + ".mid")).string();
    writeFile(path, midiBytes(notes, kTempo, 2));
    const ImportedScore imported = importScoreFile(path);
    const Score& score = imported.score;
    REQUIRE(imported.report.dropped == 0);
    REQUIRE(score.notes.size() == notes.size());

    for (const double swing : {0.2, -0.2}) {
        for (const double snr : {1000.0, 25.0}) {
            CAPTURE(swing, snr);
            const Rendition perf = perform(notes, swing, swing > 0 ? 0.9 : 0.35, snr, 3);
            RenderSettings settings;
            settings.engine.scene = "score";
            settings.engine.sceneConfig.score = path;   // the .mid itself: --score takes it directly
            settings.engine.sceneConfig.sampleRate = perf.audio.sampleRate;
            settings.audioIn = &perf.audio;
            const auto rows = renderOffline(stillMotion(static_cast<double>(perf.audio.frames()) / perf.audio.sampleRate), settings).tactile;

            // Every score note: its motor, and when its MIDI note sounds in the recording.
            std::vector<double> late;
            int missing = 0;
            double worst = 0.0;
            for (const ScoreNote& n : score.notes) {
                int motor = -1;
                for (int m = 0; m < kMaxMotors; ++m)
                    if (n.motors & (1u << m)) motor = m;
                REQUIRE(motor >= 0);
                const double beat = score.beatAtSeconds(n.start);
                const double onset = perf.at(std::round(beat * 8.0) / 8.0);
                const double e = motorOnsetNear(rows, motor, onset);
                CAPTURE(beat, motor, onset, e);
                CHECK_FALSE(std::isnan(e));
                if (std::isnan(e)) {
                    ++missing;
                    continue;
                }
                late.push_back(std::fabs(e));
                worst = std::max(worst, e);
                CHECK(e <= 0.150);
                CHECK(e >= -0.150);
            }
            const double med = median(late);
            std::printf("follow midi: tempo swing %+.0f%%, %s: %zu notes, motor onset after the note: median |error| %.1f ms, latest %.1f ms, "
                        "missing %d\n", 100 * swing, snr > 200 ? "clean" : "25 dB SNR", score.notes.size(), 1e3 * med, 1e3 * worst, missing);
            CHECK(med <= 0.050);
            CHECK(withinBounds(boundsOfRows(rows)));
            int most = 0;
            for (const auto& r : rows) {
                int on = 0;
                for (int m = 0; m < kGridMotors; ++m) on += r.levels[static_cast<std::size_t>(m)] > 0;
                most = std::max(most, on);
            }
            CHECK(most <= MidiImportOptions {}.maxMotors);
            // The final chord is felt whole: its four motors together.
            CHECK(most == 4);
        }
    }
    std::filesystem::remove(path);
}
