// `armadillo play --tactors jack` and `armadillo tactors test` as a user runs them: a JACK server
// of the test's own (dummy backend, a unique name through JACK_DEFAULT_SERVER), the tactor ports
// recorded by a JACK client of the test, compared with the tactile CSV of the same run.
#include "Cli/CliRun.h"
#include "Common/FreePort.h"
#include "Common/ScratchDir.h"
#include "Tactors/JackFixtures.h"
#include "Tactors/SignalMeasure.h"
#include "Core/AtomicFile.h"
#include "Core/Csv.h"
#include "Core/Wav.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <filesystem>
#include <sstream>

using namespace armadillo;
using namespace armadillo::core;

namespace {

std::string scratch(const std::string& name) { return (test::scratchDir("armadillo-tactors-cli") / name).string(); }

using cli::Run;

/// The real `armadillo` as a user runs it (Cli/CliRun.h), killed after `timeout` s.
Run runCli(const std::string& args, double timeout = 60.0) { return cli::runArmadilloWithin(timeout, args); }

/// The CSV's level of motor k at source time s (the row in force), and whether a change of more
/// than one level (a dither step of one level is within the tolerance) happens within [from, to].
struct Levels {
    std::vector<TactileRow> rows;
    int at(int k, double s) const
    {
        auto it = std::upper_bound(rows.begin(), rows.end(), s, [](double v, const TactileRow& r) { return v < r.t; });
        if (it == rows.begin()) return 0;
        return (it - 1)->levels[static_cast<std::size_t>(k)];
    }
    /// The largest level in force during [s, e).
    int maxOver(int k, double s, double e) const
    {
        int l = at(k, s);
        for (auto it = std::upper_bound(rows.begin(), rows.end(), s, [](double v, const TactileRow& r) { return v < r.t; });
             it != rows.end() && it->t < e; ++it)
            l = std::max<int>(l, it->levels[static_cast<std::size_t>(k)]);
        return l;
    }
    bool changeWithin(int k, double from, double to) const
    {
        int before = at(k, from);
        for (auto it = std::upper_bound(rows.begin(), rows.end(), from, [](double v, const TactileRow& r) { return v < r.t; });
             it != rows.end() && it->t <= to; ++it) {
            if (std::abs(it->levels[static_cast<std::size_t>(k)] - before) > 1) return true;
            before = it->levels[static_cast<std::size_t>(k)];
        }
        return false;
    }
};

} // namespace

TEST_CASE("tactors cli (done when): play --tactors jack --tactor-model lra: every channel's 5 ms peaks are the tactile CSV's levels / 15",
          "[tactors][cli][jack]")
{
    test::JackServer server(48000, 256, 2);
    REQUIRE(server.running());
    test::JackRecorder rec(9, 12.0);
    REQUIRE(rec.ok());
    const std::string csv = scratch("T.csv");
    const Run r = runCli("play --simulate --scene theremin --seconds 6 --tactors jack --tactor-model lra --tactile '" + csv +
                            "' --no-audio --tactor-connect rec:in_");
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.err.find("tactors on JACK client 'armadillo': ports tactor_1..tactor_9") != std::string::npos);
    CHECK(r.out.find("\"tactor_frames\":") != std::string::npos);
    Levels csvLevels;
    int motors = 0;
    csvLevels.rows = readTactile(CsvTable::read(csv), &motors);
    REQUIRE(motors == 9);
    REQUIRE(csvLevels.rows.size() > 1000);

    // The recording's 5 ms frames (15 × peak) per channel.
    constexpr double kFrame = 0.005;
    std::vector<std::vector<double>> rec15;
    for (int k = 0; k < 9; ++k) rec15.push_back(test::measureFrames(rec.channel(k), 240).level);
    const std::size_t frames = rec15[0].size();
    REQUIRE(frames > 1000);
    // The clocks: the CSV's t is the device link's steady-clock time since its start; a frame's
    // time is when its period reached the recorder (JackRecorder::frameTime, the same clock). Source time
    // s = frame time + offset: coarse from the first sound on either side, refined (1 ms steps,
    // ±60 ms) to the offset where most frames agree.
    std::vector<double> frameAt(frames);
    for (std::size_t f = 0; f < frames; ++f) frameAt[f] = rec.frameTime(f * 240);
    std::size_t firstFrame = frames;
    for (int k = 0; k < 9; ++k)
        for (std::size_t f = 0; f < frames; ++f)
            if (rec15[static_cast<std::size_t>(k)][f] > 0.5) {
                firstFrame = std::min(firstFrame, f);
                break;
            }
    double firstRow = -1.0;
    for (const TactileRow& row : csvLevels.rows)
        if (std::any_of(row.levels.begin(), row.levels.begin() + 9, [](std::uint8_t l) { return l > 0; })) {
            firstRow = row.t;
            break;
        }
    REQUIRE(firstFrame < frames);
    REQUIRE(firstRow >= 0.0);
    const double t0 = csvLevels.rows.front().t, t1 = csvLevels.rows.back().t;
    std::string failures;   // the first few, for the report
    const auto score = [&](double offset, bool report, int* checked, int* failed, int* nonzero) {
        int c = 0, bad = 0, nz = 0;
        for (int k = 0; k < 9; ++k)
            for (std::size_t f = 0; f < frames; ++f) {
                const double s = frameAt[f] + offset;
                if (s < t0 + 0.05 || s + kFrame > t1 - 0.05) continue;
                if (csvLevels.changeWithin(k, s - 0.030, s + kFrame + 0.010)) continue;   // 10 ms before to 30 ms after a change
                const int want = csvLevels.maxOver(k, s, s + kFrame);
                const double got = rec15[static_cast<std::size_t>(k)][f];
                ++c;
                nz += want > 0 ? 1 : 0;
                if (std::fabs(got - want) > 1.0 + 1e-3) {
                    ++bad;
                    if (report && bad <= 12)
                        failures += "channel " + std::to_string(k + 1) + " at s = " + std::to_string(s) + ": recorded " + std::to_string(got) +
                                    ", CSV " + std::to_string(want) + "\n";
                }
            }
        if (checked) *checked = c;
        if (failed) *failed = bad;
        if (nonzero) *nonzero = nz;
        return c - bad;
    };
    const double coarse = firstRow - frameAt[firstFrame];
    double best = coarse;
    int bestScore = -1;
    for (double o = coarse - 0.060; o <= coarse + 0.060; o += 0.001)
        if (const int sc = score(o, false, nullptr, nullptr, nullptr); sc > bestScore) {
            bestScore = sc;
            best = o;
        }
    int checked = 0, failed = 0, nonzero = 0;
    score(best, true, &checked, &failed, &nonzero);
    INFO(failures);
    INFO("offset " << best << " s; frames checked " << checked << " of " << 9 * frames << ", with a level " << nonzero << ", failed " << failed);
    CHECK(checked > static_cast<int>(9 * frames) / 2);   // the exemptions leave most of the run to check
    CHECK(nonzero > 200);                                // and levels were felt, not only silence
    CHECK(failed == 0);
    // Channel k is motor k: against another motor's column the same recording does not match.
    int crossBad = 0;
    for (int k = 0; k < 9; ++k)
        for (std::size_t f = 0; f < frames; ++f) {
            const double s = frameAt[f] + best;
            if (s < t0 + 0.05 || s + kFrame > t1 - 0.05) continue;
            const int other = (k + 4) % 9;
            if (std::fabs(rec15[static_cast<std::size_t>(k)][f] - csvLevels.maxOver(other, s, s + kFrame)) > 1.0 + 1e-3) ++crossBad;
        }
    CHECK(crossBad > 100);
}

TEST_CASE("tactors cli: errors name the cause with INTERFACES.md's exit codes, and nothing is written", "[tactors][cli][errors]")
{
    const std::string csv = scratch("T-err.csv");
    std::filesystem::remove(csv);
    const std::string base = "play --simulate --scene theremin --seconds 1 --no-audio --tactile '" + csv + "' ";
    ::setenv("JACK_DEFAULT_SERVER", ("armadillo_none_" + std::to_string(::getpid())).c_str(), 1);
    Run r = runCli(base + "--tactors jack");
    ::unsetenv("JACK_DEFAULT_SERVER");
    CHECK(r.code == 4);
    CHECK(r.err.find("not running") != std::string::npos);
    r = runCli(base + "--tactors hw:97");
    CHECK(r.code == 4);
    CHECK(r.err.find("hw:97") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(csv));
    // A gain out of range: the file and its line.
    const std::string gains = scratch("gains.json");
    writeFileAtomically(gains, "{\n  \"armadillo\": \"tactor-gains\",\n  \"version\": 1,\n  \"gain\": [1, 1,\n           1.2]\n}\n");
    r = runCli(base + "--tactors null --tactor-gain '" + gains + "'");
    CHECK(r.code == 3);
    CHECK(r.err.find(gains + ":5") != std::string::npos);
    CHECK(r.err.find("1.2") != std::string::npos);
    // Usage: an unknown model, a motor that does not exist, settings without an output.
    CHECK(runCli(base + "--tactors null --tactor-model piezo").code == 2);
    CHECK(runCli(base + "--tactors null --tactor-map 1-10").code == 2);
    CHECK(runCli(base + "--tactor-model lra").code == 2);
    CHECK(runCli(base + "--tactors null --tactor-connect x").code == 2);
    CHECK_FALSE(std::filesystem::exists(csv));
    // An ALSA device with fewer channels than the map: a 4-channel PCM of the test's own (ALSA's
    // multi plugin over the null PCM, in a configuration that includes the system's).
    const std::string conf = scratch("four.conf");
    writeFileAtomically(conf, "</usr/share/alsa/alsa.conf>\npcm.four {\n type multi\n slaves.a.pcm \"null\"\n slaves.a.channels 4\n"
                              " bindings.0 { slave a; channel 0; }\n bindings.1 { slave a; channel 1; }\n"
                              " bindings.2 { slave a; channel 2; }\n bindings.3 { slave a; channel 3; }\n}\n");
    ::setenv("ALSA_CONFIG_PATH", conf.c_str(), 1);
    r = runCli(base + "--tactors four");
    CHECK(r.code == 4);
    CHECK(r.err.find("sound card 'four': 4 output channels, 9 needed") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(csv));
    r = runCli(base + "--tactors four --tactor-map 2,4,6,8 --tactor-model voice-coil");
    ::unsetenv("ALSA_CONFIG_PATH");
    INFO(r.err);
    CHECK(r.code == 0);
    CHECK(r.err.find("tactors on ALSA 'four': 4 channels (motors 2,4,6,8)") != std::string::npos);
    CHECK(r.out.find("\"tactor_frames\":0") == std::string::npos);   // it played
    CHECK(r.out.find("\"tactor_limited\":0") != std::string::npos);  // the guard passed the engine's levels untouched
    std::filesystem::remove(csv);
    // A JACK server whose pattern matches fewer ports than the map has channels.
    test::JackServer server(48000, 256, 2);
    REQUIRE(server.running());
    r = runCli(base + "--tactors jack --tactor-connect system:playback_");
    CHECK(r.code == 4);
    CHECK(r.err.find("matches 2 input ports, the tactor map needs 9") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(csv));
    // With a map of two channels the same pattern is fine.
    r = runCli(base + "--tactors jack --tactor-connect system:playback_ --tactor-map 5,2");
    INFO(r.err);
    CHECK(r.code == 0);
}

TEST_CASE("tactors cli: tactors test buzzes each channel in turn and names it", "[tactors][cli][jack]")
{
    test::JackServer server(48000, 256, 2);
    REQUIRE(server.running());
    test::JackRecorder rec(4, 20.0);
    REQUIRE(rec.ok());
    const Run r = runCli("tactors test --tactors jack --tactor-connect rec:in_ --tactor-map 7,-,3,12 --back-motors --on 0.2 --gap 0.1");
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.out ==
          "channel 1 (tactor_1): motor m7, elbow, left\n"
          "channel 2 (tactor_2): silent (- in the map)\n"
          "channel 3 (tactor_3): motor m3, wrist, right\n"
          "channel 4 (tactor_4): motor m12, back 3\n");
    // On the recording: channels 1, 3, 4 buzz in that order, one at a time, at level 5; 2 never.
    std::vector<std::vector<double>> l;
    for (int k = 0; k < 4; ++k) l.push_back(test::measureFrames(rec.channel(k), 240).level);
    std::vector<double> firstOn(4, -1.0);
    for (std::size_t f = 0; f < l[0].size(); ++f) {
        int on = 0;
        for (int k = 0; k < 4; ++k)
            if (l[static_cast<std::size_t>(k)][f] > 0.5) {
                ++on;
                if (firstOn[static_cast<std::size_t>(k)] < 0) firstOn[static_cast<std::size_t>(k)] = static_cast<double>(f) * 0.005;
                CHECK(l[static_cast<std::size_t>(k)][f] < 5.0 + 1e-3);
            }
        REQUIRE(on <= 1);
    }
    CHECK(firstOn[1] < 0.0);
    REQUIRE(firstOn[0] >= 0.0);
    REQUIRE(firstOn[2] > firstOn[0]);
    REQUIRE(firstOn[3] > firstOn[2]);
    CHECK(firstOn[2] - firstOn[0] == Approx(0.3).margin(0.03));   // on + gap (the silent channel takes no time)
}

TEST_CASE("tactors cli: play --back-motors lets the map name motors 10..12 and logs them", "[tactors][cli][back]")
{
    const std::string csv = scratch("T-back.csv");
    std::filesystem::remove(csv);
    const std::string base = "play --simulate --scene theremin --seconds 1 --no-audio --tactile '" + csv + "' --tactors null ";
    // Without --back-motors a map naming m10 is bad usage, and nothing is written.
    Run r = runCli(base + "--tactor-map 1-12");
    CHECK(r.code == 2);
    CHECK(r.err.find("--tactor-map") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(csv));
    r = runCli(base + "--tactor-map 1-12 --back-motors");
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.err.find("12 channels") != std::string::npos);
    std::ifstream in(csv);
    std::string header;
    REQUIRE(std::getline(in, header));
    CHECK(header.find("m12") != std::string::npos);   // the tactile CSV carries the back motors
    std::filesystem::remove(csv);
}

TEST_CASE("tactors cli: render --tactor-sound: the voice coils carry the cymbal's own sound, band-limited", "[tactors][cli][sound]")
{
    // Raise the arm, strike down through horizontal, let it ring (the cymbal's strike).
    const std::string motion = scratch("strike.csv");
    {
        std::string text = "t,elevation,azimuth,roll\n";
        for (int i = 0; i <= 600; ++i) {
            const double t = i / 200.0;
            const double el = t < 0.5 ? 40.0 : (t < 0.65 ? 40.0 - (t - 0.5) / 0.15 * 70.0 : -30.0);
            text += std::to_string(t) + "," + std::to_string(el) + ",0,0\n";
        }
        writeFileAtomically(motion, text);
    }
    const std::string audio = scratch("cymbal.wav"), plain = scratch("plain.wav"), sound = scratch("sound.wav");
    const std::string base = "render --scene cymbal --seed 3 --motion '" + motion + "' --float --out '" + audio + "' --tactor-model voice-coil --tactile-wav ";
    REQUIRE(runCli(base + "'" + plain + "'").code == 0);
    Run r = runCli(base + "'" + sound + "' --tactor-sound");
    INFO(r.err);
    REQUIRE(r.code == 0);
    const AudioBuffer a = readWav(audio), p = readWav(plain), s = readWav(sound);
    REQUIRE(s.channels.size() == 9);
    // The cymbal's sound, mono, band-passed here by a test-side filter (one-pole 40 Hz high-pass
    // and two one-pole 400 Hz low-passes): what the voice coil should carry, up to its scale.
    std::vector<double> ref(a.frames());
    double hp = 0.0, prev = 0.0, lp1 = 0.0, lp2 = 0.0;
    const double kh = std::exp(-2.0 * M_PI * 40.0 / 48000.0), kl = 1.0 - std::exp(-2.0 * M_PI * 400.0 / 48000.0);
    for (std::size_t i = 0; i < a.frames(); ++i) {
        const double x = 0.5 * (double(a.channels[0][i]) + double(a.channels[1][i]));
        hp = kh * (hp + x - prev);
        prev = x;
        lp1 += (hp - lp1) * kl;
        lp2 += (lp1 - lp2) * kl;
        ref[i] = lp2;
    }
    // The busiest channel after the strike, over 0.3 s of its ring.
    std::size_t best = 0;
    double bestEnergy = 0.0;
    const std::size_t from = static_cast<std::size_t>(0.8 * 48000), to = static_cast<std::size_t>(1.1 * 48000);
    REQUIRE(s.frames() >= to);
    for (std::size_t c = 0; c < 9; ++c) {
        double e = 0.0;
        for (std::size_t i = from; i < to; ++i) e += double(s.channels[c][i]) * double(s.channels[c][i]);
        if (e > bestEnergy) { bestEnergy = e; best = c; }
    }
    REQUIRE(bestEnergy > 0.0);
    const auto correlation = [&](const std::vector<float>& x) {
        double xy = 0.0, xx = 0.0, yy = 0.0;
        for (std::size_t i = from; i < to; ++i) {
            xy += double(x[i]) * ref[i];
            xx += double(x[i]) * double(x[i]);
            yy += ref[i] * ref[i];
        }
        return xy / std::sqrt(xx * yy + 1e-30);
    };
    const double withSound = correlation(s.channels[best]), withSine = correlation(p.channels[best]);
    INFO("channel " << best + 1 << ": correlation with the band-passed cymbal " << withSound << " (the fixed carrier: " << withSine << ")");
    CHECK(withSound > 0.6);
    CHECK(std::abs(withSine) < 0.3);
    // The level law holds: no sample beyond 15/15, and the peak per 5 ms frame never above the fixed carrier's.
    for (std::size_t i = from; i < to; i += 240) {
        float ps = 0.0f, pp = 0.0f;
        for (std::size_t k = i; k < i + 240; ++k) {
            ps = std::max(ps, std::abs(s.channels[best][k]));
            pp = std::max(pp, std::abs(p.channels[best][k]));
        }
        CHECK(ps <= pp + 1e-4f);
    }
    // Usage: the sound goes to a voice coil only, and needs the scene's audio.
    CHECK(runCli("render --scene cymbal --motion '" + motion + "' --tactile-wav '" + sound + "' --tactor-model lra --tactor-sound").code == 2);
    CHECK(runCli("play --simulate --scene cymbal --seconds 1 --no-audio --tactors null --tactor-model voice-coil --tactor-sound").code == 2);
}

TEST_CASE("tactors cli: navigate drives a tactor rig beside the arm (a phone's motion and positions over OSC)", "[tactors][cli][navigate]")
{
    const std::string route = scratch("walk.json");
    writeFileAtomically(route, R"([{"lat": 48.1492, "lon": 11.5678, "name": "Start"}, {"lat": 48.1497396, "lon": 11.5678, "name": "Entrance"}])");
    const std::string csv = scratch("T-nav.csv");
    std::filesystem::remove(csv);
    const int port = test::freeUdpPort();
    Run r = runCli("navigate --route '" + route + "' --osc-in " + std::to_string(port) + " --tactors null --tactor-model lra --seconds 1 --tactile '" + csv + "'");
    INFO(r.err);
    CHECK(r.code == 0);
    CHECK(r.err.find("navigate: tactors on ALSA 'null'") != std::string::npos);
    CHECK(std::filesystem::exists(csv));
    // The tactor options need --tactors, and the offline walker has no live output.
    CHECK(runCli("navigate --route '" + route + "' --osc-in " + std::to_string(port) + " --tactor-model lra --seconds 1").code == 2);
    CHECK(runCli("navigate --route '" + route + "' --simulate-walk --simulate --tactors null --seconds 1").code == 2);
}
