// Set lists (docs/STAGE.md): the file format and its errors, and cue changes rendered offline —
// no discontinuity above −60 dBFS at a switch (the largest sample-to-sample step around the
// switch against the largest in its neighbourhood), each cue's own sound after its switch.
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Core/Pose.h"
#include "Live/Session/RowClock.h"
#include "Live/Stage/SetList.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <string>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;
using namespace armadillo::tactile;
using namespace armadillo::live;

namespace {
constexpr double kFs = 48000.0;

const char* kFourCues = R"({"armadillo_setlist": 1,
 "cues": [
  {"name": "Intro", "scene": "theremin"},
  {"name": "Gestures", "scene": "sound-design", "mapping": "default", "profile": "alice"},
  {"name": "Wide", "scene": "theremin", "parameters": {"theremin.range": 24, "theremin.scale": "minor pentatonic"}},
  {"name": "Panel", "scene": "panel"}
 ]})";

/// 5 s: elevation rising −30° → +30°, azimuth and roll swaying (every cue has something to do).
CsvTable motion(double seconds = 5.0)
{
    std::string s = "t,elevation,azimuth,roll\n";
    for (int i = 0; i <= static_cast<int>(seconds * 200.0); ++i) {
        const double t = i / 200.0;
        s += std::to_string(t) + "," + std::to_string(-30.0 + 60.0 * t / seconds) + "," + std::to_string(10.0 * std::sin(t)) + "," +
             std::to_string(40.0 * std::sin(2.0 * t)) + "\n";
    }
    return CsvTable::parse(s, "sway.csv");
}

double maxStep(const std::vector<float>& x, std::size_t from, std::size_t to)
{
    double m = 0.0;
    for (std::size_t i = std::max<std::size_t>(from, 1); i < std::min(to, x.size()); ++i)
        m = std::max(m, std::fabs(static_cast<double>(x[i]) - static_cast<double>(x[i - 1])));
    return m;
}

double rms(const std::vector<float>& x, std::size_t from, std::size_t to)
{
    double s = 0.0;
    for (std::size_t i = from; i < to; ++i) s += static_cast<double>(x[i]) * static_cast<double>(x[i]);
    return std::sqrt(s / static_cast<double>(to - from));
}

/// The largest step within the switch's fade (plus a block) above the largest step in the
/// 200 ms before it and the 200 ms after the fade: what the switch itself added.
double switchExcess(const std::vector<float>& x, double at)
{
    const auto s = static_cast<std::size_t>(at * kFs);
    const auto fade = static_cast<std::size_t>(CuePlayer::kFadeSeconds * kFs) + 64;
    const double around = std::max(maxStep(x, s - 9600, s), maxStep(x, s + fade, s + fade + 9600));
    return std::max(0.0, maxStep(x, s, s + fade) - around);
}

std::string expectInputError(const std::string& text)
{
    try {
        const SetList l = parseSetList(text, "show.json");
        CuePlayer player(l, SceneConfig {});
    } catch (const InputError& e) {
        return e.what();
    }
    return "accepted";
}
} // namespace

TEST_CASE("set list: the file's cues, and every kind of error with its file, line and key", "[setlist]")
{
    const SetList list = parseSetList(kFourCues, "show.json");
    REQUIRE(list.cues.size() == 4);
    CHECK(list.cues[0].name == "Intro");
    CHECK(list.cues[1].scene == "sound-design");
    CHECK(list.cues[1].mapping == "default");
    CHECK(list.cues[1].profile == "alice");
    CHECK(list.cues[2].parameters == std::vector<std::string> {"theremin.range=24", "theremin.scale=minor pentatonic"});
    CHECK(list.cues[3].line == 6);

    CHECK(expectInputError("{\"armadillo_setlist\": 1, \"cues\": [}").find("show.json:1: ") == 0);
    CHECK(expectInputError("{\"armadillo_setlist\": 2, \"cues\": []}").find("unsupported version") != std::string::npos);
    CHECK(expectInputError("{\"cues\": [{\"scene\": \"theremin\"}]}").find("column 'armadillo_setlist': missing") != std::string::npos);
    CHECK(expectInputError("{\"armadillo_setlist\": 1, \"cues\": []}").find("column 'cues': needs a non-empty array") != std::string::npos);
    CHECK(expectInputError("{\"armadillo_setlist\": 1,\n \"cues\": [{\"scene\": \"theremin\"},\n {\"scene\": \"kazoo\"}]}") ==
          "show.json:3: column 'cues[1].scene': unknown scene 'kazoo' (scenes: monitor, theremin, cymbal, panel, sound-design, compass, braille, score, audio-touch, layered-keyboard, theremin-duo)");
    CHECK(expectInputError("{\"armadillo_setlist\": 1,\n \"cues\": [{\"scene\": \"theremin\",\n \"tempo\": 3}]}").find("show.json:3: column 'cues[0].tempo': unknown key") == 0);
    CHECK(expectInputError("{\"armadillo_setlist\": 1, \"cues\": [{\"name\": \"x\"}]}").find("column 'cues[0].scene': missing") != std::string::npos);
    CHECK(expectInputError("{\"armadillo_setlist\": 1, \"cues\": [{\"scene\": 3}]}").find("column 'cues[0].scene': must be a string") != std::string::npos);
    CHECK(expectInputError("{\"armadillo_setlist\": 1, \"cues\": [{\"scene\": \"theremin\", \"parameters\": {\"theremin.range\": [1]}}]}")
              .find("column 'cues[0].parameters.theremin.range': a parameter is a number") != std::string::npos);
    // A parameter the scene does not have, or out of range: refused when the cues are prepared,
    // still naming the set list's file and the cue's line.
    const std::string bad = expectInputError("{\"armadillo_setlist\": 1,\n \"cues\": [\n {\"scene\": \"theremin\", \"parameters\": {\"theremin.range\": 999}}]}");
    CHECK(bad.find("show.json:3: column 'cues[0].theremin.range': '999' is not a valid value") == 0);
    CHECK(expectInputError("{\"armadillo_setlist\": 1, \"cues\": [{\"scene\": \"theremin\", \"parameters\": {\"kazoo.size\": 1}}]}").find("no such parameter") !=
          std::string::npos);
    CHECK_THROWS_AS(loadSetList("/nonexistent/show.json"), IoError);
    CHECK(parseCueChange("2.5:3").t == 2.5);
    CHECK(parseCueChange("2.5:3").cue == 3);
    for (const char* badCue : {"2.5", "x:1", "1:-1", "-1:1", "1:1x", ":1"}) CHECK_THROWS_AS(parseCueChange(badCue), std::invalid_argument);
}

TEST_CASE("set list: four cues stepped offline switch with no discontinuity above -60 dBFS, each to its own sound", "[setlist][render]")
{
    const SetList list = parseSetList(kFourCues, "show.json");
    RenderSettings settings;
    const std::vector<CueChange> changes {{1.0, 1}, {2.0, 2}, {3.0, 3}, {4.0, 0}};
    const RenderResult r = renderOffline(motion(), settings, list, changes);
    const auto& x = r.audio.channels[0];
    const double minus60 = std::pow(10.0, -60.0 / 20.0);
    for (const auto& c : changes) {
        INFO("switch at " << c.t << " s to cue " << c.cue);
        const double excess = switchExcess(x, c.t);
        std::printf("set list: switch at %.1f s to cue %d: largest step above its neighbourhood %.2e (%.1f dBFS)\n", c.t, c.cue, excess,
                    20.0 * std::log10(std::max(excess, 1e-12)));
        CHECK(excess <= minus60);
    }
    // Each cue sounds as itself: the segment after its switch equals a render of that cue's
    // scene alone … (the same motion and time; only the fade-in differs)
    auto alone = [&](int cue) {
        RenderSettings s;
        s.engine.scene = list.cues[static_cast<std::size_t>(cue)].scene;
        s.engine.parameters = list.cues[static_cast<std::size_t>(cue)].parameters;
        return renderOffline(motion(), s).audio.channels[0];
    };
    const auto theremin = alone(0), wide = alone(2);
    CHECK(rms(x, 24000, 48000) > 0.01);
    CHECK(rms(x, 24000, 48000) == Approx(rms(theremin, 24000, 48000)).epsilon(1e-6));   // cue 0 before any change
    CHECK(rms(x, 2 * 48000 + 4800, 3 * 48000) > 0.01);                                   // cue 2 sounds
    // … and a hard cut between the same two cues would have clicked (the measure can fail).
    std::vector<float> cut(theremin.begin(), theremin.begin() + 2 * 48000);
    cut.insert(cut.end(), wide.begin() + 2 * 48000, wide.end());
    INFO("a hard cut's excess " << switchExcess(cut, 2.0));
    CHECK(switchExcess(cut, 2.0) > minus60);
    CHECK(r.controlUpdates == 1001);
}

TEST_CASE("set list: requests from any thread are clamped; next/previous step; panic reaches every cue", "[setlist]")
{
    const SetList list = parseSetList(kFourCues, "show.json");
    CuePlayer player(list, SceneConfig {});
    CHECK(player.cueCount() == 4);
    CHECK(player.current() == 0);
    player.next();
    player.next();
    CHECK(player.requested() == 2);
    player.previous();
    CHECK(player.requested() == 1);
    player.request(99);
    CHECK(player.requested() == 3);
    player.next();
    CHECK(player.requested() == 3);
    player.request(-5);
    CHECK(player.requested() == 0);
    player.request(2);
    ArmState arm;
    arm.valid = true;
    (void) player.control(arm, Transport {}, 0.005);
    CHECK(player.current() == 2);
    CHECK(player.changes() == 1u);
    player.panic();
    for (int c = 0; c < 4; ++c) CHECK(player.engine(c).panicked());
    player.resume();
    for (int c = 0; c < 4; ++c) CHECK_FALSE(player.engine(c).panicked());
}

TEST_CASE("set list: every cue feels the reader's touch profile (motor gains)", "[setlist][profile]")
{
    const SetList list = parseSetList(kFourCues, "show.json");
    // A profile that halves every motor's level (a reader who feels them all strongly).
    std::array<float, kMaxMotors> gains {};
    gains.fill(0.5f);
    CuePlayer plain(list, SceneConfig {}), profiled(list, SceneConfig {}, kGridMotors, false, gains);
    for (int c = 0; c < profiled.cueCount(); ++c) {
        CHECK(profiled.engine(c).config().motorGain == gains);
        CHECK(plain.engine(c).config().motorGain == TactileConfig::unitMotorGains());
    }
    std::array<long, kMaxMotors> plainSum {}, profiledSum {};   // level × steps per motor
    ArmState arm;
    arm.valid = true;
    for (int cue = 0; cue < 2; ++cue) {   // the theremin and the sound-design cue
        plain.request(cue);
        profiled.request(cue);
        for (int i = 0; i < 1000; ++i) {
            const double t = i * 0.005;
            arm.t = t;
            arm.features.pose = Pose {-30.0 + 12.0 * t, 40.0 * std::sin(t), 60.0 * std::sin(2.0 * t)};
            arm.q = poseToQuaternion(arm.features.pose);
            const MotorLevels a = plain.control(arm, Transport {}, 0.005);
            const MotorLevels b = profiled.control(arm, Transport {}, 0.005);
            for (std::size_t m = 0; m < kGridMotors; ++m) {
                plainSum[m] += a[m];
                profiledSum[m] += b[m];
            }
        }
    }
    int driven = 0;
    for (std::size_t m = 0; m < kGridMotors; ++m) {
        CAPTURE(m, plainSum[m], profiledSum[m]);
        if (plainSum[m] == 0) {
            CHECK(profiledSum[m] == 0);
            continue;
        }
        ++driven;
        CHECK(profiledSum[m] > 0);                // still felt …
        CHECK(profiledSum[m] < plainSum[m]);      // … at the profile's lower levels
    }
    CHECK(driven > 0);
}
