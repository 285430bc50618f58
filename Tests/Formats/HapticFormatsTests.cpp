// Haptic files in and out (docs/FORMATS.md): what an imported file plays through the engine,
// against levels computed here from each format's definition.
#include "Common/ScratchDir.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Core/Json.h"
#include "Core/Wav.h"
#include "Engine/RenderSettings.h"
#include "Live/Session/RowClock.h"
#include "Formats/ScoreImport.h"
#include "Tactile/Bounds.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <random>
#include <unistd.h>

using namespace armadillo;
using namespace armadillo::tactile;
using namespace armadillo::core;
using namespace armadillo::engine;
using armadillo::live::renderOffline;
using namespace armadillo::formats;

namespace {
std::string tempPath(const std::string& name)
{
    return (test::scratchDir("armadillo-formats") / name).string();
}

CsvTable stillMotion(double seconds)
{
    std::string s = "t,elevation,azimuth,roll\n";
    for (int i = 0; i <= static_cast<int>(std::lround(seconds * 200.0)); ++i) s += std::to_string(i / 200.0) + ",0,0,0\n";
    return CsvTable::parse(s, "still.csv");
}

std::vector<TactileRow> play(const std::string& scorePath, double seconds)
{
    RenderSettings settings;
    settings.engine.scene = "score";
    settings.engine.sceneConfig.score = scorePath;
    return renderOffline(stillMotion(seconds), settings).tactile;
}

/// Levels 0..15 for 9 motors per 5 ms frame: random steps within the safety budget (at most the
/// rated level, with short bursts above it), held 1..40 frames.
std::vector<std::array<int, 9>> randomLevels(std::size_t frames, std::uint64_t seed)
{
    std::mt19937_64 rng(seed);
    std::vector<std::array<int, 9>> v(frames);
    for (int m = 0; m < 9; ++m) {
        std::size_t f = 0;
        while (f < frames) {
            const std::size_t hold = 1 + rng() % 40;
            const int level = (rng() % 10 == 0) ? static_cast<int>(6 + rng() % 6) : static_cast<int>(rng() % 6);
            for (std::size_t k = 0; k < (level > 5 ? std::min<std::size_t>(hold, 20) : hold) && f < frames; ++k) v[f++][static_cast<std::size_t>(m)] = level;
            for (std::size_t k = 0; k < 4 && f < frames && level > 5; ++k) v[f++][static_cast<std::size_t>(m)] = 0;   // a rest after a burst
        }
    }
    return v;
}
} // namespace

TEST_CASE("haptic wav: a 9-channel WAV imported and rendered back gives its levels within one step at every packet", "[formats][wav]")
{
    // The Syntacts convention, written here: channel k = motor k, a 150 Hz sine (44.1 kHz, float)
    // at amplitude level/15 over each 5 ms frame.
    const std::size_t frames = 1200;   // 6 s
    const auto levels = randomLevels(frames, 17);
    AudioBuffer wav;
    wav.sampleRate = 44100.0;
    const auto samples = static_cast<std::size_t>(static_cast<double>(frames) * 0.005 * wav.sampleRate);
    wav.channels.assign(9, std::vector<float>(samples));
    for (std::size_t i = 0; i < samples; ++i) {
        const double t = static_cast<double>(i) / wav.sampleRate;
        const double carrier = std::sin(2.0 * 3.14159265358979 * 150.0 * t);
        const auto f = std::min(frames - 1, static_cast<std::size_t>(t / 0.005));   // 220.5 samples a frame at 44.1 kHz
        for (int m = 0; m < 9; ++m) wav.channels[static_cast<std::size_t>(m)][i] = static_cast<float>(levels[f][static_cast<std::size_t>(m)] / 15.0 * carrier);
    }
    const std::string in = tempPath("tactile-in.wav");
    writeWav(in, wav, true);
    const ImportedScore s = importScoreFile(in);
    CHECK(s.report.format == "wav");
    const auto rows = play(in, 6.0);   // --score takes the WAV directly
    REQUIRE(rows.size() >= frames);
    int worst = 0;
    for (std::size_t i = 0; i < frames; ++i)
        for (int m = 0; m < 9; ++m) {
            const int d = std::abs(rows[i].levels[static_cast<std::size_t>(m)] - levels[i][static_cast<std::size_t>(m)]);
            worst = std::max(worst, d);
            if (d > 1) {
                CAPTURE(i, m, rows[i].levels[static_cast<std::size_t>(m)], levels[i][static_cast<std::size_t>(m)]);
                CHECK(d <= 1);
            }
        }
    std::printf("haptic wav: %zu packets x 9 motors, largest difference %d level(s)\n", frames, worst);
    CHECK(worst <= 1);

    // And out again: the rendered rows as a tactile WAV carry each row's level as the peak of
    // its 5 ms (measured here on the written file, not through the importer).
    const std::string out = tempPath("tactile-out.wav");
    writeTactileWav(out, rows, 9, 48000.0);
    const AudioBuffer back = readWav(out);
    REQUIRE(back.channels.size() == 9);
    for (std::size_t i = 0; i + 1 < rows.size(); ++i)
        for (int m = 0; m < 9; ++m) {
            float peak = 0.0f;
            for (std::size_t j = i * 240; j < (i + 1) * 240 && j < back.frames(); ++j) peak = std::max(peak, std::fabs(back.channels[static_cast<std::size_t>(m)][j]));
            REQUIRE(std::lround(peak * 15.0f) == rows[i].levels[static_cast<std::size_t>(m)]);
        }
}

TEST_CASE("haptic wav: wrong channel counts and non-audio are refused", "[formats][wav]")
{
    AudioBuffer a;
    a.channels.assign(17, std::vector<float>(100, 0.1f));
    const std::string p = tempPath("seventeen.wav");
    writeWav(p, a);
    CHECK_THROWS_AS(importScoreFile(p), InputError);
    const std::string junk = tempPath("junk.wav");
    writeWav(tempPath("ok.wav"), AudioBuffer {48000.0, {std::vector<float>(10, 0.0f)}});
    { std::FILE* f = std::fopen(junk.c_str(), "wb"); std::fputs("not audio", f); std::fclose(f); }
    CHECK_THROWS_AS(importScoreFile(junk), InputError);
    CHECK_THROWS_AS(importScoreFile(tempPath("missing.wav")), InputError);
    CHECK_THROWS_AS(importScoreFile(tempPath("x.tact")), InputError);
}

TEST_CASE("ahap: a transient and a continuous event with an intensity curve give the documented levels", "[formats][ahap]")
{
    // Apple's keys ("Representing haptic patterns in AHAP files"): a transient at 0.1 s,
    // intensity 0.6; a continuous event 0.3..1.3 s, intensity 0.3, under a HapticIntensityControl
    // curve starting at 0.3 s through (0, 0.2), (0.5, 1.0), (1.0, 0.4) (times from the curve's).
    const std::string ahap = R"({
      "Version": 1.0,
      "Metadata": {"Project": "test"},
      "Pattern": [
        {"Event": {"Time": 0.1, "EventType": "HapticTransient",
                   "EventParameters": [{"ParameterID": "HapticIntensity", "ParameterValue": 0.6},
                                       {"ParameterID": "HapticSharpness", "ParameterValue": 0.9}]}},
        {"Event": {"Time": 0.3, "EventType": "HapticContinuous", "EventDuration": 1.0,
                   "EventParameters": [{"ParameterID": "HapticIntensity", "ParameterValue": 0.3}]}},
        {"ParameterCurve": {"ParameterID": "HapticIntensityControl", "Time": 0.3,
                            "ParameterCurveControlPoints": [{"Time": 0.0, "ParameterValue": 0.2},
                                                            {"Time": 0.5, "ParameterValue": 1.0},
                                                            {"Time": 1.0, "ParameterValue": 0.4}]}}
      ]
    })";
    const std::string path = tempPath("effect.ahap");
    { std::FILE* f = std::fopen(path.c_str(), "wb"); std::fputs(ahap.c_str(), f); std::fclose(f); }
    HapticImportOptions o;
    const auto expected = [&](double t) {
        // Level = 15 × intensity × intensity control (multiplicative, linear between points).
        if (t >= 0.1 && t < 0.1 + o.transientSeconds) return 15.0 * 0.6;   // the curve starts at 0.3: control 1 before
        if (t < 0.3 || t >= 1.3) return 0.0;
        const double u = t - 0.3;
        const double c = u <= 0.5 ? 0.2 + (1.0 - 0.2) * u / 0.5 : 1.0 + (0.4 - 1.0) * (u - 0.5) / 0.5;
        return 15.0 * 0.3 * c;
    };
    const auto rows = play(path, 1.6);
    int checked = 0;
    for (const auto& r : rows) {
        // Skip the packets at an edge (the level changes inside them) and sample the rest.
        if (std::fabs(r.t - 0.1) < 0.006 || std::fabs(r.t - 0.13) < 0.006 || std::fabs(r.t - 0.3) < 0.006 || std::fabs(r.t - 1.3) < 0.006) continue;
        const double want = expected(r.t);
        for (int m = 0; m < 9; ++m) {
            CAPTURE(r.t, m, want);
            CHECK(std::fabs(r.levels[static_cast<std::size_t>(m)] - want) <= 1.0);   // dithered: the neighbouring integers
        }
        ++checked;
    }
    CHECK(checked > 250);
    // The mean over the rising half of the curve equals the definition's mean (dithering is exact on average).
    double sum = 0.0, want = 0.0;
    int n = 0;
    for (const auto& r : rows)
        if (r.t >= 0.35 && r.t < 0.75) {
            sum += r.levels[0];
            want += expected(r.t);
            ++n;
        }
    CHECK(sum / n == Approx(want / n).margin(0.15));

    // One actuator on a chosen set: only those motors.
    o.motors = 0;
    REQUIRE(parseMotorSet("wrist", o.motors));
    const ImportedScore wrist = importAhap(ahap, "effect.ahap", o);
    for (const auto& note : wrist.score.notes) CHECK(note.motors == o.motors);
}

TEST_CASE("ahap: malformed patterns are refused naming the line", "[formats][ahap]")
{
    HapticImportOptions o;
    CHECK_THROWS_AS(importAhap("[1,2]", "a.ahap", o), InputError);
    CHECK_THROWS_AS(importAhap(R"({"Version": 1})", "a.ahap", o), InputError);
    CHECK_THROWS_AS(importAhap(R"({"Pattern": [{"Event": {"Time": 0, "EventType": "HapticContinuous"}}]})", "a.ahap", o), InputError);
    CHECK_THROWS_AS(importAhap(R"({"Pattern": [{"Event": {"Time": 0, "EventType": "Rumble"}}]})", "a.ahap", o), InputError);
    CHECK_THROWS_AS(importAhap(R"({"Pattern": [{"Event": {"Time": "soon", "EventType": "HapticTransient"}}]})", "a.ahap", o), InputError);
    CHECK_THROWS_AS(importAhap(R"({"Pattern": [{"Event": {"Time": 0, "EventType": "AudioCustom"}}]})", "a.ahap", o), InputError);
    try {
        (void) importAhap("{\n\"Pattern\": [\n{\"Event\": {\"Time\": -1, \"EventType\": \"HapticTransient\"}}]}", "a.ahap", o);
        FAIL("accepted");
    } catch (const InputError& e) {
        CHECK(e.line() == 3);
    }
}

TEST_CASE("meta .haptic: the amplitude envelope and an emphasis give the documented levels", "[formats][haptic]")
{
    // The Lofelt data model v1 (Meta Haptics Studio): amplitude breakpoints, linear between them;
    // an emphasis held emphasisSeconds at 15 × its amplitude.
    const std::string haptic = R"({
      "version": {"major": 1, "minor": 0, "patch": 0},
      "metadata": {"editor": "test"},
      "signals": {"continuous": {"envelopes": {
        "amplitude": [{"time": 0.0, "amplitude": 0.1}, {"time": 0.4, "amplitude": 0.3},
                      {"time": 0.6, "amplitude": 0.3, "emphasis": {"amplitude": 0.8, "frequency": 0.5}},
                      {"time": 1.0, "amplitude": 0.0}],
        "frequency": [{"time": 0.0, "frequency": 0.5}]}}}
    })";
    const std::string path = tempPath("effect.haptic");
    { std::FILE* f = std::fopen(path.c_str(), "wb"); std::fputs(haptic.c_str(), f); std::fclose(f); }
    HapticImportOptions o;
    const auto expected = [&](double t) {
        if (t >= 0.6 && t < 0.6 + o.emphasisSeconds) return 15.0 * 0.8;
        if (t < 0.4) return 15.0 * (0.1 + 0.2 * t / 0.4);
        if (t < 0.6) return 15.0 * 0.3;
        if (t < 1.0) return 15.0 * 0.3 * (1.0 - (t - 0.6) / 0.4);
        return 0.0;
    };
    const auto rows = play(path, 1.2);
    for (const auto& r : rows) {
        if (std::fabs(r.t - 0.6) < 0.006 || std::fabs(r.t - 0.63) < 0.006 || r.t < 0.006) continue;
        CAPTURE(r.t);
        CHECK(std::fabs(r.levels[4] - expected(r.t)) <= 1.0);
    }
    const ImportedScore s = importScoreFile(path);
    CHECK_FALSE(s.report.warnings.empty());   // the frequency envelope has no counterpart
    HapticImportOptions bad;
    CHECK_THROWS_AS(importMetaHaptic(R"({"version": {"major": 2}, "signals": {}})", "x.haptic", bad), InputError);
    CHECK_THROWS_AS(importMetaHaptic(R"({"version": {"major": 1}, "signals": {"continuous": {"envelopes": {"amplitude": []}}}})", "x.haptic", bad), InputError);
    CHECK_THROWS_AS(importMetaHaptic(R"({"version": {"major": 1}, "signals": {"continuous": {"envelopes": {"amplitude": [{"time": 0, "amplitude": 1.5}]}}}})", "x.haptic", bad), InputError);
    CHECK_THROWS_AS(importMetaHaptic(R"({"version": {"major": 1}, "signals": {"continuous": {"envelopes": {"amplitude": [{"time": 1, "amplitude": 0.5}, {"time": 0.5, "amplitude": 0.5}]}}}})", "x.haptic", bad), InputError);
    CHECK_THROWS_AS(importMetaHaptic(R"({"version": {"major": 1}, "signals": {"continuous": {"envelopes": {"amplitude": [{"time": 0, "amplitude": 0.5, "emphasis": {"amplitude": 0.2, "frequency": 0}}]}}}})", "x.haptic", bad), InputError);
}

namespace {
/// Packets every 5 ms from t = 2 s (a render's rows need not start at 0), random levels, and the
/// all-off row a render ends with.
std::vector<TactileRow> randomRows(std::size_t frames, std::uint64_t seed)
{
    const auto levels = randomLevels(frames, seed);
    std::vector<TactileRow> rows(frames + 1);
    for (std::size_t i = 0; i <= frames; ++i) {
        rows[i].t = 2.0 + 0.005 * static_cast<double>(i);
        if (i < frames)
            for (std::size_t m = 0; m < 9; ++m) rows[i].levels[m] = static_cast<std::uint8_t>(levels[i][m]);
    }
    return rows;
}

/// The one actuator's level the files must carry: the loudest of `motors` at each packet.
int loudest(const TactileRow& row, std::uint16_t motors)
{
    int l = 0;
    for (std::size_t m = 0; m < 9; ++m)
        if (motors & (1u << m)) l = std::max(l, static_cast<int>(row.levels[m]));
    return l;
}

void writeText(const std::string& path, const std::string& text)
{
    std::FILE* f = std::fopen(path.c_str(), "wb");
    REQUIRE(f);
    std::fwrite(text.data(), 1, text.size(), f);
    std::fclose(f);
}

/// Writes an exported file, imports it onto motor 5 alone, plays the score and returns the largest
/// difference from the loudest of motor 5 in `rows` over the first 1200 packets (each beyond one
/// step is reported).
int roundTripWorst(const std::vector<TactileRow>& rows, const std::string& file, const std::string& text)
{
    const std::uint16_t one = 0x0010;
    const std::string path = tempPath(file);
    writeText(path, text);
    HapticImportOptions o;
    o.motors = one;
    const ImportedScore s = importScoreFile(path, {}, o);
    const std::string scorePath = tempPath(file + ".score");
    writeText(scorePath, s.text);
    const auto back = play(scorePath, 6.0);
    REQUIRE(back.size() >= 1200);
    int worst = 0;
    for (std::size_t i = 0; i < 1200; ++i) {
        const int d = std::abs(static_cast<int>(back[i].levels[4]) - loudest(rows[i], one));
        if (d > 1) {
            CAPTURE(i, static_cast<int>(back[i].levels[4]), loudest(rows[i], one));
            CHECK(d <= 1);
        }
        worst = std::max(worst, d);
    }
    return worst;
}
} // namespace

TEST_CASE("ahap export: the file says the loudest of the chosen motors at every packet, and imports back to it", "[formats][ahap][export]")
{
    const auto rows = randomRows(1200, 23);
    const std::uint16_t three = 0x0007;   // motors 1,2,3: three motors collapse into the one actuator
    const std::string text = exportAhap(rows, three, "random");
    // Read with Apple's definition ("Representing haptic patterns in AHAP files"): a Pattern of
    // Events; a HapticContinuous event lasts EventDuration (at most 30 s) from Time, at
    // HapticIntensity 0..1; with no intensity control, the actuator's level is 15 x intensity.
    const armadillo::core::JsonValue root = armadillo::core::parseJson(text, "export.ahap");
    REQUIRE(root.find("Version"));
    CHECK(root.find("Version")->number == 1.0);
    const armadillo::core::JsonValue* pattern = root.find("Pattern");
    REQUIRE(pattern);
    REQUIRE(pattern->kind == armadillo::core::JsonValue::Kind::Array);
    struct Ev { double time, duration, intensity; };
    std::vector<Ev> events;
    for (const auto& entry : pattern->array) {
        const armadillo::core::JsonValue* e = entry.find("Event");
        REQUIRE(e);
        REQUIRE(e->find("EventType")->string == "HapticContinuous");
        const armadillo::core::JsonValue* params = e->find("EventParameters");
        REQUIRE(params);
        REQUIRE(params->array.size() == 1);
        REQUIRE(params->array[0].find("ParameterID")->string == "HapticIntensity");
        events.push_back({e->find("Time")->number, e->find("EventDuration")->number, params->array[0].find("ParameterValue")->number});
        CHECK(events.back().duration > 0.0);
        CHECK(events.back().duration <= 30.0);
        CHECK(events.back().intensity > 0.0);
        CHECK(events.back().intensity <= 1.0);
    }
    REQUIRE(!events.empty());
    for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
        const double t = rows[i].t - rows.front().t + 0.0025;   // the middle of packet i's 5 ms
        double level = 0.0;
        int covering = 0;
        for (const Ev& e : events)
            if (t >= e.time && t < e.time + e.duration) {
                level = 15.0 * e.intensity;
                ++covering;
            }
        REQUIRE(covering <= 1);   // one actuator, one event at a time
        REQUIRE(std::lround(level) == loudest(rows[i], three));
    }

    // Imported back onto one motor (--motors 5) and played: the same level at every packet
    // (within one step), the file's timing kept.
    const std::uint16_t one = 0x0010;
    const int worst = roundTripWorst(rows, "export.ahap", exportAhap(rows, one, "random"));
    std::printf("ahap export -> import: 1200 packets, largest difference %d level(s)\n", worst);
    CHECK(worst <= 1);
}

TEST_CASE("meta .haptic export: the amplitude envelope steps through the chosen motors' levels and imports back to them", "[formats][haptic][export]")
{
    const auto rows = randomRows(1200, 31);
    const std::uint16_t elbow = 0x01C0;   // motors 7,8,9
    const std::string text = exportMetaHaptic(rows, elbow, "random");
    // Read with the Lofelt data model v1 (NiceVibrations core/datamodel/src/v1.rs): version
    // {major 1}; signals.continuous.envelopes.amplitude: breakpoints {time, amplitude 0..1},
    // times never decreasing, the amplitude linear between consecutive breakpoints.
    const armadillo::core::JsonValue root = armadillo::core::parseJson(text, "export.haptic");
    REQUIRE(root.find("version"));
    CHECK(root.find("version")->find("major")->number == 1.0);
    const armadillo::core::JsonValue* amplitude = root.find("signals")->find("continuous")->find("envelopes")->find("amplitude");
    REQUIRE(amplitude);
    std::vector<std::pair<double, double>> points;
    for (const auto& p : amplitude->array) {
        points.emplace_back(p.find("time")->number, p.find("amplitude")->number);
        CHECK(points.back().second >= 0.0);
        CHECK(points.back().second <= 1.0);
        if (points.size() > 1) REQUIRE(points.back().first >= points[points.size() - 2].first);
    }
    REQUIRE(points.size() >= 2);
    const auto envelope = [&](double t) {
        for (std::size_t i = 0; i + 1 < points.size(); ++i)
            if (t >= points[i].first && t < points[i + 1].first)
                return points[i].second + (points[i + 1].second - points[i].second) * (t - points[i].first) / (points[i + 1].first - points[i].first);
        return 0.0;
    };
    for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
        const double t = rows[i].t - rows.front().t + 0.0025;
        REQUIRE(std::lround(15.0 * envelope(t)) == loudest(rows[i], elbow));
    }

    const int worst = roundTripWorst(rows, "export.haptic", exportMetaHaptic(rows, 0x0010, "random"));
    std::printf(".haptic export -> import: 1200 packets, largest difference %d level(s)\n", worst);
    CHECK(worst <= 1);
}

TEST_CASE("haptic export: no levels give an empty pattern; a last row that is not all-off is held one packet", "[formats][export]")
{
    std::vector<TactileRow> rows(2);
    rows[0].t = 0.0;
    rows[1].t = 0.005;
    CHECK(actuatorRuns(rows, 0x01FF).empty());
    rows[1].levels[0] = 7;
    const auto runs = actuatorRuns(rows, 0x01FF);
    REQUIRE(runs.size() == 1);
    CHECK(runs[0].start == Approx(0.005));
    CHECK(runs[0].duration == Approx(0.005));
    CHECK(runs[0].level == 7);
    CHECK(actuatorRuns(rows, 0x0002).empty());   // motor 2 is silent
}

// ---- bHaptics .tact ----------------------------------------------------------------------
// The structure is that of bHaptics Designer's exports (docs/FORMATS.md, "bHaptics .tact");
// the expected levels follow the rule documented there, computed here on their own:
// Tactosy index i → our row 0 (i < 3) or 2 (i ≥ 3), column i mod 3 (mirrored for ForearmL);
// level = 15 × intensity; FADE_OUT falls linearly to 0 at endTime; a path point at (x, y) gives
// motor (row, col) 15 × intensity × max(0, 1 − |2x − col|) × max(0, 1 − |2y − row|).

TEST_CASE("tact: a dot-mode and a path-mode effect give the documented motor levels over time", "[formats][tact]")
{
    // Track 1: a dot effect at 100 ms (length 600): index 1 at 0.3 for 100..400 ms (below the rated level: the safety stage leaves it) of it (NONE),
    // index 5 at 0.8 fading out over 0..300 ms of it. Track 2: a path effect at 1000 ms (length
    // 400): from (0, 0) to (1, 0) at intensity 0.8 over 400 ms. A vest effect is left out.
    const std::string tact = R"({"project":{"name":"test","layout":{"name":"Tactosy2","type":"Tactosy2","layouts":{}},
      "tracks":[
       {"enable":true,"effects":[
        {"name":"dots","startTime":100,"offsetTime":600,"modes":{
          "ForearmR":{"mode":"DOT_MODE","dotMode":{"dotConnected":false,"feedback":[
             {"startTime":100,"endTime":400,"playbackType":"NONE","pointList":[{"index":1,"intensity":0.3}]},
             {"startTime":0,"endTime":300,"playbackType":"FADE_OUT","pointList":[{"index":5,"intensity":"0.800"}]}]},
           "pathMode":{"feedback":[]}},
          "VestFront":{"mode":"DOT_MODE","dotMode":{"feedback":[{"startTime":0,"endTime":300,"playbackType":"NONE","pointList":[{"index":3,"intensity":1}]}]},
           "pathMode":{"feedback":[]}}}}]},
       {"enable":true,"effects":[
        {"name":"path","startTime":1000,"offsetTime":400,"modes":{
          "ForearmR":{"mode":"PATH_MODE","dotMode":{"feedback":[]},"pathMode":{"feedback":[
             {"movingPattern":"CONST_SPEED","playbackType":"NONE","visible":true,
              "pointList":[{"time":0,"x":0,"y":0,"intensity":0.8},{"time":400,"x":1,"y":0,"intensity":0.8}]}]}}}}]},
       {"enable":false,"effects":[
        {"name":"disabled","startTime":0,"offsetTime":2000,"modes":{
          "ForearmR":{"mode":"DOT_MODE","dotMode":{"feedback":[{"startTime":0,"endTime":2000,"playbackType":"NONE","pointList":[{"index":0,"intensity":1}]}]},
           "pathMode":{"feedback":[]}}}}]}]},
      "durationMillis":0,"intervalMillis":20,"size":20})";
    const auto expected = [](double t, int motor) {
        double l = 0.0;
        if (motor == 1 && t >= 0.2 && t < 0.5) l = std::max(l, 15.0 * 0.3);           // index 1 → wrist, middle column
        if (motor == 8 && t >= 0.1 && t < 0.4) l = std::max(l, 15.0 * 0.8 * (1.0 - (t - 0.1) / 0.3));   // index 5 → elbow, right
        if (t >= 1.0 && t < 1.4 && motor < 3) {                                       // the path along the wrist row
            const double x = (t - 1.0) / 0.4;
            l = std::max(l, 15.0 * 0.8 * std::max(0.0, 1.0 - std::fabs(2.0 * x - motor)));
        }
        return l;
    };
    const std::string path = tempPath("effect.tact");
    writeText(path, tact);
    const ImportedScore s = importScoreFile(path);
    CHECK(s.report.format == "tact");
    REQUIRE(s.report.warnings.size() == 1);   // the vest effect
    CHECK(s.report.warnings[0].find("VestFront") != std::string::npos);
    const auto rows = play(path, 1.7);        // --score takes the .tact directly
    int checked = 0;
    for (const auto& r : rows) {
        // Skip the packets at an edge (the level changes inside them).
        bool edge = false;
        for (const double e : {0.1, 0.2, 0.4, 0.5, 1.0, 1.4})
            if (std::fabs(r.t - e) < 0.006) edge = true;
        if (edge) continue;
        for (int m = 0; m < 9; ++m) {
            const double want = expected(r.t, m);
            CAPTURE(r.t, m, want);
            CHECK(std::fabs(r.levels[static_cast<std::size_t>(m)] - want) <= 1.0);   // dithered: the neighbouring integers
        }
        ++checked;
    }
    CHECK(checked > 300);

    // ForearmL: the same grid mirrored into the right-arm layout (index 5 → elbow, left column).
    std::string left = tact;
    for (std::size_t at; (at = left.find("ForearmR")) != std::string::npos;) left.replace(at, 8, "ForearmL");
    HapticImportOptions o;
    const ImportedScore mirrored = importTact(left, "left.tact", o);
    bool elbowLeft = false, elbowRight = false;
    for (const auto& n : mirrored.score.notes) {
        elbowLeft = elbowLeft || n.motors == (1u << 6);
        elbowRight = elbowRight || n.motors == (1u << 8);
    }
    CHECK(elbowLeft);
    CHECK_FALSE(elbowRight);
    // Asking for the other forearm names what the file plays on.
    o.tactDevice = "ForearmR";
    CHECK_THROWS_WITH(importTact(left, "left.tact", o), Catch::Contains("ForearmL") && Catch::Contains("nothing to feel"));
}

TEST_CASE("tact: malformed files are refused naming what is wrong", "[formats][tact]")
{
    const auto effect = [](const std::string& mode) {
        return R"({"project":{"tracks":[{"effects":[{"startTime":0,"offsetTime":500,"modes":{"ForearmR":)" + mode + "}}]}]}}";
    };
    const std::string dot = R"({"mode":"DOT_MODE","dotMode":{"feedback":[{"startTime":0,"endTime":100,"playbackType":"NONE","pointList":[{"index":2,"intensity":0.5}]}]},"pathMode":{"feedback":[]}})";
    HapticImportOptions o;
    CHECK_NOTHROW(importTact(effect(dot), "ok.tact", o));
    const std::vector<std::pair<std::string, std::string>> bad {
        {"[1, 2]", "JSON object"},
        {R"({"tracks":[]})", "project"},
        {R"({"project":{"tracks":{}}})", "tracks"},
        {R"({"project":{"tracks":[]}})", "nothing to feel"},
        {effect(R"({"mode":"DOT_MODE","dotMode":{"feedback":[{"startTime":0,"endTime":100,"pointList":[{"index":6,"intensity":0.5}]}]}})"), "index"},
        {effect(R"({"mode":"DOT_MODE","dotMode":{"feedback":[{"startTime":0,"endTime":100,"pointList":[{"index":1,"intensity":50}]}]}})"), "intensity"},
        {effect(R"({"mode":"DOT_MODE","dotMode":{"feedback":[{"startTime":0,"endTime":100,"pointList":[{"index":1,"intensity":"loud"}]}]}})"), "not a number"},
        {effect(R"({"mode":"DOT_MODE","dotMode":{"feedback":[{"startTime":200,"endTime":100,"pointList":[{"index":1,"intensity":0.5}]}]}})"), "ends before"},
        {effect(R"({"mode":"DOT_MODE","dotMode":{"feedback":[{"startTime":0,"endTime":100,"playbackType":"WOBBLE","pointList":[{"index":1,"intensity":0.5}]}]}})"), "WOBBLE"},
        {effect(R"({"mode":"SPIRAL_MODE","dotMode":{"feedback":[{"startTime":0,"endTime":100,"pointList":[{"index":1,"intensity":0.5}]}]}})"), "SPIRAL_MODE"},
        {effect(R"({"mode":"PATH_MODE","pathMode":{"feedback":[{"pointList":[{"time":100,"x":0,"y":0,"intensity":1},{"time":50,"x":1,"y":0,"intensity":1}]}]}})"), "must not decrease"},
        {effect(R"({"mode":"PATH_MODE","pathMode":{"feedback":[{"pointList":[{"time":0,"x":2,"y":0,"intensity":1}]}]}})"), "0..1"},
        {effect(R"({"mode":"PATH_MODE","pathMode":{"feedback":[{"pointList":[{"time":0,"y":0,"intensity":1}]}]}})"), "x"},
        {effect(R"({"mode":"DOT_MODE","dotMode":{"feedback":[{"startTime":0,"endTime":100,"pointList":[{"index":1,"intensity":0}]}]}})"), "every intensity is 0"},
        {R"({"project":{"tracks":[{"effects":[{"modes":{"ForearmR":{"mode":"DOT_MODE","dotMode":{"feedback":[{"startTime":0,"endTime":100,"pointList":[{"index":1,"intensity":0.5}]}]}}}}]}]}})", ""},
        {"{\"project\":", "column"},
    };
    for (const auto& [text, why] : bad) {
        CAPTURE(text);
        if (why.empty()) {   // offsetTime absent: the effect is not cut (valid)
            CHECK_NOTHROW(importTact(text, "f.tact", o));
            continue;
        }
        CHECK_THROWS_AS(importTact(text, "f.tact", o), InputError);
        CHECK_THROWS_WITH(importTact(text, "f.tact", o), Catch::Contains("f.tact") && Catch::Contains(why));
    }
}

TEST_CASE("tact export: every motor of a render survives the round trip within one step", "[formats][tact][export]")
{
    // Random levels on all nine motors (the wrist and elbow rows as dots, the middle row as
    // still path points), written, read back as JSON with the .tact structure, and imported.
    const auto rows = randomRows(1200, 41);
    const std::string text = exportTact(rows, "round trip");
    const armadillo::core::JsonValue root = armadillo::core::parseJson(text, "out.tact");
    REQUIRE(root.find("project"));
    const auto* tracks = root.find("project")->find("tracks");
    REQUIRE(tracks);
    REQUIRE(tracks->array.size() == 1);
    // Each effect, read with the documented rule, gives the packet's levels at its start.
    const auto& effects = tracks->array[0].find("effects")->array;
    REQUIRE(effects.size() > 100);
    for (const auto& e : effects) {
        const double start = e.find("startTime")->number / 1000.0;
        const auto i = static_cast<std::size_t>(std::lround(start / 0.005));
        REQUIRE(i < rows.size());
        const auto& mode = *e.find("modes")->find("ForearmR");
        if (mode.find("mode")->string == "DOT_MODE") {
            for (const auto& p : mode.find("dotMode")->find("feedback")->array[0].find("pointList")->array) {
                const int index = static_cast<int>(p.find("index")->number);
                const int motor = (index < 3 ? 0 : 6) + index % 3;
                CHECK(std::lround(15.0 * p.find("intensity")->number) == rows[i].levels[static_cast<std::size_t>(motor)]);
            }
        } else {
            for (const auto& fb : mode.find("pathMode")->find("feedback")->array) {
                const auto& p = fb.find("pointList")->array[0];
                CHECK(p.find("y")->number == 0.5);
                const int motor = 3 + static_cast<int>(std::lround(2.0 * p.find("x")->number));
                CHECK(std::lround(15.0 * p.find("intensity")->number) == rows[i].levels[static_cast<std::size_t>(motor)]);
            }
        }
    }
    const std::string path = tempPath("roundtrip.tact");
    writeText(path, text);
    const auto back = play(path, 6.0);
    REQUIRE(back.size() >= 1200);
    int worst = 0;
    for (std::size_t i = 0; i < 1200; ++i)
        for (std::size_t m = 0; m < 9; ++m) {
            const int d = std::abs(static_cast<int>(back[i].levels[m]) - static_cast<int>(rows[i].levels[m]));
            if (d > 1) {
                CAPTURE(i, m, static_cast<int>(back[i].levels[m]), static_cast<int>(rows[i].levels[m]));
                CHECK(d <= 1);
            }
            worst = std::max(worst, d);
        }
    CHECK(worst <= 1);
    std::printf("tact round trip: 1200 packets x 9 motors, largest difference %d\n", worst);
}

TEST_CASE("tact: mutated files never crash or hang: imported or refused with an InputError", "[formats][tact][fuzz]")
{
    // An exported file (dots and paths) and a hand-written one with fades and a moving path,
    // each mutated byte by byte and number by number (huge, negative, fractional values).
    const std::vector<std::string> seeds {
        exportTact(randomRows(200, 7), "fuzz"),
        R"({"project":{"tracks":[{"effects":[{"startTime":10,"offsetTime":500,"modes":{"ForearmL":{"mode":"PATH_MODE","dotMode":{"feedback":[]},)"
        R"("pathMode":{"feedback":[{"playbackType":"FADE_IN_OUT","pointList":[{"time":0,"x":0.1,"y":0.9,"intensity":0.7},{"time":250,"x":0.9,"y":0.2,"intensity":"0.3"},)"
        R"({"time":500,"x":0.5,"y":0.5,"intensity":1}]}]}}}},{"startTime":0,"offsetTime":300,"modes":{"ForearmL":{"mode":"DOT_MODE","dotMode":{"feedback":[)"
        R"({"startTime":0,"endTime":300,"playbackType":"FADE_IN","pointList":[{"index":0,"intensity":0.5},{"index":4,"intensity":0.9}]}]},"pathMode":{"feedback":[]}}}}]}]}})"};
    std::mt19937_64 rng(99);
    const char* replacements[] = {"1e308", "-1", "3600001", "0.5", "7", "\"x\"", "[]", "{}", "null", "1e-300", "2.5"};
    int imported = 0, refused = 0;
    for (int i = 0; i < 3000; ++i) {
        std::string m = seeds[static_cast<std::size_t>(i % 2)];
        const int edits = 1 + static_cast<int>(rng() % 4);
        for (int e = 0; e < edits; ++e) {
            const std::size_t at = rng() % m.size();
            if (rng() % 2 == 0) {
                m[at] = static_cast<char>(rng() % 128);
            } else {   // a number replaced
                std::size_t from = at;
                while (from < m.size() && !(m[from] >= '0' && m[from] <= '9')) ++from;
                std::size_t to = from;
                while (to < m.size() && ((m[to] >= '0' && m[to] <= '9') || m[to] == '.')) ++to;
                if (from < m.size()) m.replace(from, to - from, replacements[rng() % (sizeof replacements / sizeof *replacements)]);
            }
        }
        try {
            const ImportedScore s = importTact(m, "fuzz.tact", HapticImportOptions {});
            CHECK(s.report.notes > 0);
            ++imported;
        } catch (const InputError& e) {
            CHECK(std::string(e.what()).find("fuzz.tact") != std::string::npos);
            ++refused;
        }
    }
    CHECK(imported + refused == 3000);
    CHECK(imported > 0);
    CHECK(refused > 0);
    std::printf("tact fuzz: 3000 mutated files, %d imported, %d refused\n", imported, refused);
}

TEST_CASE("tact: a diagonal path crosses the 3x3 through the middle row (bilinear spreading)", "[formats][tact]")
{
    // ForearmR, one path effect at 200 ms: (0, 0) → (1, 1) over 400 ms at intensity 0.6, FADE_IN
    // off (NONE). Documented rule: motor (row, col) = 15 × 0.6 × max(0, 1 − |2x − col|) ×
    // max(0, 1 − |2y − row|), x = y = the fraction of the path done.
    const std::string tact = R"({"project":{"tracks":[{"enable":true,"effects":[{"startTime":200,"offsetTime":400,"modes":{"ForearmR":{"mode":"PATH_MODE",
      "dotMode":{"feedback":[]},"pathMode":{"feedback":[{"movingPattern":"CONST_TDM","playbackType":"NONE","visible":true,
      "pointList":[{"time":0,"x":0,"y":0,"intensity":0.6},{"time":400,"x":1,"y":1,"intensity":0.6}]}]}}}}]}]}})";
    const std::string path = tempPath("diagonal.tact");
    writeText(path, tact);
    const auto rows = play(path, 0.8);
    int checked = 0, middle = 0;
    for (const auto& r : rows) {
        if (std::fabs(r.t - 0.2) < 0.006 || std::fabs(r.t - 0.6) < 0.006) continue;
        for (int m = 0; m < 9; ++m) {
            double want = 0.0;
            if (r.t >= 0.2 && r.t < 0.6) {
                const double u = (r.t - 0.2) / 0.4;
                want = 15.0 * 0.6 * std::max(0.0, 1.0 - std::fabs(2.0 * u - m % 3)) * std::max(0.0, 1.0 - std::fabs(2.0 * u - m / 3));
            }
            CAPTURE(r.t, m, want);
            CHECK(std::fabs(r.levels[static_cast<std::size_t>(m)] - want) <= 1.0);
        }
        middle += r.levels[4] > 0;
        ++checked;
    }
    CHECK(checked > 150);
    CHECK(middle > 20);   // the middle row, which dot mode cannot reach, is felt
}
