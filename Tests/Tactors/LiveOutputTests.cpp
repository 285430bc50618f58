// The live tactor output (Live/Outputs/TactorOutput) and `armadillo play --tactors` / `tactors test` as a
// user runs them, against a JACK server of the test's own (dummy backend) and ALSA's null PCM.
#define ARMADILLO_REALTIME_GUARD_IMPLEMENTATION
#include "Common/RealtimeGuard.h"
#include "Common/ScratchDir.h"
#include "Tactors/JackFixtures.h"
#include "Tactors/SignalMeasure.h"
#include "Core/AtomicFile.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Core/Wav.h"
#include "Formats/ScoreImport.h"
#include "Live/Outputs/TactorOutput.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>

using namespace armadillo;
using namespace armadillo::formats;
using namespace armadillo::core;

namespace {

std::string scratch(const std::string& name) { return (test::scratchDir("armadillo-tactors-live") / name).string(); }

} // namespace

TEST_CASE("tactor output: a period drains the control steps and renders without allocating or locking", "[tactors][live][realtime]")
{
    ARMADILLO_REQUIRE_GUARD();
    live::TactorOutputConfig c;
    c.device = "null";   // ALSA's null PCM: opened for real, plays nowhere
    c.params.model = tactors::TactorModel::Lra;
    live::TactorOutput out(c);
    REQUIRE(out.channels() == 9);
    std::vector<std::vector<float>> buf(9, std::vector<float>(4096));
    std::array<float*, tactors::kMaxChannels> p {};
    for (int k = 0; k < 9; ++k) p[static_cast<std::size_t>(k)] = buf[static_cast<std::size_t>(k)].data();
    MotorLevels l {};
    test::RealtimeGuard guard;
    for (int block = 0; block < 300; ++block) {
        for (int s = 0; s < 3; ++s) {
            for (int m = 0; m < 9; ++m) l[static_cast<std::size_t>(m)] = static_cast<std::uint8_t>((block + m + s) % 7);
            out.push(0.005 * (3 * block + s), l);
        }
        out.renderPeriod(p.data(), 64 + (block * 97) % 4000, 0.0);
    }
    const bool clean = guard.clean();
    INFO(guard.report());
    CHECK(clean);
    CHECK(out.recordsDropped() == 0);
    test::RealtimeGuard pushGuard;   // the control thread's side
    out.push(10.0, l);
    const bool pushClean = pushGuard.clean();
    CHECK(pushClean);
}

TEST_CASE("tactor output: a voice coil handed the session's sound carries it, in real time, and drops a backlog", "[tactors][live][sound]")
{
    ARMADILLO_REQUIRE_GUARD();
    live::TactorOutputConfig c;
    c.device = "null";
    c.params.model = tactors::TactorModel::VoiceCoil;
    c.params.voiceCoilSound = true;
    live::TactorOutput out(c);
    REQUIRE(out.wantsSound());
    constexpr int kPeriod = 256;
    std::vector<std::vector<float>> buf(9, std::vector<float>(kPeriod));
    std::array<float*, tactors::kMaxChannels> p {};
    for (int k = 0; k < 9; ++k) p[static_cast<std::size_t>(k)] = buf[static_cast<std::size_t>(k)].data();
    MotorLevels l {};
    l[2] = 4;
    std::vector<float> left(kPeriod), right(kPeriod), carried;
    carried.reserve(100 * kPeriod);   // the test's own record, sized before the guard
    const double sr = out.sampleRate();
    std::uint64_t n = 0;
    test::RealtimeGuard guard;
    for (int block = 0; block < 200; ++block) {
        for (int i = 0; i < kPeriod; ++i, ++n) {   // the session's audio: 120 Hz, left only
            left[static_cast<std::size_t>(i)] = static_cast<float>(0.6 * std::sin(6.283185307179586 * 120.0 * static_cast<double>(n) / sr));
            right[static_cast<std::size_t>(i)] = 0.0f;
        }
        out.pushSound(left.data(), right.data(), kPeriod);
        out.push(0.005 * block, l);
        out.renderPeriod(p.data(), kPeriod, 0.0);
        if (block >= 100) carried.insert(carried.end(), buf[2].begin(), buf[2].end());
    }
    const bool clean = guard.clean();
    INFO(guard.report());
    CHECK(clean);
    // Motor 3's channel carries the 120 Hz sound at level 4's peak; the others nothing.
    int crossings = 0;
    float peak = 0.0f;
    for (std::size_t i = 1; i < carried.size(); ++i) {
        if (carried[i - 1] < 0.0f && carried[i] >= 0.0f) ++crossings;
        peak = std::max(peak, std::abs(carried[i]));
    }
    CHECK(crossings == Approx(120.0 * static_cast<double>(carried.size()) / sr).margin(2.0));
    CHECK(peak == Approx(4.0 / 15.0).epsilon(0.03));
    CHECK(*std::max_element(buf[0].begin(), buf[0].end()) == 0.0f);
    // A sound clock far ahead of the output's (a whole second pushed at once): the backlog is
    // dropped down to kSoundBacklog, so the carrier lags the sound by at most that much.
    std::vector<float> second(static_cast<std::size_t>(sr), 0.1f);
    for (std::size_t at = 0; at + kPeriod <= second.size(); at += kPeriod) out.pushSound(second.data() + at, second.data() + at, kPeriod);
    CHECK(out.soundWaiting() > live::TactorOutput::kSoundBacklog + kPeriod);
    out.renderPeriod(p.data(), kPeriod, 0.0);
    CHECK(out.soundWaiting() <= live::TactorOutput::kSoundBacklog);
}

TEST_CASE("tactor output: the live output and render --tactile-wav carry the same samples", "[tactors][live][wav]")
{
    // Control steps every 5 ms, each pushed just before the period that starts at its time (a
    // period of 240 samples): the live path; the same rows through Formats' writer: the file.
    std::vector<TactileRow> rows;
    for (int i = 0; i < 800; ++i) {
        TactileRow r;
        r.t = 0.005 * i;
        for (int m = 0; m < 9; ++m) r.levels[static_cast<std::size_t>(m)] = static_cast<std::uint8_t>((i / (7 + m)) % 6);
        rows.push_back(r);
    }
    for (auto model : {tactors::TactorModel::Erm, tactors::TactorModel::Lra, tactors::TactorModel::VoiceCoil}) {
        live::TactorOutputConfig c;
        c.device = "null";
        c.params.model = model;
        live::TactorOutput out(c);
        REQUIRE(out.sampleRate() == 48000.0);
        std::vector<std::vector<float>> live(9, std::vector<float>(rows.size() * 240));
        std::array<float*, tactors::kMaxChannels> p {};
        for (std::size_t i = 0; i < rows.size(); ++i) {
            out.push(rows[i].t, rows[i].levels);
            for (int k = 0; k < 9; ++k) p[static_cast<std::size_t>(k)] = live[static_cast<std::size_t>(k)].data() + i * 240;
            out.renderPeriod(p.data(), 240, 0.0);
        }
        const std::string path = scratch(std::string("same-") + tactors::modelName(model) + ".wav");
        writeTactileWav(path, rows, c.params, c.map, c.gains, 48000.0, true);
        const AudioBuffer file = readWav(path);
        REQUIRE(file.channels.size() == 9);
        for (int k = 0; k < 9; ++k) {
            INFO(tactors::modelName(model) << " channel " << k + 1);
            CHECK(live[static_cast<std::size_t>(k)] == file.channels[static_cast<std::size_t>(k)]);
        }
    }
}

TEST_CASE("tactor output: errors name the cause and open nothing", "[tactors][live][errors]")
{
    live::TactorOutputConfig c;
    c.device = "hw:97";   // no such card
    try {
        live::TactorOutput out(c);
        FAIL("opened");
    } catch (const IoError& e) {
        CHECK(std::string(e.what()).find("hw:97") != std::string::npos);
    }
    // No JACK server of this name.
    ::setenv("JACK_DEFAULT_SERVER", ("armadillo_none_" + std::to_string(::getpid())).c_str(), 1);
    c.device = "jack";
    try {
        live::TactorOutput out(c);
        FAIL("opened");
    } catch (const IoError& e) {
        CHECK(std::string(e.what()).find("not running") != std::string::npos);
    }
    ::unsetenv("JACK_DEFAULT_SERVER");
    // Gains for more channels than the map: refused before any device is opened (hw:97 would throw IoError).
    c.device = "hw:97";
    c.gains.count = 12;
    c.gains.source = "rig.json";
    CHECK_THROWS_AS(live::TactorOutput(c), InputError);
}

TEST_CASE("tactor output: JACK ports tactor_1..9, connected by pattern; too few ports is an error", "[tactors][live][jack]")
{
    test::JackServer server(48000, 256, 4);
    REQUIRE(server.running());
    live::TactorOutputConfig c;
    c.device = "jack";
    c.connect = "rec:in_";
    {
        test::JackRecorder rec(9, 2.0);
        REQUIRE(rec.ok());
        live::TactorOutput out(c);
        CHECK(out.sampleRate() == 48000.0);
        CHECK(out.periodFrames() == 256);
        out.start();
        for (int k = 0; k < 9; ++k) {
            // (the graph reaches other clients asynchronously)
            REQUIRE(testing::eventually([&] { return rec.connections(k).size() == 1; }, 10.0));
            const auto conn = rec.connections(k);
            CHECK(conn[0] == "armadillo:tactor_" + std::to_string(k + 1));
        }
        // Motor k at level k: channel k carries k/15.
        MotorLevels l {};
        for (int m = 0; m < 9; ++m) l[static_cast<std::size_t>(m)] = static_cast<std::uint8_t>(m + 1 > 5 ? 5 : m + 1);
        const std::size_t from = rec.frames();
        double t = 0.0;
        REQUIRE(testing::eventually([&] {
            out.push(t, l);   // a control step every poll (the levels stay the same)
            t += 0.002;
            return rec.frames() > from + 24000;
        }));
        out.stop();
        for (int k = 0; k < 9; ++k) {
            const auto x = rec.channel(k);
            const auto m = test::measureFrames(std::vector<float>(x.end() - 4800, x.end() - 2400), 240);
            INFO("channel " << k + 1);
            CHECK(*std::max_element(m.level.begin(), m.level.end()) == Approx(std::min(k + 1, 5)).margin(0.05));
        }
    }
    // The dummy backend has 4 playback ports: 9 channels cannot all be connected.
    c.connect = "system:playback_";
    live::TactorOutput out(c);
    CHECK_THROWS_AS(out.start(), IoError);
    c.connect = "nothing:here";
    CHECK_THROWS_AS(live::TactorOutput(c), IoError);
}
