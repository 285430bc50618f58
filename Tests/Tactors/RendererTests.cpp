// The tactor renderer (Source/Tactors): each model's level law and carrier, measured on the
// samples; the channel map and gain file readers; one code path for files and live blocks; no
// allocation or lock on the audio thread.
#define ARMADILLO_REALTIME_GUARD_IMPLEMENTATION
#include "Common/RealtimeGuard.h"
#include "Tactors/SignalMeasure.h"
#include "Core/Errors.h"
#include "Core/Wav.h"
#include "Formats/ScoreImport.h"
#include "Tactors/TactorRenderer.h"
#include <catch2/catch.hpp>
#include <array>
#include <cmath>
#include <filesystem>
#include <vector>

using namespace armadillo;
using namespace armadillo::formats;
using namespace armadillo::core;
using namespace armadillo::tactors;

namespace {

constexpr double kRate = 48000.0;

/// Renders `seconds` of each level of `steps` on every channel, block by block as a live output
/// would (blocks of 240 samples); returns channel `c`.
std::vector<std::vector<float>> renderSteps(TactorRenderer& r, const std::vector<std::pair<int, double>>& steps)
{
    std::vector<std::vector<float>> out(static_cast<std::size_t>(r.channels()));
    std::vector<std::vector<float>> block(static_cast<std::size_t>(r.channels()), std::vector<float>(240));
    std::array<float*, kMaxChannels> p {};
    for (int c = 0; c < r.channels(); ++c) p[static_cast<std::size_t>(c)] = block[static_cast<std::size_t>(c)].data();
    double dt = 0.0;
    for (const auto& [level, seconds] : steps) {
        MotorLevels l {};
        l.fill(static_cast<std::uint8_t>(level));
        r.setLevels(l, dt);
        dt = seconds;
        const auto n = static_cast<int>(std::lround(seconds * kRate));
        for (int done = 0; done < n; done += 240) {
            const int len = std::min(240, n - done);
            r.render(p.data(), len);
            for (int c = 0; c < r.channels(); ++c)
                out[static_cast<std::size_t>(c)].insert(out[static_cast<std::size_t>(c)].end(), block[static_cast<std::size_t>(c)].begin(),
                                                        block[static_cast<std::size_t>(c)].begin() + len);
        }
    }
    return out;
}

/// Frequency from the upward zero crossings of x[from, to).
double measuredHz(const std::vector<float>& x, std::size_t from, std::size_t to)
{
    std::vector<double> ups;
    for (std::size_t i = from + 1; i < to; ++i)
        if (x[i - 1] < 0.0f && x[i] >= 0.0f) ups.push_back(static_cast<double>(i - 1) + static_cast<double>(x[i - 1] / (x[i - 1] - x[i])));
    if (ups.size() < 2) return 0.0;
    return kRate * static_cast<double>(ups.size() - 1) / (ups.back() - ups.front());
}

std::string tempPath(const std::string& name)
{
    const auto dir = std::filesystem::temp_directory_path() / "armadillo-tests-tactors";
    std::filesystem::create_directories(dir);
    return (dir / name).string();
}

} // namespace

TEST_CASE("tactors: every model carries level/15 of full scale, frame by frame", "[tactors]")
{
    for (TactorModel model : {TactorModel::Erm, TactorModel::Lra, TactorModel::VoiceCoil}) {
        TactorParams p;
        p.model = model;
        TactorRenderer r;
        r.prepare(p, ChannelMap::identity(9), TactorGains {}, kRate);
        // Levels within the safety bounds (5 s at the rating, short visits above it).
        std::vector<std::pair<int, double>> steps {{1, 0.2}, {3, 0.2}, {5, 0.2}, {9, 0.2}, {2, 0.2}, {15, 0.1}, {4, 0.2}, {0, 0.2}};
        const auto out = renderSteps(r, steps);
        CHECK(r.limited() == 0);
        const auto m = test::measureFrames(out[4], 240);   // 5 ms frames, aligned with the steps
        std::size_t frame = 0;
        for (const auto& [level, seconds] : steps) {
            const auto frames = static_cast<std::size_t>(std::lround(seconds / 0.005));
            for (std::size_t f = frame + 2; f < frame + frames; ++f) {   // (the first two frames of a stop hold the LRA's 6 ms brake)
                INFO(modelName(model) << " level " << level << " frame " << f);
                CHECK(m.level[f] == Approx(level).margin(0.01));
            }
            frame += frames;
        }
    }
}

TEST_CASE("tactors: the carriers: ERM rising with the level and spinning up, LRA at resonance, voice coil fixed", "[tactors]")
{
    TactorParams p;
    p.model = TactorModel::Erm;
    TactorRenderer r;
    r.prepare(p, ChannelMap::identity(1), TactorGains {}, kRate);
    const auto erm = renderSteps(r, {{2, 0.5}, {5, 0.5}, {4, 0.5}})[0];
    const double low = measuredHz(erm, 12000, 24000), high = measuredHz(erm, 36000, 48000);
    CHECK(low == Approx(carrierHz(p, 2)).epsilon(0.01));    // 100 + 150·2/15 = 120 Hz
    CHECK(high == Approx(carrierHz(p, 5)).epsilon(0.01));   // 150 Hz
    CHECK(carrierHz(p, 15) == Approx(250.0));
    // Spinning up: the first 20 ms after the step are slower than the settled speed.
    const double early = measuredHz(erm, 24000, 24000 + 960);
    CHECK(early < high - 5.0);
    CHECK(early > low);

    p.model = TactorModel::Lra;
    r.prepare(p, ChannelMap::identity(1), TactorGains {}, kRate);
    CHECK(measuredHz(renderSteps(r, {{3, 0.5}, {5, 0.5}})[0], 0, 48000) == Approx(170.0).epsilon(0.005));
    p.model = TactorModel::VoiceCoil;
    r.prepare(p, ChannelMap::identity(1), TactorGains {}, kRate);
    CHECK(measuredHz(renderSteps(r, {{3, 0.5}, {9, 0.1}})[0], 0, 28800) == Approx(250.0).epsilon(0.005));
}

TEST_CASE("tactors: an LRA that stops is braked by one antiphase pulse at most at the rating", "[tactors][lra]")
{
    TactorParams p;
    p.model = TactorModel::Lra;
    p.lraHz = 160.0;   // 300 samples a period at 48 kHz
    TactorRenderer r;
    r.prepare(p, ChannelMap::identity(1), TactorGains {}, kRate);
    const auto x = renderSteps(r, {{10, 0.1}, {0, 0.1}})[0];
    const std::size_t stop = 4800, brake = static_cast<std::size_t>(std::lround(p.lraBrakeTime * kRate));
    double peak = 0.0, correlation = 0.0;
    for (std::size_t i = stop; i < stop + brake; ++i) {
        peak = std::max(peak, std::fabs(static_cast<double>(x[i])));
        correlation += static_cast<double>(x[i]) * static_cast<double>(x[i - 300]);   // the drive one period earlier
    }
    CHECK(peak > 4.9 / 15.0);
    CHECK(peak <= 5.0 / 15.0 + 1e-6);   // 10 asked, braked at the rating
    CHECK(correlation < 0.0);           // antiphase
    for (std::size_t i = stop + brake; i < x.size(); ++i) REQUIRE(x[i] == 0.0f);
    // Without braking the stop is silence at once.
    p.lraBrakeTime = 0.0;
    r.prepare(p, ChannelMap::identity(1), TactorGains {}, kRate);
    const auto y = renderSteps(r, {{10, 0.1}, {0, 0.1}})[0];
    for (std::size_t i = stop; i < y.size(); ++i) REQUIRE(y[i] == 0.0f);
    // Other models never brake.
    p.model = TactorModel::VoiceCoil;
    r.prepare(p, ChannelMap::identity(1), TactorGains {}, kRate);
    const auto z = renderSteps(r, {{10, 0.1}, {0, 0.1}})[0];
    for (std::size_t i = stop; i < z.size(); ++i) REQUIRE(z[i] == 0.0f);
}

TEST_CASE("tactors: the channel map routes motors to channels; bad maps are refused", "[tactors][map]")
{
    CHECK(channelMapText(parseChannelMap("1-9", 9)) == "1,2,3,4,5,6,7,8,9");
    CHECK(channelMapText(parseChannelMap("10-12,-,1", 12)) == "10,11,12,-,1");
    CHECK(parseChannelMap("3", 9).channels == 1);
    for (const char* bad : {"", "0", "10", "a", "1,,2", "3-1", "1-2-3", "1,2,", "1.5", "-1"}) {
        INFO(bad);
        CHECK_THROWS_AS(parseChannelMap(bad, 9), InputError);
    }
    CHECK_THROWS_AS(parseChannelMap("1-9,1-8", 9), InputError);   // 17 channels
    try {
        parseChannelMap("1,11", 9);
        FAIL("accepted");
    } catch (const InputError& e) {
        CHECK(std::string(e.what()).find("--back-motors") != std::string::npos);
    }
    // Routing: channel 0 plays motor 3, channel 1 is silent, channel 2 plays motor 1.
    TactorRenderer r;
    r.prepare(TactorParams {}, parseChannelMap("3,-,1", 9), TactorGains {}, kRate);
    MotorLevels l {};
    l[0] = 3;
    l[2] = 9;
    r.setLevels(l, 0.0);
    std::vector<std::vector<float>> buf(3, std::vector<float>(480));
    float* p[3] = {buf[0].data(), buf[1].data(), buf[2].data()};
    r.render(p, 480);
    CHECK(test::measureFrames(buf[0], 480).level[0] == Approx(9.0).margin(0.01));
    CHECK(test::measureFrames(buf[1], 480).level[0] == 0.0);
    CHECK(test::measureFrames(buf[2], 480).level[0] == Approx(3.0).margin(0.01));
}

TEST_CASE("tactors: the gain file attenuates channels; bad files are refused with file and line", "[tactors][gain]")
{
    const TactorGains g = parseTactorGains("{\n  \"armadillo\": \"tactor-gains\",\n  \"version\": 1,\n  \"gain\": [1, 0.5, 0.25]\n}\n", "rig.json");
    REQUIRE(g.count == 3);
    CHECK(g.gain[1] == 0.5f);
    CHECK(g.gain[3] == 1.0f);
    TactorRenderer r;
    r.prepare(TactorParams {}, ChannelMap::identity(9), g, kRate);
    const auto out = renderSteps(r, {{6, 0.05}});
    CHECK(test::measureFrames(out[0], 240).level[2] == Approx(6.0).margin(0.01));
    CHECK(test::measureFrames(out[1], 240).level[2] == Approx(3.0).margin(0.01));
    CHECK(test::measureFrames(out[2], 240).level[2] == Approx(1.5).margin(0.01));

    struct Bad {
        const char* text;
        long line;
    };
    const Bad bad[] = {
        {"{\n\"armadillo\": \"tactor-gains\",\n\"version\": 1,\n\"gain\": [1,\n 1.5]\n}", 5},   // out of range, on its own line
        {"{\n\"armadillo\": \"tactor-gains\",\n\"version\": 1,\n\"gain\": [-0.1]\n}", 4},
        {"{\n\"armadillo\": \"tactor-gains\",\n\"version\": 2,\n\"gain\": [1]\n}", 3},
        {"{\n\"armadillo\": \"calibration\",\n\"version\": 1,\n\"gain\": [1]\n}", 2},
        {"{\n\"armadillo\": \"tactor-gains\",\n\"version\": 1,\n\"gains\": [1]\n}", 4},
        {"{\n\"armadillo\": \"tactor-gains\",\n\"version\": 1,\n\"gain\": []\n}", 4},
        {"{\n\"armadillo\": \"tactor-gains\",\n\"version\": 1,\n\"gain\": [\"1\"]\n}", 4},
        {"{\n\"armadillo\": \"tactor-gains\",\n\"version\": 1,\n\"gain\": [1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,1]\n}", 4},
        {"[1, 2]", 1},
        {"{\n\"armadillo\": \"tactor-gains\",\n\"version\": 1,\n\"gain\": [1,\n", 5},   // syntax: ends early
    };
    for (const Bad& b : bad) {
        INFO(b.text);
        try {
            parseTactorGains(b.text, "rig.json");
            FAIL("accepted");
        } catch (const InputError& e) {
            CHECK(e.file() == "rig.json");
            CHECK(e.line() == b.line);
        }
    }
    CHECK_THROWS_AS(loadTactorGains(tempPath("missing-gains.json")), IoError);
    // More gains than the map has channels.
    TactorGains twelve;
    twelve.count = 12;
    twelve.source = "rig.json";
    CHECK_THROWS_AS(r.prepare(TactorParams {}, ChannelMap::identity(9), twelve, kRate), InputError);
    // Settings out of range.
    TactorParams p;
    p.lraHz = 30.0;
    CHECK_THROWS_AS(validate(p, kRate, "x"), InputError);
    p = {};
    p.voiceCoilHz = 401.0;
    CHECK_THROWS_AS(validate(p, kRate, "x"), InputError);
    p = {};
    p.model = TactorModel::VoiceCoil;
    CHECK_THROWS_AS(validate(p, 400.0, "x"), InputError);
}

TEST_CASE("tactors: a file and a live output carry the same samples (one code path)", "[tactors][wav]")
{
    // Rows at a control rate that does not divide the sample rate (1/285 s), levels changing.
    std::vector<TactileRow> rows;
    std::uint32_t seed = 7;
    for (int i = 0; i < 600; ++i) {
        TactileRow row;
        row.t = 0.25 + i / 285.0;
        seed = seed * 1664525u + 1013904223u;
        for (int m = 0; m < 9; ++m) row.levels[static_cast<std::size_t>(m)] = static_cast<std::uint8_t>(((seed >> (3 * m)) & 7u) % 6u);
        rows.push_back(row);
    }
    for (TactorModel model : {TactorModel::Erm, TactorModel::Lra, TactorModel::VoiceCoil}) {
        TactorParams p;
        p.model = model;
        // The file, through Formats' writer, read back as float.
        const std::string path = tempPath(std::string("same-") + modelName(model) + ".wav");
        writeTactileWav(path, rows, p, ChannelMap::identity(9), TactorGains {}, kRate, true);
        const AudioBuffer file = readWav(path);
        // Live: the renderer handed each row as it comes and asked for blocks that end where
        // rows begin (what a sound card's period does when a packet arrives at its edge).
        TactorRenderer live;
        live.prepare(p, ChannelMap::identity(9), TactorGains {}, kRate);
        REQUIRE(file.channels.size() == 9);
        std::vector<std::vector<float>> got(9);
        std::vector<std::vector<float>> block(9, std::vector<float>(512));
        std::array<float*, kMaxChannels> ptr {};
        for (int c = 0; c < 9; ++c) ptr[static_cast<std::size_t>(c)] = block[static_cast<std::size_t>(c)].data();
        std::size_t at = 0;
        for (std::size_t i = 0; i < rows.size(); ++i) {
            live.setLevels(rows[i].levels, i ? rows[i].t - rows[i - 1].t : 0.0);
            const std::size_t end = i + 1 < rows.size() ? static_cast<std::size_t>(std::ceil((rows[i + 1].t - rows[0].t - 1e-9) * kRate)) : file.frames();
            while (at < end) {
                const int n = static_cast<int>(std::min<std::size_t>(512, end - at));
                live.render(ptr.data(), n);
                for (int c = 0; c < 9; ++c)
                    got[static_cast<std::size_t>(c)].insert(got[static_cast<std::size_t>(c)].end(), block[static_cast<std::size_t>(c)].begin(), block[static_cast<std::size_t>(c)].begin() + n);
                at += static_cast<std::size_t>(n);
            }
        }
        for (int c = 0; c < 9; ++c) {
            INFO(modelName(model) << " channel " << c + 1);
            REQUIRE(got[static_cast<std::size_t>(c)].size() == file.frames());
            CHECK(got[static_cast<std::size_t>(c)] == file.channels[static_cast<std::size_t>(c)]);
        }
    }
}

TEST_CASE("tactors: setLevels, render and allOff neither allocate nor lock", "[tactors][realtime]")
{
    ARMADILLO_REQUIRE_GUARD();
    for (TactorModel model : {TactorModel::Erm, TactorModel::Lra, TactorModel::VoiceCoil}) {
        TactorParams p;
        p.model = model;
        TactorRenderer r;
        r.prepare(p, ChannelMap::identity(12), TactorGains {}, kRate);
        std::vector<std::vector<float>> buf(12, std::vector<float>(1024));
        std::array<float*, kMaxChannels> ptr {};
        for (int c = 0; c < 12; ++c) ptr[static_cast<std::size_t>(c)] = buf[static_cast<std::size_t>(c)].data();
        MotorLevels l {};
        test::RealtimeGuard guard;
        for (int block = 0; block < 400; ++block) {
            for (int m = 0; m < 12; ++m) l[static_cast<std::size_t>(m)] = static_cast<std::uint8_t>((block * (m + 3)) % 16);
            r.setLevels(l, 0.005);
            r.render(ptr.data(), 1 + (block * 37) % 1024);
            if (block % 50 == 49) r.allOff();
        }
        const bool clean = guard.clean();
        INFO(guard.report());
        CHECK(clean);
    }
}

TEST_CASE("tactors: a voice coil handed the scene's sound carries it band-limited, at level/15 peak; silence falls back", "[tactors][sound]")
{
    // The sound: 150 Hz (felt) + 3 kHz (above what skin feels) + a DC offset, then silence.
    TactorParams p;
    p.model = TactorModel::VoiceCoil;
    p.voiceCoilSound = true;
    TactorRenderer r;
    r.prepare(p, ChannelMap::identity(1), TactorGains {}, kRate);
    constexpr int kBlock = 240;
    const int blocks = 400;   // 2 s: 1.5 s of sound, 0.5 s of silence
    std::vector<float> out(static_cast<std::size_t>(blocks * kBlock)), sound(kBlock);
    MotorLevels levels {};
    levels[0] = 4;   // at most the rating: the guard leaves it alone for the whole run
    for (int b = 0; b < blocks; ++b) {
        for (int i = 0; i < kBlock; ++i) {
            const double t = static_cast<double>(b * kBlock + i) / kRate;
            sound[static_cast<std::size_t>(i)] = t < 1.5 ? static_cast<float>(0.2 + 0.3 * std::sin(6.283185307 * 150.0 * t) + 0.3 * std::sin(6.283185307 * 3000.0 * t)) : 0.0f;
        }
        r.setLevels(levels, b ? 0.005 : 0.0);
        float* ptr[1] {out.data() + b * kBlock};
        r.setSound(sound.data(), kBlock);
        r.render(ptr, kBlock);
    }
    // While the sound plays (after the filters settle): the peak is the level's, the carrier the
    // 150 Hz part (the 3 kHz and the DC are gone: zero crossings at 150 Hz).
    const auto m = test::measureFrames(out, 240);
    for (std::size_t f = 40; f < 290; ++f) {
        INFO("frame " << f);
        CHECK(m.level[f] == Approx(4.0).margin(0.25));
    }
    CHECK(measuredHz(out, 24000, 72000) == Approx(150.0).epsilon(0.01));
    // Silence: once the envelope has fallen below −80 dBFS the fixed 250 Hz carrier holds the level.
    CHECK(measuredHz(out, 86400, 96000) == Approx(250.0).epsilon(0.01));
    for (std::size_t f = 360; f < 400; ++f) CHECK(m.level[f] == Approx(4.0).margin(0.01));
    // A model that is not a voice coil cannot take a sound.
    p.model = TactorModel::Lra;
    CHECK_THROWS_AS(r.prepare(p, ChannelMap::identity(1), TactorGains {}, kRate), InputError);
}
