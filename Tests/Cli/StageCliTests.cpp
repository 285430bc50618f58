// `armadillo render --setlist` as a user runs it: the cue changes heard in the WAV, and every
// mistake refused with its exit code (2 usage, 3 bad input) and a message naming the problem.
#include "CliRun.h"
#include "Core/AtomicFile.h"
#include "Core/Csv.h"
#include "Core/Pose.h"
#include "Core/Wav.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace armadillo;
using namespace armadillo::cli;

namespace {
std::string sway(const std::string& name)
{
    std::string s = "t,elevation,azimuth,roll\n";
    for (int i = 0; i <= 600; ++i) s += std::to_string(i / 200.0) + "," + std::to_string(-30.0 + 20.0 * i / 200.0) + ",0,0\n";
    return file(name, s);
}
} // namespace

TEST_CASE("cli: render --setlist steps cues at --cue-at times; mistakes are refused with their exit codes", "[cli][setlist]")
{
    const std::string motion = sway("sl-motion.csv");
    const std::string show = file("show.json", R"({"armadillo_setlist": 1, "cues": [
        {"name": "one", "scene": "theremin"},
        {"name": "silence", "scene": "monitor"},
        {"name": "two", "scene": "theremin", "parameters": {"theremin.base": 440}}]})");
    const std::string out = path("sl.wav");
    const Run ok = runArmadillo("render --setlist '" + show + "' --motion '" + motion + "' --out '" + out + "' --cue-at 1:1 --cue-at 2:2");
    INFO(ok.err);
    REQUIRE(ok.code == 0);
    const AudioBuffer a = readWav(out);
    auto rms = [&](double from, double to) {
        double s = 0.0;
        const auto i0 = static_cast<std::size_t>(from * 48000), i1 = static_cast<std::size_t>(to * 48000);
        for (std::size_t i = i0; i < i1; ++i) s += static_cast<double>(a.channels[0][i]) * static_cast<double>(a.channels[0][i]);
        return std::sqrt(s / static_cast<double>(i1 - i0));
    };
    CHECK(rms(0.3, 0.9) > 0.01);    // cue 0 sounds
    CHECK(rms(1.1, 1.9) == 0.0);    // cue 1 (monitor) is silent after its 50 ms fade
    CHECK(rms(2.1, 2.9) > 0.01);    // cue 2 sounds

    const std::string base = "render --motion '" + motion + "' --out '" + path("x.wav") + "' ";
    CHECK(runArmadillo(base).code == 2);                                                     // neither --scene nor --setlist
    CHECK(runArmadillo(base + "--scene theremin --setlist '" + show + "'").code == 2);       // both
    CHECK(runArmadillo(base + "--scene theremin --cue-at 1:1").code == 2);                   // --cue-at without a set list
    CHECK(runArmadillo(base + "--setlist '" + show + "' --cue-at 1").code == 2);             // not T:INDEX
    CHECK(runArmadillo(base + "--setlist '" + show + "' --param theremin.range=3").code == 2);
    const Run range = runArmadillo(base + "--setlist '" + show + "' --cue-at 1:7");
    CHECK(range.code == 3);
    CHECK(range.err.find("cue 7 does not exist") != std::string::npos);
    const std::string broken = file("broken.json", "{\"armadillo_setlist\": 1,\n \"cues\": [{\"scene\": \"kazoo\"}]}");
    const Run bad = runArmadillo(base + "--setlist '" + broken + "'");
    CHECK(bad.code == 3);
    CHECK(bad.err.find("broken.json:2") != std::string::npos);
    CHECK(bad.err.find("kazoo") != std::string::npos);
    CHECK(runArmadillo(base + "--setlist '" + path("missing.json") + "'").code == 4);
}

TEST_CASE("cli: play --setlist steps cues by keys and panics them all; mistakes refused", "[cli][setlist][panic]")
{
    const std::string show = file("play-show.json", R"({"armadillo_setlist": 1, "cues": [
        {"name": "one", "scene": "theremin"}, {"name": "two", "scene": "sound-design"},
        {"name": "three", "scene": "theremin", "parameters": {"theremin.base": 330}}, {"name": "four", "scene": "panel"}]})");
    // Keys typed 0.3 s apart (the pacing only keeps two keys out of one control step; nothing
    // here is timed): next, next, next, back, 3 — four cues visited, ending on cue 3.
    const std::string keys = path("play-keys.sh");
    writeFileAtomically(keys, "for k in n n n b 3; do sleep 0.3; printf $k; done; sleep 0.5\n");
    const std::string cmd = std::string("sh '") + keys + "' | '" + ARMADILLO_BIN + "' play --setlist '" + show +
                            "' --simulate --keys --seconds 2.6 --out '" + path("play-sl.wav") + "' >'" + path("sl-out.txt") + "' 2>'" +
                            path("sl-err.txt") + "'";
    REQUIRE(std::system(cmd.c_str()) == 0);
    const std::string out = readWholeFile(path("sl-out.txt")), err = readWholeFile(path("sl-err.txt"));
    INFO(err);
    CHECK(out.find("\"cue\":3,\"cue_changes\":5") != std::string::npos);
    for (const char* line : {"cue 1 'two'", "cue 2 'three'", "cue 3 'four'"}) CHECK(err.find(line) != std::string::npos);
    const AudioBuffer a = readWav(path("play-sl.wav"));
    double peak = 0.0;
    for (float v : a.channels[0]) peak = std::max(peak, std::fabs(static_cast<double>(v)));
    CHECK(peak > 0.05);
    // Panic with a set list: every cue silent, and a cue change does not bring the sound back.
    writeFileAtomically(keys, "printf p; sleep 0.3; printf n; sleep 0.5\n");
    const std::string cmd2 = std::string("sh '") + keys + "' | '" + ARMADILLO_BIN + "' play --setlist '" + show +
                             "' --simulate --keys --seconds 1.2 --out '" + path("play-panic.wav") + "' >'" + path("sl-out.txt") + "' 2>'" +
                             path("sl-err.txt") + "'";
    REQUIRE(std::system(cmd2.c_str()) == 0);
    CHECK(readWholeFile(path("sl-out.txt")).find("\"panics\":1") != std::string::npos);
    const AudioBuffer p = readWav(path("play-panic.wav"));
    double late = 0.0;   // after the first 0.3 s (the key arrives at once; 0.3 s is generous)
    for (std::size_t i = static_cast<std::size_t>(0.3 * 48000); i < p.frames(); ++i) late = std::max(late, std::fabs(static_cast<double>(p.channels[0][i])));
    CHECK(late == 0.0);

    CHECK(runArmadillo("play --simulate --seconds 1 --no-audio").code == 2);   // neither --scene nor --setlist
    CHECK(runArmadillo("play --setlist '" + show + "' --scene theremin --simulate --seconds 1 --no-audio").code == 2);
    CHECK(runArmadillo("play --setlist '" + path("nope.json") + "' --simulate --seconds 1 --no-audio").code == 4);
    const std::string broken = file("play-broken.json", "{\"armadillo_setlist\": 1, \"cues\": [{\"scene\": \"theremin\", \"parameters\": {\"theremin.range\": 999}}]}");
    const Run bad = runArmadillo("play --setlist '" + broken + "' --simulate --seconds 1 --no-audio");
    CHECK(bad.code == 3);
    CHECK(bad.err.find("play-broken.json:1") != std::string::npos);
}

TEST_CASE("cli: render --motion-left: two arms, the left arm's motors and both orientations written", "[cli][twoarms]")
{
    auto poseFile = [](const std::string& name, double el, double roll) {
        std::string s = "t,elevation,azimuth,roll\n";
        for (int i = 0; i <= 200; ++i) s += std::to_string(i / 200.0) + "," + std::to_string(el) + ",0," + std::to_string(roll) + "\n";
        return file(name, s);
    };
    const std::string right = poseFile("duo-right.csv", 20.0, 0.0), left = poseFile("duo-left.csv", 40.0, -30.0);
    const Run r = runArmadillo("render --scene theremin-duo --motion '" + right + "' --motion-left '" + left + "' --out '" + path("duo.wav") +
                               "' --tactile-left '" + path("duo-left-tactile.csv") + "' --arms-log '" + path("duo-arms.csv") + "'");
    INFO(r.err);
    REQUIRE(r.code == 0);
    const CsvTable arms = CsvTable::read(path("duo-arms.csv"));
    REQUIRE(arms.rowCount() == 201);
    CHECK(arms.header() == std::vector<std::string> {"t", "qw", "qx", "qy", "qz", "left_qw", "left_qx", "left_qy", "left_qz"});
    // The logged orientations are the two files' poses (INTERFACES.md's pose → quaternion).
    const Eigen::Quaterniond qr = poseToQuaternion(Pose {20.0, 0.0, 0.0}), ql = poseToQuaternion(Pose {40.0, 0.0, -30.0});
    CHECK(std::fabs(std::fabs(arms.value(100, 1) * qr.w() + arms.value(100, 2) * qr.x() + arms.value(100, 3) * qr.y() + arms.value(100, 4) * qr.z()) - 1.0) < 1e-6);
    CHECK(std::fabs(std::fabs(arms.value(100, 5) * ql.w() + arms.value(100, 6) * ql.x() + arms.value(100, 7) * ql.y() + arms.value(100, 8) * ql.z()) - 1.0) < 1e-6);
    const CsvTable lt = CsvTable::read(path("duo-left-tactile.csv"));
    CHECK(lt.rowCount() == 201);
    const std::string base = "render --scene theremin-duo --motion '" + right + "' --out '" + path("x.wav") + "' ";
    CHECK(runArmadillo(base + "--tactile-left '" + path("t.csv") + "'").code == 2);   // needs --motion-left
    CHECK(runArmadillo(base + "--arms-log '" + path("a.csv") + "'").code == 2);
    CHECK(runArmadillo(base + "--motion-left '" + path("none.csv") + "'").code == 4);
    const std::string garbage = file("duo-garbage.csv", "a,b\n1,2\n");
    CHECK(runArmadillo(base + "--motion-left '" + garbage + "'").code == 3);
}

namespace {
/// RMS angle (deg) between each logged orientation and the motion file's pose at that time
/// (linear in time between rows; the simulator loops the file), after the first second.
double rmsAgainstMotion(const CsvTable& log, int qwColumn, const CsvTable& motion)
{
    const auto rows = readPoses(motion);
    const double period = rows.back().t;
    double sum = 0.0;
    int n = 0;
    for (std::size_t r = 0; r < log.rowCount(); ++r) {
        const double t = log.value(r, 0);
        if (t < 1.0 || !std::isfinite(log.value(r, qwColumn))) continue;
        const double u = std::fmod(t, period);
        std::size_t k = 0;
        while (k + 2 < rows.size() && rows[k + 1].t <= u) ++k;
        const double f = std::clamp((u - rows[k].t) / (rows[k + 1].t - rows[k].t), 0.0, 1.0);
        const Pose& a = rows[k].pose;
        const Pose& b = rows[k + 1].pose;
        const Eigen::Quaterniond truth = poseToQuaternion(Pose {a.elevationDeg + f * (b.elevationDeg - a.elevationDeg), a.azimuthDeg + f * (b.azimuthDeg - a.azimuthDeg),
                                                               a.rollDeg + f * (b.rollDeg - a.rollDeg)});
        const Eigen::Quaterniond q(log.value(r, qwColumn), log.value(r, qwColumn + 1), log.value(r, qwColumn + 2), log.value(r, qwColumn + 3));
        const double angle = 2.0 * std::acos(std::min(1.0, std::fabs(q.normalized().dot(truth)))) * 180.0 / 3.14159265358979;
        sum += angle * angle;
        ++n;
    }
    return n > 0 ? std::sqrt(sum / n) : 1e9;
}
} // namespace

TEST_CASE("cli: play with two simulated arms logs two independent orientations, each as accurate as that arm alone", "[cli][twoarms]")
{
    std::string r = "t,elevation,azimuth,roll\n", l = r;
    for (int i = 0; i <= 600; ++i) {
        const double t = i / 200.0;
        // Slow motions (≤ 25°/s), so the comparison measures the fusion, not the time alignment.
        r += std::to_string(t) + "," + std::to_string(30.0 * std::sin(0.5 * t)) + ",20,0\n";
        l += std::to_string(t) + "," + std::to_string(-20.0 + 10.0 * std::sin(0.7 * t)) + ",300," + std::to_string(40.0 * std::sin(0.6 * t)) + "\n";
    }
    const std::string right = file("arm-right.csv", r), left = file("arm-left.csv", l);
    const Run both = runArmadillo("play --scene theremin-duo --simulate --motion '" + right + "' --motion-left '" + left + "' --seconds 3 --out '" +
                                  path("two.wav") + "' --arms-log '" + path("two-arms.csv") + "'");
    INFO(both.err);
    REQUIRE(both.code == 0);
    CHECK(both.out.find("\"left_packets\":") != std::string::npos);
    const Run rightAlone = runArmadillo("play --scene theremin --simulate --motion '" + right + "' --seconds 3 --no-audio --log '" + path("right-alone.csv") + "'");
    const Run leftAlone = runArmadillo("play --scene theremin --simulate --motion '" + left + "' --seconds 3 --no-audio --log '" + path("left-alone.csv") + "'");
    REQUIRE(rightAlone.code == 0);
    REQUIRE(leftAlone.code == 0);
    const CsvTable arms = CsvTable::read(path("two-arms.csv"));
    const CsvTable ra = CsvTable::read(path("right-alone.csv")), la = CsvTable::read(path("left-alone.csv"));
    REQUIRE(arms.rowCount() > 300);
    const double eRight = rmsAgainstMotion(arms, 1, CsvTable::read(right)), eLeft = rmsAgainstMotion(arms, 5, CsvTable::read(left));
    const double eRightAlone = rmsAgainstMotion(ra, ra.requireColumn("qw"), CsvTable::read(right));
    const double eLeftAlone = rmsAgainstMotion(la, la.requireColumn("qw"), CsvTable::read(left));
    std::printf("play, two simulated arms: RMS orientation error right %.2f deg (alone %.2f), left %.2f deg (alone %.2f)\n", eRight, eRightAlone, eLeft,
                eLeftAlone);
    // Within the accuracy of one arm alone: no worse than alone by more than half (live runs
    // differ in timing; the error here is mostly the simulator's lag against the file's time)
    // plus half a degree. Measured 1.34° vs 1.32° (right) and 4.16° vs 3.49° (left).
    CHECK(eRight <= 1.5 * eRightAlone + 1.0);
    CHECK(eLeft <= 1.5 * eLeftAlone + 1.0);
    CHECK(eRight < 5.0);
    CHECK(eLeft < 5.0);
    // Mistakes.
    CHECK(runArmadillo("play --scene theremin --port /dev/null --motion-left '" + left + "' --seconds 1 --no-audio").code == 2);   // needs --simulate
    CHECK(runArmadillo("play --scene theremin --simulate --arms-log '" + path("x.csv") + "' --seconds 1 --no-audio").code == 2);
    CHECK(runArmadillo("play --scene theremin --simulate --motion-left '" + path("none.csv") + "' --seconds 1 --no-audio").code == 4);
    CHECK(runArmadillo("play --scene theremin --simulate --motion-left - --port-left /dev/null --seconds 1 --no-audio").code == 2);
}

TEST_CASE("cli: render/play --setlist --profile: every cue feels the reader's touch profile", "[cli][setlist][touch-profile]")
{
    // As `render --profile` for one scene (TouchProfileTests.cpp): thresholds 8, 4, 2 on the wrist
    // row, 4 elsewhere; median 4, so m1 ×2, m2 ×1, m3 ×0.5 — here for a braille cue.
    const std::string profile = file("sl-fit.json", "{\"threshold\": [8, 4, 2, 4, 4, 4, 4, 4, 4]}");
    const std::string show = file("sl-braille.json", R"({"armadillo_setlist": 1, "cues": [{"name": "word", "scene": "braille", "text": "exit"}]})");
    const std::string motion = std::string(ARMADILLO_SOURCE_DIR) + "/Resources/Braille/read-word.pose.csv";
    auto levels = [&](const std::string& extra) {
        const Run r = runArmadillo("render --setlist '" + show + "' --motion '" + motion + "' --out '" + path("slp.wav") + "' --tactile '" +
                                   path("slp.csv") + "'" + extra);
        INFO(r.err);
        REQUIRE(r.code == 0);
        // How often each wrist-row motor took each level: rows "t,m1,…".
        std::array<std::map<int, int>, 3> seen;
        std::istringstream in(readWholeFile(path("slp.csv")));
        std::string line;
        std::getline(in, line);
        while (std::getline(in, line)) {
            std::istringstream f(line);
            std::string cell;
            std::getline(f, cell, ',');
            for (std::size_t m = 0; m < 3; ++m) {
                std::getline(f, cell, ',');
                ++seen[m][std::stoi(cell)];
            }
        }
        return seen;
    };
    const auto plain = levels("");
    const auto fitted = levels(" --profile '" + profile + "'");
    for (std::size_t m = 0; m < 3; ++m) CHECK(plain[m].count(5) == 1);   // the cells at level 5
    CHECK(fitted[0].count(10) == 1);   // m1 twice as hard
    CHECK(fitted[0].count(5) == 0);
    CHECK(fitted[1].count(5) == 1);    // m2 unchanged
    CHECK(fitted[2].count(5) == 0);    // m3 at half (2.5, dithered)
    CHECK((fitted[2].count(2) + fitted[2].count(3)) > 0);
    // A bad profile is refused before anything runs, by render and by play, naming the file.
    const std::string bad = file("sl-bad-profile.json", "{\"threshold\": [1, 2]}");
    for (const std::string& cmd : {"render --motion '" + motion + "' --out '" + path("slx.wav") + "'", std::string("play --simulate --seconds 0.2")}) {
        const Run r = runArmadillo(cmd + " --setlist '" + show + "' --profile '" + bad + "'");
        CAPTURE(cmd, r.err);
        CHECK(r.code == 3);
        CHECK(r.err.find("sl-bad-profile.json") != std::string::npos);
    }
}

TEST_CASE("cli: play --map: a panic ends the mapping's notes and sends CC 120 + CC 123 on 16 channels, then nothing until resume", "[cli][panic][mapping]")
{
    // Zones over the whole circle of azimuth: one note always sounds on channel 3 while the
    // mapping runs, so a panic ends exactly one note (1 note-off + 16 × 2 controllers = 33).
    const std::string map = file("panic-map.json", R"({"version": 1, "mappings": [
        {"source": "azimuth", "to": {"midi": "notes", "channel": 3, "velocity": 100,
         "zones": [[0, 90, 60], [90, 180, 62], [180, 270, 64], [270, 360, 65]]}}]})");
    const std::string keys = path("panic-map-keys.sh");
    writeFileAtomically(keys, "sleep 0.3; printf p; sleep 0.8\n");
    const std::string cmd = std::string("sh '") + keys + "' | '" + ARMADILLO_BIN + "' play --scene theremin --map '" + map +
                            "' --simulate --keys --seconds 1.0 --no-audio >'" + path("pm-out.txt") + "' 2>'" + path("pm-err.txt") + "'";
    REQUIRE(std::system(cmd.c_str()) == 0);
    const std::string out = readWholeFile(path("pm-out.txt"));
    INFO(out << readWholeFile(path("pm-err.txt")));
    CHECK(out.find("\"panics\":1") != std::string::npos);
    CHECK(out.find("\"panic_midi_events\":33") != std::string::npos);
    // Without a panic the key is absent (and the mapping ran).
    const Run calm = runArmadillo("play --scene theremin --map '" + map + "' --simulate --seconds 0.5 --no-audio");
    REQUIRE(calm.code == 0);
    CHECK(calm.out.find("panic_midi_events") == std::string::npos);
    CHECK(calm.out.find("\"mapping_midi_events\":0") == std::string::npos);
}
