// `armadillo touch-profile --port PTY` against a simulated reader on a pseudo-terminal (issue 26's
// done-when): the reader plays the device (answers each motor packet with a sensor packet),
// decodes the motor packets itself per docs/DEVICE.md (5 bytes: motor 1 in the high nibble of
// byte 0, …, motor 9 in the high nibble of byte 4, end nibble 0x8 in its low nibble) and answers
// each "? " prompt with y or n by comparing the level the stimulated motor got with its own
// hidden threshold.
#include "CliRun.h"
#include "Core/AtomicFile.h"
#include "PtyDevice.h"
#include <map>
#include <regex>
#include <sstream>

using namespace armadillo::cli;

namespace {

struct ReaderResult {
    int code = -1;
    int prompts = 0;
    long motorPackets = 0;
    long onPackets = 0;   ///< motor packets with some motor on: the stimuli's on-time
    std::string err;
};

/// Runs touch-profile with the reader whose hidden thresholds are `hidden` (m1..m9).
ReaderResult runSimulatedReader(const std::array<int, 9>& hidden, const std::string& outFile)
{
    test::PtyDevice dev({"touch-profile", "--unpaced", "--out", outFile});
    ReaderResult r;
    test::Levels maxSincePrompt {};
    dev.run(
        [&](const test::Levels& levels) {
            bool on = false;
            for (std::size_t m = 0; m < 9; ++m) {
                maxSincePrompt[m] = std::max(maxSincePrompt[m], levels[m]);
                on = on || levels[m] > 0;
            }
            r.onPackets += on;
        },
        [&](const std::string& line) {
            if (line.rfind("? ", 0) != 0) return;
            ++r.prompts;
            // The stimulated motor is the one that was on; the reader's hidden rule decides.
            int motor = -1, level = 0;
            for (int m = 0; m < 9; ++m)
                if (maxSincePrompt[static_cast<std::size_t>(m)] > level) {
                    level = maxSincePrompt[static_cast<std::size_t>(m)];
                    motor = m;
                }
            bool yes = false;
            if (motor >= 0) {
                const int t = hidden[static_cast<std::size_t>(motor)];
                yes = line.find("comfortable") != std::string::npos ? level >= t + 2 : level >= t;
            }
            dev.answer(yes ? "y" : "n");
            maxSincePrompt.fill(0);
        });
    r.code = dev.wait();
    r.motorPackets = dev.motorPackets;
    r.err = dev.err;
    return r;
}

std::vector<int> jsonIntArray(const std::string& json, const std::string& key)
{
    const std::regex re("\"" + key + "\": \\[([0-9, ]*)\\]");
    std::smatch m;
    std::vector<int> out;
    if (!std::regex_search(json, m, re)) return out;
    std::string list = m[1];
    for (std::size_t at = 0; at < list.size();) {
        const auto comma = list.find(',', at);
        out.push_back(std::stoi(list.substr(at, comma - at)));
        if (comma == std::string::npos) break;
        at = comma + 1;
    }
    return out;
}

} // namespace

TEST_CASE("touch-profile over a pty finds nine different thresholds within one level in under 5 minutes of stimuli", "[cli][touch-profile][pty]")
{
    const std::array<int, 9> hidden {2, 5, 9, 3, 7, 12, 4, 6, 10};
    const std::string out = path("touch-profile.json");
    const ReaderResult r = runSimulatedReader(hidden, out);
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string json = armadillo::core::readWholeFile(out);
    INFO(json);
    const std::vector<int> found = jsonIntArray(json, "threshold");
    REQUIRE(found.size() == 9);
    for (std::size_t m = 0; m < 9; ++m) {
        INFO("motor m" << m + 1);
        CHECK(std::abs(found[m] - hidden[m]) <= 1);
    }
    // Stimulus time, counted by the reader itself: each motor packet with a motor on stood for
    // 1/303 s (--unpaced: the 57 600-baud lock-step period, 10 bits × 19 bytes per exchange),
    // and each stimulus is followed by the documented 0.5 s of stillness. The reader's own
    // answering time is not stimulus time (here it is wall-clock milliseconds, during which the
    // link keeps exchanging all-off packets).
    const double seconds = r.onPackets * (10.0 * 19.0 / 57600.0) + r.prompts * 0.5;
    INFO(r.prompts << " prompts, " << r.onPackets << " packets with a motor on: " << seconds << " s of stimuli");
    CHECK(r.prompts > 9 * 5);
    CHECK(seconds < 300.0);
    // The comfortable level: the first level at least two above m5's threshold.
    CHECK(json.find("\"comfort\": " + std::to_string(hidden[4] + 2)) != std::string::npos);
}

TEST_CASE("touch-profile refuses bad usage and a missing port, and --profile checks its file", "[cli][touch-profile]")
{
    CHECK(runArmadillo("touch-profile --out x.json").code == 2);
    CHECK(runArmadillo("touch-profile --simulate").code == 2);
    CHECK(runArmadillo("touch-profile --port /dev/does-not-exist --out " + path("x.json")).code == 4);
    // stdin ends before the procedure does: exit 3, nothing written.
    const Run early = runArmadillo("touch-profile --simulate --unpaced --out " + path("early.json"), file("three.txt", "y\nn\ny\n"));
    CHECK(early.code == 3);
    CHECK_FALSE(std::filesystem::exists(path("early.json")));
    // A bad profile is refused with its file and key named (exit 3).
    const std::string bad = file("bad-profile.json", "{\"threshold\": [1, 2, 3]}");
    const Run r = runArmadillo("render --scene braille --text exit --motion " + std::string(ARMADILLO_SOURCE_DIR) +
                               "/Resources/Braille/read-word.pose.csv --out " + path("o.wav") + " --profile " + bad);
    CHECK(r.code == 3);
    CHECK(r.err.find("bad-profile.json") != std::string::npos);
    CHECK(r.err.find("threshold") != std::string::npos);
}

TEST_CASE("render --profile: each motor's levels scaled by its threshold over the median, before the safety stage", "[cli][touch-profile]")
{
    // Thresholds 8, 4, 2 on the wrist row, 4 elsewhere: median 4, so m1 ×2, m2 ×1, m3 ×0.5.
    const std::string profile = file("fit.json", "{\"threshold\": [8, 4, 2, 4, 4, 4, 4, 4, 4]}");
    const std::string motion = std::string(ARMADILLO_SOURCE_DIR) + "/Resources/Braille/read-word.pose.csv";
    auto levels = [&](const std::string& extra) {
        const Run r = runArmadillo("render --scene braille --text exit --motion " + motion + " --out " + path("p.wav") + " --tactile " +
                                   path("p.csv") + extra);
        REQUIRE(r.code == 0);
        // Every level each wrist-row motor took, counted: rows "t,m1,…,m9".
        std::array<std::map<int, int>, 3> seen;
        std::istringstream in(armadillo::core::readWholeFile(path("p.csv")));
        std::string line;
        std::getline(in, line);
        while (std::getline(in, line)) {
            std::istringstream f(line);
            std::string cell;
            std::getline(f, cell, ',');
            for (int m = 0; m < 3; ++m) {
                std::getline(f, cell, ',');
                ++seen[static_cast<std::size_t>(m)][std::stoi(cell)];
            }
        }
        return seen;
    };
    const auto plain = levels("");
    const auto fitted = levels(" --profile " + profile);
    // Without a profile the cells are at level 5 (after the 15-level jump-start).
    for (int m = 0; m < 3; ++m) CHECK(plain[static_cast<std::size_t>(m)].count(5) == 1);
    // m1 twice as hard (10, still under the run limit: a pulse is 0.25 s), m2 unchanged,
    // m3 at half (2.5: dithered between 2 and 3), never at 5.
    CHECK(fitted[0].count(10) == 1);
    CHECK(fitted[0].count(5) == 0);
    CHECK(fitted[1].count(5) == 1);
    CHECK(fitted[2].count(5) == 0);
    CHECK((fitted[2].count(2) + fitted[2].count(3)) > 0);
}
