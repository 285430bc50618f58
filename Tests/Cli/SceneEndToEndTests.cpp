// End-to-end: the scenes through `armadillo render`, measured from the files it writes, as a
// user (or a DAW) would receive them.
#include "CliRun.h"
#include "Core/Csv.h"
#include "Core/Wav.h"
#include "SafetyBounds.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>
#include <cstring>
#include <set>

using namespace armadillo;
using namespace armadillo::core;
using armadillo::testing::checkSafety;

namespace {
std::string poseFile(const std::string& name, double seconds, double rate,
                     const std::function<Pose(double)>& pose)
{
    std::string s = "t,elevation,azimuth,roll\n";
    for (int i = 0; i <= static_cast<int>(seconds * rate); ++i) {
        const double t = i / rate;
        const Pose p = pose(t);
        s += std::to_string(t) + "," + std::to_string(p.elevationDeg) + "," + std::to_string(p.azimuthDeg) + "," +
             std::to_string(p.rollDeg) + "\n";
    }
    return cli::file(name, s);
}

/// Frequency of a steady tone from rising zero crossings with linear interpolation, Hz.
double pitchOf(const std::vector<float>& x, double sampleRate, std::size_t from, std::size_t to)
{
    double first = -1.0, last = -1.0;
    int crossings = 0;
    for (std::size_t i = from + 1; i < to && i < x.size(); ++i) {
        if (x[i - 1] < 0.0f && x[i] >= 0.0f) {
            const double a = x[i - 1], b = x[i];
            const double pos = static_cast<double>(i - 1) + a / (a - b);
            if (first < 0.0) first = pos;
            else ++crossings;
            last = pos;
        }
    }
    return crossings > 0 ? crossings * sampleRate / (last - first) : 0.0;
}

double rms(const std::vector<float>& x, std::size_t from, std::size_t to)
{
    double s = 0.0;
    for (std::size_t i = from; i < to; ++i) s += double(x[i]) * double(x[i]);
    return std::sqrt(s / double(to - from));
}

double cents(double f, double reference) { return 1200.0 * std::log2(f / reference); }
/// Renders a score over a still arm for `seconds` and returns its tactile rows, after checking
/// them against the safety bounds.
std::vector<TactileRow> renderScoreSafely(const std::string& score, double seconds)
{
    const std::string motion = poseFile("still-" + score + ".csv", seconds, 200.0, [](double) { return Pose {}; });
    const std::string tactile = cli::path(score + ".csv");
    const auto r = cli::runArmadillo("render --scene score --score " + score + " --motion '" + motion + "' --out '" +
                                     cli::path(score + ".wav") + "' --tactile '" + tactile + "'");
    REQUIRE(r.code == 0);
    auto rows = readTactile(CsvTable::read(tactile));
    const auto report = checkSafety(rows, kGridMotors);
    INFO(report.worst << "; longest above rating " << report.longestAboveRating << " s, worst 2 s " << report.maxAboveIn2s
                      << " s, worst 10 s power " << report.maxPowerIn10s);
    CHECK(report.ok());
    return rows;
}
} // namespace

TEST_CASE("e2e: theremin pitch follows elevation within 5 cents of f = 220·2^(e/12)", "[e2e][theremin]")
{
    // Hold three elevations for 1.5 s each, facing the azimuth where the scene starts (full volume).
    const double held[] = {-30.0, 0.0, 30.0};
    const std::string motion = poseFile("theremin.csv", 4.5, 200.0, [&](double t) {
        return Pose {held[std::min(2, static_cast<int>(t / 1.5))], 0.0, 0.0};
    });
    const std::string wav = cli::path("theremin.wav");
    const auto r = cli::runArmadillo("render --scene theremin --motion '" + motion + "' --out '" + wav + "' --float");
    REQUIRE(r.code == 0);
    const AudioBuffer a = readWav(wav);
    for (int k = 0; k < 3; ++k) {
        // e runs linearly in sin(elevation): −45° ⇒ 0, +45° ⇒ 12 semitones.
        const double e = 12.0 * (std::sin(degToRad(held[k])) + std::sin(degToRad(45.0))) / (2.0 * std::sin(degToRad(45.0)));
        const double expected = 220.0 * std::pow(2.0, e / 12.0);
        const auto from = static_cast<std::size_t>((k * 1.5 + 0.7) * a.sampleRate), to = static_cast<std::size_t>((k * 1.5 + 1.4) * a.sampleRate);
        const double f = pitchOf(a.channels[0], a.sampleRate, from, to);
        INFO("elevation " << held[k] << ": expected " << expected << " Hz, measured " << f << " Hz");
        CHECK(std::abs(cents(f, expected)) < 5.0);
        CHECK(rms(a.channels[0], from, to) > 0.01);
    }
}

TEST_CASE("e2e: play sends the theremin to the sound card at the held elevation's pitch", "[e2e][theremin][audio]")
{
    // The sound card here is ALSA's `file` device (works without hardware): every sample play
    // hands to ALSA lands in a raw float file that is measured like a recording of the card.
    // The simulated sensors start with an unknown gyro bias, so the live estimate of the held
    // 20° wanders by about a degree while the filter learns it: the expected pitch comes from
    // the elevation the session itself logged over the measured second.
    const std::string motion = poseFile("theremin-card.csv", 2.0, 200.0, [&](double) { return Pose {20.0, 0.0, 0.0}; });
    const std::string raw = cli::path("theremin-card.raw"), log = cli::path("theremin-card-log.csv");
    const auto r = cli::runArmadillo("play --scene theremin --simulate --motion '" + motion + "' --seconds 2.5 --log '" + log +
                                     "' --audio-device \"file:'" + raw + "',raw\"");
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.err.find("sound on 'file:") != std::string::npos);
    const std::string bytes = readWholeFile(raw);
    std::vector<float> left(bytes.size() / 8);
    for (std::size_t i = 0; i < left.size(); ++i) std::memcpy(&left[i], bytes.data() + 8 * i, sizeof(float));
    const double rate = 48000.0;
    REQUIRE(left.size() > static_cast<std::size_t>(2.0 * rate));   // about the session's length
    const CsvTable t = CsvTable::read(log);
    const int ct = t.requireColumn("t"), cw = t.requireColumn("qw"), cx = t.requireColumn("qx"), cy = t.requireColumn("qy"), cz = t.requireColumn("qz");
    double sinElevation = 0.0;   // the forearm (device x) rotated into earth: its Y component
    int rows = 0;
    for (std::size_t i = 0; i < t.rowCount(); ++i) {
        const double since = t.value(i, ct) - t.value(0, ct);
        if (since < 1.0 || since > 2.0) continue;
        sinElevation += 2.0 * (t.value(i, cx) * t.value(i, cy) + t.value(i, cw) * t.value(i, cz));
        ++rows;
    }
    REQUIRE(rows > 100);
    sinElevation /= rows;
    const double e = 12.0 * (sinElevation + std::sin(degToRad(45.0))) / (2.0 * std::sin(degToRad(45.0)));
    const double expected = 220.0 * std::pow(2.0, e / 12.0);
    const auto from = static_cast<std::size_t>(1.0 * rate), to = static_cast<std::size_t>(2.0 * rate);
    INFO("logged elevation " << radToDeg(std::asin(sinElevation)) << " deg (held 20)");
    CHECK(std::abs(radToDeg(std::asin(sinElevation)) - 20.0) < 3.0);
    const double f = pitchOf(left, rate, from, to);
    INFO("expected " << expected << " Hz, measured " << f << " Hz");
    CHECK(std::abs(cents(f, expected)) < 5.0);
    CHECK(rms(left, from, to) > 0.01);
}

TEST_CASE("e2e: play without --out on a machine with no sound card says so once and plays on", "[e2e][audio]")
{
    const auto r = cli::runArmadillo("play --scene monitor --simulate --seconds 1");
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("\"packets\":") != std::string::npos);
    // Either this machine has a card ("sound on 'default'") or it says why there is no sound.
    const bool card = r.err.find("sound on 'default'") != std::string::npos;
    const bool told = r.err.find("no sound: sound card 'default'") != std::string::npos;
    CHECK((card || told));
    CHECK(r.err.find("ALSA lib") == std::string::npos);   // ALSA's own noise stays quiet
    const auto quiet = cli::runArmadillo("play --scene monitor --simulate --seconds 0.5 --no-audio");
    CHECK(quiet.code == 0);
    CHECK(quiet.err.find("sound") == std::string::npos);
    CHECK(cli::runArmadillo("play --scene monitor --simulate --seconds 0.5 --no-audio --out x.wav").code == 2);
    CHECK(cli::runArmadillo("play --scene monitor --simulate --seconds 0.5 --audio-device null --out x.wav").code == 2);
    const auto missing = cli::runArmadillo("play --scene monitor --simulate --seconds 0.5 --audio-device hw:97");
    CHECK(missing.code == 4);
    CHECK(missing.err.find("sound card 'hw:97'") != std::string::npos);
}

TEST_CASE("e2e: theremin level falls as the arm turns away from the starting azimuth", "[e2e][theremin]")
{
    const std::string motion = poseFile("theremin-az.csv", 6.0, 200.0, [](double t) {
        return Pose {0.0, t < 2.0 ? 0.0 : (t < 4.0 ? 30.0 : 70.0), 0.0};
    });
    const std::string wav = cli::path("theremin-az.wav");
    REQUIRE(cli::runArmadillo("render --scene theremin --motion '" + motion + "' --out '" + wav + "' --float").code == 0);
    const AudioBuffer a = readWav(wav);
    const auto seg = [&](double t0, double t1) {
        return rms(a.channels[0], static_cast<std::size_t>(t0 * a.sampleRate), static_cast<std::size_t>(t1 * a.sampleRate));
    };
    const double full = seg(1.0, 1.9), half = seg(3.0, 3.9), silent = seg(5.0, 5.9);
    INFO("rms at 0°, 30°, 70°: " << full << ", " << half << ", " << silent);
    CHECK(full > half * 1.2);
    CHECK(half > silent);
    CHECK(silent < full * 0.05);
}

TEST_CASE("e2e: the Rite of Spring score is one motor at a time and never breaks the safety bounds", "[e2e][score]")
{
    const auto rows = renderScoreSafely("rite-of-spring", 60.0);
    std::size_t active = 0, multi = 0;
    std::set<int> used;
    for (const auto& row : rows) {
        int on = 0;
        for (int m = 0; m < kGridMotors; ++m)
            if (row.levels[static_cast<std::size_t>(m)] > 0) {
                ++on;
                used.insert(m);
            }
        active += on > 0;
        multi += on > 1;
    }
    INFO("rows with a motor on: " << active << ", with more than one: " << multi << ", motors used: " << used.size());
    CHECK(active > rows.size() / 4);
    CHECK(multi < active / 20 + 1);   // handovers only
    CHECK(used.size() >= 3);
}

TEST_CASE("e2e: the Polytope score is texture and never breaks the safety bounds", "[e2e][score]")
{
    const auto rows = renderScoreSafely("polytope", 90.0);
    std::size_t textured = 0;
    for (const auto& row : rows) {
        int on = 0;
        for (int m = 0; m < kGridMotors; ++m) on += row.levels[static_cast<std::size_t>(m)] > 0;
        textured += on >= 3;
    }
    CHECK(textured > rows.size() / 10);
}

TEST_CASE("e2e: the cymbal render repeats for a seed and differs across seeds", "[e2e][cymbal]")
{
    // Raise the arm, strike down through horizontal, let it ring.
    const std::string motion = poseFile("strike.csv", 3.0, 200.0, [](double t) {
        const double el = t < 0.5 ? 40.0 : (t < 0.65 ? 40.0 - (t - 0.5) / 0.15 * 70.0 : -30.0);
        return Pose {el, 0.0, 0.0};
    });
    const auto render = [&](const std::string& name, int seed) {
        const std::string wav = cli::path(name);
        REQUIRE(cli::runArmadillo("render --scene cymbal --seed " + std::to_string(seed) + " --motion '" + motion + "' --out '" + wav +
                               "' --float --tail 2")
                    .code == 0);
        return readWav(wav);
    };
    const AudioBuffer a = render("c1.wav", 7), b = render("c1b.wav", 7), c = render("c2.wav", 8);
    CHECK(a.channels == b.channels);
    CHECK(a.channels != c.channels);
    CHECK(rms(a.channels[0], static_cast<std::size_t>(0.7 * a.sampleRate), static_cast<std::size_t>(1.2 * a.sampleRate)) > 0.01);
}

TEST_CASE("e2e: reading a sign word in braille never breaks the safety bounds", "[e2e][braille]")
{
    // Hanging arm (within 30° of vertical), rolling in 20° steps back and forth.
    const std::string motion = poseFile("braille-roll.csv", 40.0, 200.0, [](double t) {
        const int step = static_cast<int>(t / 0.8);
        return Pose {-80.0, 0.0, 20.0 * (step % 8 < 4 ? step % 8 : 8 - step % 8)};
    });
    const std::string tactile = cli::path("braille.csv");
    const auto r = cli::runArmadillo("render --scene braille --text ENTRANCE --motion '" + motion + "' --out '" + cli::path("braille.wav") +
                                  "' --tactile '" + tactile + "'");
    REQUIRE(r.code == 0);
    const auto rows = readTactile(CsvTable::read(tactile));
    const auto report = checkSafety(rows, kGridMotors);
    INFO(report.worst);
    CHECK(report.ok());
    std::size_t active = 0;
    for (const auto& row : rows)
        for (int m = 0; m < kGridMotors; ++m) active += row.levels[static_cast<std::size_t>(m)] > 0;
    CHECK(active > 0);
}

TEST_CASE("e2e: the cymbal cuts fragments from a user recording given with --audio", "[e2e][cymbal]")
{
    // A recording that sounds nothing like noise: a pure 1 kHz tone.
    AudioBuffer tone;
    tone.sampleRate = 48000;
    tone.channels.assign(1, std::vector<float>(48000 * 6));
    for (std::size_t i = 0; i < tone.channels[0].size(); ++i) tone.channels[0][i] = 0.8f * float(std::sin(2.0 * kPi * 1000.0 * double(i) / 48000.0));
    const std::string recording = cli::path("tone.wav");
    writeWav(recording, tone);
    const std::string motion = poseFile("strike-audio.csv", 3.0, 200.0, [](double t) {
        const double el = t < 0.5 ? 40.0 : (t < 0.65 ? 40.0 - (t - 0.5) / 0.15 * 70.0 : -30.0);
        return Pose {el, 0.0, 0.0};
    });
    const auto render = [&](const std::string& extra, const std::string& name) {
        const std::string wav = cli::path(name);
        const auto r = cli::runArmadillo("render --scene cymbal --seed 5 --motion '" + motion + "' --out '" + wav + "' --float " + extra);
        REQUIRE(r.code == 0);
        return readWav(wav);
    };
    const AudioBuffer builtIn = render("", "bank.wav");
    const AudioBuffer withFile = render("--param cymbal.fileMix=100 --audio '" + recording + "'", "file.wav");
    CHECK(builtIn.channels != withFile.channels);
    // A bad recording is refused as bad input, naming the file.
    const auto bad = cli::runArmadillo("render --scene cymbal --motion '" + motion + "' --out '" + cli::path("x.wav") + "' --audio '" + motion + "'");
    CHECK(bad.code == 3);
    CHECK(bad.err.find("strike-audio.csv") != std::string::npos);
    CHECK(cli::runArmadillo("render --scene theremin --motion '" + motion + "' --out '" + cli::path("x.wav") + "' --audio '" + recording + "'").code == 2);
}

TEST_CASE("e2e: braille training live through play: prompts out, typed answers in, the log records them", "[e2e][braille]")
{
    // The plan `braille --plan` prints is the plan the live scene follows (same seed). Answer
    // every trial as planned except every seventh, which gets a nonsense answer; "hold" trials
    // are right only if the asked row happens to show, so they are not predicted.
    const auto plan = cli::runArmadillo("braille --plan --seed 3");
    REQUIRE(plan.code == 0);
    std::vector<std::string> expected, stages;
    {
        // trial,stage,"prompt",expected: text columns (CsvTable holds numbers only), read by hand.
        std::istringstream in(plan.out);
        std::string line;
        std::getline(in, line);   // header
        while (std::getline(in, line)) {
            const auto firstComma = line.find(','), secondComma = line.find(',', firstComma + 1);
            stages.push_back(line.substr(firstComma + 1, secondComma - firstComma - 1));
            expected.push_back(line.substr(line.rfind(',') + 1));
        }
    }
    REQUIRE(expected.size() > 20);
    std::string answers;
    std::vector<std::string> sent;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        sent.push_back(i % 7 == 3 ? std::string("zz") : expected[i]);
        answers += sent.back() + (i % 5 == 0 ? "\r\n" : "\n");   // CRLF from some terminals too
    }
    const std::string input = cli::file("answers.txt", answers), log = cli::path("training.csv");
    const auto r = cli::runArmadillo("play --scene braille --simulate --seed 3 --seconds 120 --no-audio --training-log '" + log + "'", input);
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("\"packets\":") != std::string::npos);
    CHECK(r.err.find("braille training 1/" + std::to_string(expected.size()) + ": ") != std::string::npos);
    CHECK(r.err.find("braille training complete: ") != std::string::npos);
    CHECK(r.err.find("wrong, it was '" + expected[3] + "'") != std::string::npos);

    // The log's answer rows, in order: what was typed, scored as the plan says.
    std::istringstream in(readWholeFile(log));
    std::string line;
    std::getline(in, line);
    REQUIRE(line.rfind("t,event,stage,trial,expected,prompt", 0) == 0);
    std::size_t k = 0;
    int rightOutsideHold = 0;
    while (std::getline(in, line)) {
        if (line.find(",answer,") == std::string::npos) continue;
        REQUIRE(k < sent.size());
        const auto lastComma = line.rfind(','), before = line.rfind(',', lastComma - 1);
        const std::string given = line.substr(before + 1, lastComma - before - 1), correct = line.substr(lastComma + 1);
        INFO("trial " << k + 1 << " (" << stages[k] << "): " << line);
        CHECK(given == sent[k]);
        if (stages[k] != "hold") {
            CHECK(correct == (k % 7 == 3 ? "0" : "1"));
            if (correct == "1") ++rightOutsideHold;
        }
        ++k;
    }
    CHECK(k == sent.size());
    CHECK(rightOutsideHold > 0);
    // Misuse is refused before anything runs.
    CHECK(cli::runArmadillo("play --scene theremin --simulate --seconds 1 --training-log x.csv").code == 2);
    CHECK(cli::runArmadillo("play --scene braille --simulate --param braille.mode=active --training-log x.csv", input).code == 2);
    const auto unwritable = cli::runArmadillo("play --scene braille --simulate --no-audio --training-log /nonexistent/dir/t.csv", input);
    CHECK(unwritable.code == 4);
    CHECK(unwritable.err.find("--training-log: cannot write '/nonexistent/dir/t.csv': the folder '/nonexistent/dir' does not exist") != std::string::npos);
    CHECK(unwritable.err.find("braille training 1/") == std::string::npos);   // refused before the first trial

    // stdin ends early, its last answer without a newline: that answer counts, the session ends
    // by itself and says how many trials were left, and the log is written.
    const std::string shortInput = cli::file("short.txt", sent[0] + "\n" + sent[1] + "\n" + sent[2]);
    const std::string shortLog = cli::path("training-short.csv");
    const auto early = cli::runArmadillo("play --scene braille --simulate --seed 3 --no-audio --training-log '" + shortLog + "'", shortInput);
    INFO(early.err);
    REQUIRE(early.code == 0);
    CHECK(early.err.find("no more answers (stdin ended) with " + std::to_string(sent.size() - 3) + " of ") != std::string::npos);
    const std::string shortCsv = readWholeFile(shortLog);
    std::size_t answerRows = 0;
    for (std::size_t at = shortCsv.find(",answer,"); at != std::string::npos; at = shortCsv.find(",answer,", at + 1)) ++answerRows;
    CHECK(answerRows == 3 + 1);   // three answers and the header's column name
}
