// `armadillo render --setlist` as a user runs it: the cue changes heard in the WAV, and every
// mistake refused with its exit code (2 usage, 3 bad input) and a message naming the problem.
#include "CliRun.h"
#include "Core/Wav.h"
#include <catch2/catch.hpp>
#include <cmath>

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
