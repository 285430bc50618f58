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
    double firstOn = -1.0;
    for (const auto& row : rows)
        if (row.levels[static_cast<std::size_t>(m)] > 0) {
            firstOn = row.t - rows.front().t;
            break;
        }
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
