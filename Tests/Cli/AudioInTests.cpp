// `armadillo render --audio-in` and `armadillo play --audio-in`: the score follows a recording
// given on the command line, measured on the files the binary writes.
#include "CliRun.h"
#include "Core/Csv.h"
#include "Core/Wav.h"
#include "Follow/Performance.h"
#include "SafetyBounds.h"
#include <catch2/catch.hpp>
#include <cmath>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::tactile;

namespace {
std::string stillMotion(const std::string& name, double seconds)
{
    std::string s = "t,elevation,azimuth,roll\n";
    for (int i = 0; i <= static_cast<int>(seconds * 200.0); ++i) s += std::to_string(i / 200.0) + ",0,0,0\n";
    return cli::file(name, s);
}

Score riteScore() { return loadScore(ARMADILLO_SOURCE_DIR "/Resources/Scores/rite-of-spring.score"); }

std::vector<int> followedOf(const Score& s)
{
    std::vector<int> f;
    for (std::size_t i = 0; i < s.notes.size(); ++i)
        if (s.notes[i].part >= 0 && s.parts[static_cast<std::size_t>(s.notes[i].part)].followNotes) f.push_back(static_cast<int>(i));
    return f;
}
} // namespace

TEST_CASE("cli: render --audio-in follows the recording: every note's motor within 60 ms", "[cli][follow]")
{
    const Score score = riteScore();
    test::PerformanceStyle style;
    style.snrDb = 20.0;
    style.sampleRate = 44100.0;   // the recording's rate is taken when --sample-rate is not given
    const test::Performance perf = test::perform(score, followedOf(score), style);
    const std::string wav = cli::path("bassoon.wav");
    writeWav(wav, perf.audio, true);
    const double seconds = static_cast<double>(perf.audio.frames()) / perf.audio.sampleRate;
    const std::string motion = stillMotion("still-follow.csv", seconds);
    const std::string tactile = cli::path("follow.csv");
    const auto r = cli::runArmadillo("render --scene score --score rite-of-spring --motion '" + motion + "' --audio-in '" + wav +
                                     "' --out '" + cli::path("follow-out.wav") + "' --tactile '" + tactile + "'");
    INFO(r.err);
    REQUIRE(r.code == 0);
    const auto rows = readTactile(CsvTable::read(tactile));
    const auto report = armadillo::testing::checkSafety(rows, kGridMotors);
    CHECK(report.ok());
    double worst = 0.0;
    for (const auto& n : perf.notes) {
        const auto mask = score.notes[static_cast<std::size_t>(n.scoreNote)].motors;
        int m = 0;
        while (!(mask & (1u << m))) ++m;
        const double found = armadillo::test::motorOnsetNear(rows, m, n.onset);
        CAPTURE(n.onset);
        REQUIRE_FALSE(std::isnan(found));
        worst = std::max(worst, std::fabs(found));
    }
    CHECK(worst <= 0.060);
}

TEST_CASE("cli: --audio-in refuses a scene that does not listen, a missing file and a sample-rate mismatch", "[cli][follow]")
{
    const std::string motion = stillMotion("still-short.csv", 1.0);
    AudioBuffer tone;
    tone.sampleRate = 48000.0;
    tone.channels.assign(1, std::vector<float>(48000, 0.1f));
    const std::string wav = cli::path("tone.wav");
    writeWav(wav, tone);
    auto run = [&](const std::string& extra) {
        return cli::runArmadillo("render --motion '" + motion + "' --out '" + cli::path("x.wav") + "' " + extra);
    };
    const auto theremin = run("--scene theremin --audio-in '" + wav + "'");
    CHECK(theremin.code == 3);
    CHECK(theremin.err.find("does not listen") != std::string::npos);
    const auto missing = run("--scene score --score rite-of-spring --audio-in '" + cli::path("nope.wav") + "'");
    CHECK(missing.code == 4);   // a file that cannot be opened: I/O failure, as for --motion
    CHECK(missing.err.find("nope.wav") != std::string::npos);
    const auto rate = run("--scene score --score rite-of-spring --sample-rate 44100 --audio-in '" + wav + "'");
    CHECK(rate.code == 3);
    CHECK(rate.err.find("sample rate") != std::string::npos);
    const auto notWav = run("--scene score --score rite-of-spring --audio-in '" + motion + "'");
    CHECK(notWav.code == 3);
    const auto noAudio = cli::runArmadillo("play --scene score --score rite-of-spring --simulate --seconds 1 --no-audio --audio-in '" + wav + "'");
    CHECK(noAudio.code == 2);
}

TEST_CASE("cli: play --audio-in plays the recording out while the score follows it", "[cli][follow][audio]")
{
    const Score score = riteScore();
    test::PerformanceStyle style;
    style.start = 0.3;
    style.firstNoteSeconds = 1.5;
    const test::Performance perf = test::perform(score, followedOf(score), style);
    const std::string wav = cli::path("bassoon-play.wav");
    writeWav(wav, perf.audio, true);
    const std::string out = cli::path("played.wav"), tactile = cli::path("played.csv");
    const auto r = cli::runArmadillo("play --scene score --score rite-of-spring --simulate --seconds 3 --audio-in '" + wav + "' --out '" + out +
                                     "' --tactile '" + tactile + "'");
    INFO(r.err);
    REQUIRE(r.code == 0);
    // The recording is in the output (the score scene itself is silent): its first 2.5 s match.
    const AudioBuffer played = readWav(out);
    REQUIRE(played.frames() > static_cast<std::size_t>(2.5 * 48000));
    double err = 0.0, energy = 0.0;
    for (std::size_t i = 0; i < static_cast<std::size_t>(2.5 * 48000); ++i) {
        const double d = played.channels[0][i] - perf.audio.channels[0][i];
        err += d * d;
        energy += double(perf.audio.channels[0][i]) * double(perf.audio.channels[0][i]);
    }
    CHECK(energy > 0.0);
    CHECK(err < 1e-3 * energy);   // 16-bit rounding only
    // And the motors followed it: the first note's motor came on only after the recording's first
    // note began (0.3 s in), and within the session.
    const auto rows = readTactile(CsvTable::read(tactile));
    const auto mask = score.notes[static_cast<std::size_t>(perf.notes[0].scoreNote)].motors;
    int m = 0;
    while (!(mask & (1u << m))) ++m;
    // On the session's timeline (the tactile log's t counts from the link's start, which is the
    // audio clock's start too), not from the first logged step: a machine that delays the
    // first control steps (a loaded CI runner) has the recording playing already.
    double firstOn = -1.0;
    for (const auto& row : rows)
        if (row.levels[static_cast<std::size_t>(m)] > 0) {
            firstOn = row.t;
            break;
        }
    INFO("first row at " << rows.front().t << " s, the first note's motor on at " << firstOn << " s");
    CHECK(firstOn > 0.25);
    CHECK(firstOn < 1.0);
}

TEST_CASE("cli: play --keys: p panics: silence and every motor off, reported, counted in the summary", "[cli][panic]")
{
    using namespace armadillo::cli;
    // The same session with and without the key: the theremin sounds and frets are felt without
    // it; with it (read at once from stdin) nothing sounds after the first millisecond and every
    // motor packet is all-off.
    const std::string motion = file("panic-motion.csv", [] {
        std::string s = "t,elevation,azimuth,roll\n";
        for (int i = 0; i <= 400; ++i) s += std::to_string(i / 200.0) + "," + std::to_string(-40.0 + 0.2 * i) + ",0,0\n";
        return s;
    }());
    const std::string keys = file("panic-keys.txt", "p");
    const std::string base = "play --scene theremin --simulate --motion '" + motion + "' --seconds 1.5 --keys";
    const Run normal = runArmadillo(base + " --out '" + path("normal.wav") + "' --tactile '" + path("normal.csv") + "'");
    REQUIRE(normal.code == 0);
    CHECK(normal.out.find("\"panics\"") == std::string::npos);
    CHECK(normal.err.find("p = panic") != std::string::npos);
    const Run panicked = runArmadillo(base + " --out '" + path("panic.wav") + "' --tactile '" + path("panic.csv") + "'", keys);
    INFO(panicked.err);
    REQUIRE(panicked.code == 0);
    CHECK(panicked.err.find("PANIC") != std::string::npos);
    CHECK(panicked.out.find("\"panics\":1") != std::string::npos);
    auto energy = [](const AudioBuffer& b, std::size_t from) {
        double e = 0.0;
        for (std::size_t i = from; i < b.frames(); ++i) e += static_cast<double>(b.channels[0][i]) * static_cast<double>(b.channels[0][i]);
        return e;
    };
    auto motorSum = [](const std::string& csvPath) {
        const CsvTable t = CsvTable::read(csvPath);
        double s = 0.0;
        for (std::size_t r = 0; r < t.rowCount(); ++r)
            for (int c = 1; c < static_cast<int>(t.header().size()); ++c) s += t.value(r, c);
        return s;
    };
    CHECK(energy(readWav(path("normal.wav")), 0) > 1.0);
    CHECK(energy(readWav(path("panic.wav")), 48) == 0.0);
    CHECK(motorSum(path("normal.csv")) > 0.0);
    CHECK(motorSum(path("panic.csv")) == 0.0);
}

#include "Common/MidiWriter.h"

TEST_CASE("cli: render --midi-in: the layered keyboard logs the MIDI file's notes as it captures them; bad uses refused", "[cli][layered][midi]")
{
    // A synthesised phrase (A2 E4 G4 C5, one every 0.5 s from 0.2 s, partials 1..6 at 1/h decaying)
    // and the MIDI file that played it (120 bpm: beat 0.4 + i, 0.9 beats long).
    const int notes[4] = {45, 64, 67, 72};
    const double fs = 48000.0;
    AudioBuffer wav;
    wav.sampleRate = fs;
    wav.channels.assign(1, std::vector<float>(static_cast<std::size_t>(2.6 * fs), 0.0f));
    for (int k = 0; k < 4; ++k) {
        const double f0 = 440.0 * std::pow(2.0, (notes[k] - 69) / 12.0);
        for (std::size_t i = static_cast<std::size_t>((0.2 + 0.5 * k) * fs); i < wav.channels[0].size(); ++i) {
            const double t = static_cast<double>(i) / fs - (0.2 + 0.5 * k);
            double v = 0.0;
            for (int h = 1; h <= 6; ++h) v += std::exp(-t * h / 0.6) * std::sin(2.0 * 3.14159265358979 * h * f0 * t) / h;
            wav.channels[0][i] += static_cast<float>(0.2 * std::min(1.0, t / 0.002) * v);
        }
    }
    const std::string audio = cli::path("phrase.wav"), mid = cli::path("phrase.mid");
    writeWav(audio, wav, true);
    std::vector<test::WrittenNote> written;
    for (int k = 0; k < 4; ++k) written.push_back({0.4 + k, 0.9, notes[k], 90, 0, 0});
    test::writeFile(mid, test::midiBytes(written, {{0, 120}}, 1));
    std::string motion = "t,elevation,azimuth,roll\n";
    for (int i = 0; i <= 800; ++i) motion += std::to_string(i / 200.0) + "," + std::to_string(i < 520 ? -20.0 : 60.0 * (i - 520) / 280.0) + ",10,0\n";
    const std::string pose = cli::file("rise.csv", motion);
    const std::string base = "render --scene layered-keyboard --motion '" + pose + "' --out '" + cli::path("layered.wav") + "' --audio-in '" + audio + "'";
    const cli::Run r = cli::runArmadillo(base + " --midi-in '" + mid + "'");
    REQUIRE(r.code == 0);
    std::size_t at = 0;
    for (const char* name : {"A2", "E4", "G4", "C5"}) {
        INFO(r.err);
        const std::size_t found = r.err.find(std::string("render: captured ") + name + " at", at);
        REQUIRE(found != std::string::npos);   // in order
        at = found + 1;
    }
    CHECK(cli::runArmadillo("render --scene layered-keyboard --motion '" + pose + "' --out '" + cli::path("x.wav") + "' --midi-in '" + mid + "'").code == 2);
    const cli::Run bad = cli::runArmadillo(base + " --midi-in '" + cli::file("bad.mid", "MThd\x00\x00\x00\x06") + "'");
    CHECK(bad.code == 3);
    CHECK(bad.err.find("bad.mid") != std::string::npos);
    const cli::Run score = cli::runArmadillo("render --scene audio-touch --motion '" + pose + "' --out '" + cli::path("y.wav") + "' --audio-in '" + audio + "' --midi-in '" + mid + "'");
    CHECK(score.code == 3);
    CHECK(score.err.find("does not listen to MIDI") != std::string::npos);
}
