// The app's status line (Live/Session/StatusLine.h) reports only what the counters show: a source that
// stops sending is "silent" within a second, a steady one its rate; audio and motors likewise.
#include "Live/Session/StatusLine.h"
#include <catch2/catch.hpp>

using armadillo::live::SourceKind;
using armadillo::live::StatusLine;
using armadillo::live::StatusSnapshot;

namespace {
StatusSnapshot at(double t, SourceKind source, std::uint64_t samples, std::uint64_t blocks = 0)
{
    StatusSnapshot s;
    s.now = t;
    s.source = source;
    s.sourceSamples = samples;
    s.audioBlocks = blocks;
    return s;
}
} // namespace

TEST_CASE("status line: a connected device that sends nothing is silent within a second, never alive", "[status]")
{
    StatusLine line;
    double silentAt = -1.0;
    for (int i = 0; i <= 30; ++i) {   // the editor's 10 Hz timer for 3 s; the packet counter never moves
        auto s = at(100.0 + i * 0.1, SourceKind::Device, 0);
        s.deviceConnected = true;
        s.deviceName = "/dev/ttyUSB0";
        const auto text = line.update(s);
        CHECK_THAT(text, !Catch::Contains("packets/s"));
        CHECK(line.sourceRate() == 0.0);
        if (line.sourceSilent() && silentAt < 0.0) silentAt = i * 0.1;
        if (i * 0.1 >= 1.0) CHECK_THAT(text, Catch::Contains("silent"));
    }
    CHECK(silentAt >= 0.0);
    CHECK(silentAt <= 1.0);
}

TEST_CASE("status line: a steady source shows its rate; when it stops it turns silent within a second", "[status]")
{
    StatusLine line;
    std::uint64_t packets = 0;
    std::string text;
    for (int i = 0; i <= 20; ++i) {   // 200 packets/s for 2 s
        auto s = at(i * 0.1, SourceKind::Device, packets);
        s.deviceConnected = true;
        s.deviceName = "sim";
        text = line.update(s);
        packets += 20;
    }
    CHECK_FALSE(line.sourceSilent());
    CHECK(line.sourceRate() == Approx(200.0).margin(1.0));
    CHECK_THAT(text, Catch::Contains("200 packets/s"));
    // It stops: the last count stays.
    const auto last = packets - 20;
    double silentAfter = -1.0;
    for (int i = 1; i <= 15; ++i) {
        auto s = at(2.0 + i * 0.1, SourceKind::Device, last);
        s.deviceConnected = true;
        s.deviceName = "sim";
        text = line.update(s);
        if (line.sourceSilent() && silentAfter < 0.0) silentAfter = i * 0.1;
    }
    CHECK(silentAfter > 0.0);
    CHECK(silentAfter <= 1.0);
    CHECK_THAT(text, Catch::Contains("silent"));
}

TEST_CASE("status line: each source, the audio and the motors are named as they are", "[status]")
{
    StatusLine line;
    // Simulator at 200 steps/s with audio flowing at 48 kHz / 512 (94 blocks/s).
    std::string text;
    for (int i = 0; i <= 10; ++i) {
        auto s = at(i * 0.1, SourceKind::Simulator, static_cast<std::uint64_t>(i * 20), static_cast<std::uint64_t>(i * 9));
        s.outputPeak = 0.25f;
        text = line.update(s);
    }
    CHECK_THAT(text, Catch::Contains("simulated arm (200 steps/s)"));
    CHECK_THAT(text, Catch::Contains("Audio: running, output -12 dBFS peak"));
    CHECK_THAT(text, Catch::Contains("Motors: off (no device connected"));
    CHECK(line.audioFlowing());

    // The audio stops (no sound card): within half a second it says so.
    for (int i = 11; i <= 16; ++i) text = line.update(at(i * 0.1, SourceKind::Simulator, static_cast<std::uint64_t>(i * 20), 90));
    CHECK_FALSE(line.audioFlowing());
    CHECK_THAT(text, Catch::Contains("Audio: not running"));

    // OSC chosen while OSC in is off; the device chosen while none is connected.
    text = line.update(at(2.0, SourceKind::Osc, 0));
    CHECK_THAT(text, Catch::Contains("OSC in is off"));
    text = line.update(at(2.1, SourceKind::Device, 0));
    CHECK_THAT(text, Catch::Contains("device, not connected"));

    // A listening scene with the standalone's input muted says so; motors driven are counted.
    auto s = at(2.2, SourceKind::Device, 0);
    s.deviceConnected = true;
    s.listens = true;
    s.inputMuted = 1;
    s.motorsActive = 3;
    text = line.update(s);
    CHECK_THAT(text, Catch::Contains("Input: MUTED"));
    CHECK_THAT(text, Catch::Contains("Motors: on (3 of 9 driven)"));
}

TEST_CASE("status line: the left arm's sender is live while its counter moves, silent when it stops, absent when off", "[plugin][status][two-arms]")
{
    StatusLine line;
    // Off: no left-arm part at all (the line as before issue 28's left arm).
    auto off = at(10.0, SourceKind::HostAutomation, 0);
    CHECK_THAT(line.update(off), !Catch::Contains("Left arm"));
    CHECK(line.leftArmSilent());
    // On, nothing received yet: silent at once (never "live" without a sample).
    auto s = at(10.1, SourceKind::HostAutomation, 0);
    s.leftArmPort = 9003;
    auto text = line.update(s);
    CHECK_THAT(text, Catch::Contains("Left arm: OSC port 9003 (silent, nothing received)"));
    // 100 messages/s for a second: live.
    for (int i = 1; i <= 10; ++i) {
        s.now = 10.1 + i * 0.1;
        s.leftArmSamples = static_cast<std::uint64_t>(i * 10);
        text = line.update(s);
    }
    CHECK_THAT(text, Catch::Contains("Left arm: OSC port 9003 (live)"));
    CHECK_FALSE(line.leftArmSilent());
    // The sender stops: silent within kSilentAfter (+ one 10 Hz tick).
    double silentAfter = -1.0;
    for (int i = 1; i <= 20 && silentAfter < 0.0; ++i) {
        s.now = 11.1 + i * 0.1;
        text = line.update(s);
        if (line.leftArmSilent()) silentAfter = i * 0.1;
    }
    CHECK(silentAfter > 0.0);
    CHECK(silentAfter <= StatusLine::kSilentAfter + 0.1 + 1e-9);
    CHECK_THAT(text, Catch::Contains("Left arm: OSC port 9003 (silent"));
}
