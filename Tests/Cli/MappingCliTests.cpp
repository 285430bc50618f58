// `armadillo render --map … --midi-out OUT.mid` and `--osc-out` as a user runs them (issue 23's
// Done-when): the written Standard MIDI File is read back with the test's own SMF reader and
// decoded by the MIDI 1.0 rules (and, for the scenerotator preset, by IEM SceneRotator's own
// arithmetic); OSC is caught on a loopback UDP socket. Expected values come from the motion file
// the test writes, through the definitions in the issue and docs/MAPPING.md.
#include "Cli/CliRun.h"
#include "Osc/Osc.h"
#include "Mapping/SmfReader.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <arpa/inet.h>
#include <cmath>
#include <fcntl.h>
#include <map>
#include <netinet/in.h>
#include <poll.h>
#include <csignal>
#include <sys/wait.h>
#include <sstream>
#include <sys/socket.h>
#include <unistd.h>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::cli;
using armadillo::mapping::test::readSmf;
using armadillo::mapping::test::Smf;

namespace {

struct Row {
    double t, el, az, roll;
};

std::string posesCsv(const std::vector<Row>& rows)
{
    std::ostringstream s;
    s.precision(10);
    s << "t,elevation,azimuth,roll\n";
    for (const Row& r : rows) s << r.t << "," << r.el << "," << r.az << "," << r.roll << "\n";
    return s.str();
}

std::vector<std::uint8_t> readBytes(const std::string& p)
{
    const std::string s = readWholeFile(p);
    return {s.begin(), s.end()};
}

int expected14(double x, double lo, double hi)
{
    const double n = std::clamp((x - lo) / (hi - lo), 0.0, 1.0);
    return static_cast<int>(std::lround(n * 16383.0));
}

/// The row each event belongs to (the nearest row time), and how far from it the event lies.
std::size_t nearestRow(const std::vector<Row>& rows, double seconds, double& distance)
{
    std::size_t best = 0;
    distance = 1e9;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const double d = std::fabs(rows[i].t - rows[0].t - seconds);
        if (d < distance) {
            distance = d;
            best = i;
        }
    }
    return best;
}

/// A UDP socket on 127.0.0.1 with a port of the system's choosing.
struct Loopback {
    int fd = -1;
    int port = 0;
    Loopback()
    {
        fd = ::socket(AF_INET, SOCK_DGRAM, 0);
        REQUIRE(fd >= 0);
        int size = 4 * 1024 * 1024;
        ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &size, sizeof size);
        sockaddr_in a {};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        a.sin_port = 0;
        REQUIRE(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
        socklen_t len = sizeof a;
        REQUIRE(::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) == 0);
        port = ntohs(a.sin_port);
        ::fcntl(fd, F_SETFL, O_NONBLOCK);
    }
    ~Loopback() { ::close(fd); }
    std::vector<std::vector<std::uint8_t>> drain() const
    {
        std::vector<std::vector<std::uint8_t>> out;
        std::uint8_t buf[2048];
        for (;;) {
            const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
            if (n <= 0) break;
            out.emplace_back(buf, buf + n);
        }
        return out;
    }
};

const char* const kIssueExample = R"({"version": 1, "mappings": [
  {"source": "elevation", "in": [-45, 45], "to": {"midi": "cc14", "channel": 1, "cc": 1}},
  {"source": "roll", "in": [-90, 90], "curve": "linear", "to": {"midi": "pitchbend", "channel": 2}},
  {"source": "azimuth", "to": {"midi": "notes", "channel": 3, "velocity": 100,
     "zones": [[0, 90, 60], [90, 180, 62], [180, 270, 64], [270, 360, 65]]}},
  {"source": "elevation", "in": [-90, 90], "out": [0, 1], "to": {"osc": "/synth/cutoff"}}]})";

} // namespace

TEST_CASE("render --map FILE --midi-out: the issue's example, row by row", "[cli][mapping]")
{
    // 6 s at 200 Hz from t = 3.7 s: azimuth 60 → 100° (crossing 90° once), then wiggling ±1.5°
    // across 90° for 2 s, then 90 → 200° (crossing 180° once); elevation and roll sweep past
    // their `in` ranges so clamping is exercised too.
    std::vector<Row> rows;
    for (int i = 0; i < 1200; ++i) {
        const double s = i * 0.005;
        double az = 0.0;
        if (s < 2.0) az = 60.0 + 20.0 * s;
        else if (s < 4.0) az = 90.0 + 1.5 * std::sin((s - 2.0) * 37.0);
        else az = 90.0 + 55.0 * (s - 4.0);
        rows.push_back({3.7 + s, 60.0 * std::sin(s * 1.3), az, 110.0 * std::sin(s * 0.9 + 0.4)});
    }
    const std::string motion = file("map-poses.csv", posesCsv(rows));
    const std::string map = file("issue-map.json", kIssueExample);
    const std::string mid = path("issue.mid");
    const Run r = runArmadillo("render --scene monitor --motion '" + motion + "' --map '" + map + "' --midi-out '" + mid + "'");
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("\"mapping_midi_events\":"));
    const Smf smf = readSmf(readBytes(mid));
    REQUIRE(smf.format == 1);

    // Every event belongs to a row (within 1 ms) and is one the mapping names (nothing else is sent).
    std::vector<std::vector<const armadillo::mapping::test::SmfEvent*>> byRow(rows.size());
    for (const auto& e : smf.events) {
        double d = 0.0;
        const std::size_t row = nearestRow(rows, e.seconds, d);
        CHECK(d <= 0.001);
        byRow[row].push_back(&e);
        const int status = e.bytes[0];
        const bool cc14 = status == 0xB0 && (e.bytes[1] == 1 || e.bytes[1] == 33);
        const bool bend = status == 0xE1;
        const bool note = status == 0x92 || status == 0x82;
        CHECK((cc14 || bend || note));
    }

    // Replay row by row: after each row the receiver's state decodes to the expected values.
    int msb = -1, lsb = -1, bendValue = -1;
    std::vector<std::pair<int, int>> notes;   // (on?, note) with the row index in notesRow
    std::vector<std::size_t> notesRow;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        for (const auto* e : byRow[i]) {
            if (e->bytes[0] == 0xB0 && e->bytes[1] == 1) msb = e->bytes[2];
            if (e->bytes[0] == 0xB0 && e->bytes[1] == 33) lsb = e->bytes[2];
            if (e->bytes[0] == 0xE1) bendValue = e->bytes[1] | (e->bytes[2] << 7);
            if (e->bytes[0] == 0x92 || e->bytes[0] == 0x82) {
                notes.push_back({e->bytes[0] == 0x92 && e->bytes[2] > 0, e->bytes[1]});
                notesRow.push_back(i);
                if (e->bytes[0] == 0x92) CHECK(e->bytes[2] == 100);
            }
        }
        CHECK(std::abs(128 * msb + lsb - expected14(rows[i].el, -45.0, 45.0)) <= 1);
        CHECK(std::abs(bendValue - expected14(rows[i].roll, -90.0, 90.0)) <= 1);
    }
    // MSB before LSB in every pair (MIDI 1.0).
    for (std::size_t k = 0; k + 1 < smf.events.size(); ++k)
        if (smf.events[k].bytes[0] == 0xB0 && smf.events[k].bytes[1] == 1) CHECK(smf.events[k + 1].bytes[1] == 33);

    // Notes: the start zone's note from the first row, then exactly one off/on pair per border crossing.
    REQUIRE(notes.size() == 6);   // … and the sounding note ends with the render
    CHECK(notes[0] == std::make_pair(1, 60));
    CHECK(notesRow[0] == 0);
    CHECK(notes[1] == std::make_pair(0, 60));
    CHECK(notes[2] == std::make_pair(1, 62));
    CHECK(notesRow[1] == notesRow[2]);
    CHECK(notes[3] == std::make_pair(0, 62));
    CHECK(notes[4] == std::make_pair(1, 64));
    CHECK(notes[5] == std::make_pair(0, 64));
    CHECK(notesRow[5] == rows.size() - 1);
    // Each pair comes once the azimuth is past the border by the hysteresis (1.5° … 5°), not before.
    const double past1 = rows[notesRow[1]].az - 90.0, past2 = rows[notesRow[3]].az - 180.0;
    CHECK(past1 >= 1.5);
    CHECK(past1 <= 5.0 + 20.0 * 0.005);
    CHECK(past2 >= 1.5);
    CHECK(past2 <= 5.0 + 55.0 * 0.005);
    // No note at all while the azimuth wiggles across 90° (rows of 2 … 4 s).
    CHECK(notesRow[3] > 800);
}

TEST_CASE("render --map scenerotator: SceneRotator's decoding within 0.05°, LSB first; the OSC preset on loopback", "[cli][mapping]")
{
    std::vector<Row> rows;
    for (int i = 0; i < 60; ++i) {
        const double s = i * 0.01;
        rows.push_back({s, -70.0 + 2.3 * i, std::fmod(350.0 + 11.7 * i, 360.0), -170.0 + 5.6 * i});
    }
    const std::string motion = file("sr-poses.csv", posesCsv(rows));
    const std::string mid = path("sr.mid");
    Run r = runArmadillo("render --scene monitor --motion '" + motion + "' --map scenerotator --midi-out '" + mid + "'");
    INFO(r.err);
    REQUIRE(r.code == 0);
    const Smf smf = readSmf(readBytes(mid));
    // IEM SceneRotator (PluginProcessor.cpp, processBlock): CC 48+k stores the LSB, CC 16+k sets the
    // parameter to (128·MSB + LSB)/16384 of its −180…180° range.
    int lsb[3] {0, 0, 0};
    bool fresh[3] {false, false, false};
    double angle[3] {0, 0, 0};
    std::size_t row = 0;
    int decoded = 0;
    for (std::size_t k = 0; k < smf.events.size(); ++k) {
        const auto& e = smf.events[k];
        REQUIRE((e.bytes[0] & 0xF0) == 0xB0);   // controllers only
        const int cc = e.bytes[1];
        if (cc >= 48 && cc <= 50) {
            lsb[cc - 48] = e.bytes[2];
            fresh[cc - 48] = true;
            continue;
        }
        REQUIRE((cc >= 16 && cc <= 18));
        CHECK(fresh[cc - 16]);   // its LSB came first
        fresh[cc - 16] = false;
        angle[cc - 16] = -180.0 + 360.0 * ((128 * e.bytes[2] + lsb[cc - 16]) * (1.0 / 16384));
        double d = 0.0;
        row = nearestRow(rows, e.seconds, d);
        CHECK(d <= 0.001);
        const bool lastOfRow = k + 1 == smf.events.size() || std::fabs(smf.events[k + 1].seconds - e.seconds) > 0.002;
        if (lastOfRow && row > 0) {   // every angle has been sent at least once by now
            const double yaw = -std::remainder(rows[row].az, 360.0), pitch = rows[row].el, roll = rows[row].roll;
            CHECK(std::fabs(std::remainder(angle[0] - yaw, 360.0)) <= 0.05);
            CHECK(std::fabs(angle[1] - pitch) <= 0.05);
            CHECK(std::fabs(std::remainder(angle[2] - roll, 360.0)) <= 0.05);
            ++decoded;
        }
    }
    CHECK(decoded >= 50);

    Loopback udp;
    r = runArmadillo("render --scene monitor --motion '" + motion + "' --map scenerotator-osc --osc-out 127.0.0.1:" + std::to_string(udp.port) +
                     " --midi-out '" + path("sr-osc.mid") + "'");
    INFO(r.err);
    REQUIRE(r.code == 0);
    const auto packets = udp.drain();
    CHECK(packets.size() == 2 * rows.size());
    std::size_t ypr = 0;
    for (const auto& p : packets) {
        REQUIRE(osc::decodeOscPacket(p.data(), p.size(), [&](const osc::OscMessage& m) {
            if (m.address != "/SceneRotator/ypr") return;
            REQUIRE(m.types == "fff");
            REQUIRE(ypr < rows.size());
            const Row& w = rows[ypr++];   // one per row, in order (every row moves the arm)
            CHECK(std::fabs(std::remainder(double(m.args[0].f) - (-std::remainder(w.az, 360.0)), 360.0)) <= 0.05);
            CHECK(std::fabs(double(m.args[1].f) - w.el) <= 0.05);
            CHECK(std::fabs(std::remainder(double(m.args[2].f) - w.roll, 360.0)) <= 0.05);
        }));
    }
    CHECK(ypr == rows.size());
    // The MIDI file of an OSC-only mapping holds no events.
    CHECK(readSmf(readBytes(path("sr-osc.mid"))).events.empty());
}

TEST_CASE("--map: bad input and bad usage get the documented exit codes and messages", "[cli][mapping]")
{
    const std::string motion = file("tiny.csv", posesCsv({{0.0, 0, 0, 0}, {0.01, 1, 1, 1}}));
    Run r = runArmadillo("render --scene monitor --motion '" + motion + "' --map '" + file("bad-map.json", "{\"version\": 1,\n \"mappings\": [{\"source\": \"elbow\", \"to\": {\"macro\": 1}}]}") +
                         "' --midi-out '" + path("x.mid") + "'");
    CHECK(r.code == 3);
    CHECK_THAT(r.err, Catch::Contains("bad-map.json:2:") && Catch::Contains("column") && Catch::Contains("elbow"));
    CHECK_FALSE(std::filesystem::exists(path("x.mid")));
    r = runArmadillo("render --scene monitor --motion '" + motion + "' --map no-such-preset --midi-out '" + path("x.mid") + "'");
    CHECK(r.code == 4);
    CHECK_THAT(r.err, Catch::Contains("no-such-preset") && Catch::Contains("scenerotator"));
    r = runArmadillo("render --scene monitor --motion '" + motion + "' --midi-out '" + path("x.mid") + "'");
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("--map"));
    r = runArmadillo("render --scene monitor --motion '" + motion + "' --map classic");
    CHECK(r.code == 2);
    r = runArmadillo("render --scene monitor --motion '" + motion + "' --map '" + file("p.json", R"({"version": 1, "mappings": [{"source": "roll", "to": {"param": "theremin.range"}}]})") +
                     "' --midi-out '" + path("x.mid") + "'");
    CHECK(r.code == 3);
    CHECK_THAT(r.err, Catch::Contains("theremin.range"));
    r = runArmadillo("play --scene monitor --simulate --seconds 1 --no-audio --midi-out ARMadillo");
    CHECK(r.code == 2);
}

TEST_CASE("play --map --midi-out opens an ALSA sequencer port, or says why it cannot (exit 4)", "[cli][mapping]")
{
    const Run r = runArmadillo("play --scene monitor --simulate --unpaced --seconds 0.5 --no-audio --map classic --midi-out 'ARMadillo test'");
    INFO(r.err);
    if (std::filesystem::exists("/dev/snd/seq")) {
        CHECK(r.code == 0);
        CHECK_THAT(r.out, Catch::Contains("\"mapping_midi_events\":"));
    } else {
        CHECK(r.code == 4);
        CHECK_THAT(r.err, Catch::Contains("ALSA sequencer") && Catch::Contains("/dev/snd/seq"));
    }
}

TEST_CASE("play --map sends the mapping's OSC (and only it) to --osc-out", "[cli][mapping]")
{
    Loopback udp;
    const std::string map = file("play-osc.json", R"({"version": 1, "mappings": [{"source": "elevation", "to": {"osc": "/el", "args": ["$elevation"]}}]})");
    const Run r = runArmadillo("play --scene monitor --simulate --seconds 0.5 --no-audio --map '" + map + "' --osc-out 127.0.0.1:" +
                               std::to_string(udp.port));
    INFO(r.err);
    REQUIRE(r.code == 0);
    const auto packets = udp.drain();
    CHECK(packets.size() > 5);
    for (const auto& p : packets)
        osc::decodeOscPacket(p.data(), p.size(), [&](const osc::OscMessage& m) {
            CHECK(m.address == "/el");   // no /armadillo/* stream with --map
            CHECK(std::fabs(m.args[0].f) <= 90.0f);
        });
}

TEST_CASE("resources lists the mapping presets", "[cli][mapping]")
{
    const Run r = runArmadillo("resources --mappings");
    REQUIRE(r.code == 0);
    for (const char* n : {"classic\n", "mpe\n", "scenerotator\n", "scenerotator-osc\n"}) CHECK_THAT(r.out, Catch::Contains(n));
}

TEST_CASE("map check / show / learn-posture", "[cli][mapping]")
{
    Run r = runArmadillo("map check scenerotator");
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("\"mappings\":3"));
    r = runArmadillo("map check '" + file("bad-cc.json", "{\"version\": 1, \"mappings\": [\n{\"source\": \"roll\", \"to\": {\"midi\": \"cc\", \"cc\": 300}}]}") + "'");
    CHECK(r.code == 3);
    CHECK_THAT(r.err, Catch::Contains("bad-cc.json:2:") && Catch::Contains("mappings[0].to.cc") && Catch::Contains("300"));
    r = runArmadillo("map show classic");
    REQUIRE(r.code == 0);
    const std::string shown = file("classic-copy.json", r.out);
    r = runArmadillo("map check '" + shown + "'");
    CHECK(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("\"mappings\":7"));
    r = runArmadillo("map frobnicate");
    CHECK(r.code == 2);

    // A held pose (small tremor) becomes a posture that a mapping then plays from.
    std::vector<Row> hold, later;
    for (int i = 0; i < 300; ++i) hold.push_back({i * 0.01, 45.0 + 0.5 * std::sin(i * 0.05), 300.0 + 0.5 * std::cos(i * 0.04), 30.0});
    const std::string map = file("posture-map.json", R"({"version": 1, "mappings": [{"source": "posture:salute", "to": {"midi": "note", "channel": 2, "note": 70}}],
        "postures": [{"name": "salute", "examples": [[1, 0, 0, 0]]}]})");
    r = runArmadillo("map learn-posture --name salute --motion '" + file("hold.csv", posesCsv(hold)) + "' --map '" + map + "' --out '" + path("learned.json") + "'");
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("\"examples\":64"));
    for (int i = 0; i < 200; ++i) {
        const double s = i * 0.01;
        const bool held = s >= 0.5 && s < 1.5;
        later.push_back({s, held ? 45.0 : -30.0, held ? 300.0 : 100.0, held ? 30.0 : 0.0});
    }
    r = runArmadillo("render --scene monitor --motion '" + file("later.csv", posesCsv(later)) + "' --map '" + path("learned.json") + "' --midi-out '" +
                     path("posture.mid") + "'");
    INFO(r.err);
    REQUIRE(r.code == 0);
    const Smf smf = readSmf(readBytes(path("posture.mid")));
    REQUIRE(smf.events.size() == 2);
    CHECK(smf.events[0].bytes == std::vector<std::uint8_t> {0x91, 70, 100});
    // The row of the jump into the pose moves at thousands of °/s (the orientation's own rate):
    // no posture is held while moving, so the note starts at the next, still row.
    CHECK(smf.events[0].seconds >= 0.5);
    CHECK(smf.events[0].seconds <= 0.511);
    CHECK(smf.events[1].bytes[0] == 0x81);
    CHECK(smf.events[1].seconds == Approx(1.5).margin(0.001));
    r = runArmadillo("map learn-posture --name blur --motion '" + file("empty-hold.csv", posesCsv({{0.0, 0, 0, 0}, {0.01, 0, 0, 0}})) + "' --out '" + path("no.json") + "'");
    CHECK(r.code == 3);
    CHECK_THAT(r.err, Catch::Contains("still samples"));
    CHECK_FALSE(std::filesystem::exists(path("no.json")));
}

TEST_CASE("--forward sets where yaw is measured from; play takes SIGUSR1 as 'set forward now'", "[cli][mapping]")
{
    // render: an arm pointing east (90°) with forward 90 has yaw 0 on the scenerotator preset.
    const std::string motion = file("east.csv", posesCsv({{0.0, 10.0, 90.0, 0.0}, {0.01, 10.0, 90.0, 0.0}}));
    Run r = runArmadillo("render --scene monitor --motion '" + motion + "' --map scenerotator --forward 90 --midi-out '" + path("east.mid") + "'");
    INFO(r.err);
    REQUIRE(r.code == 0);
    int lsb = 0;
    double yaw = 999.0;
    for (const auto& e : readSmf(readBytes(path("east.mid"))).events) {
        if (e.bytes[1] == 48) lsb = e.bytes[2];
        if (e.bytes[1] == 16) yaw = -180.0 + 360.0 * (128 * e.bytes[2] + lsb) / 16384.0;
    }
    CHECK(std::fabs(yaw) <= 0.05);
    CHECK(runArmadillo("render --scene monitor --motion '" + motion + "' --map scenerotator --forward 400 --midi-out '" + path("e.mid") + "'").code == 2);

    // play: the simulated arm holds still pointing north; forward starts at 180 (yaw ±180), then
    // SIGUSR1 makes the current direction forward (yaw 0). The test waits for messages, not time.
    Loopback udp;
    const std::string map = file("yaw-osc.json", R"({"version": 1, "mappings": [{"source": "yaw", "to": {"osc": "/yaw", "args": ["$yaw"]}}]})");
    const std::string still = file("still.csv", posesCsv({{0.0, 0.0, 0.0, 0.0}, {1.0, 0.0, 0.0, 0.0}}));
    const std::string port = "127.0.0.1:" + std::to_string(udp.port);   // before the fork: no allocation in the child
    const pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        const int quiet = ::open("/dev/null", O_WRONLY);
        ::dup2(quiet, STDOUT_FILENO);
        ::dup2(quiet, STDERR_FILENO);
        ::execl(ARMADILLO_BIN, ARMADILLO_BIN, "play", "--scene", "monitor", "--simulate", "--motion", still.c_str(), "--seconds", "20", "--no-audio",
                "--map", map.c_str(), "--forward", "180", "--osc-out", port.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    const auto nextYaw = [&](float& out) {
        pollfd p {udp.fd, POLLIN, 0};
        if (::poll(&p, 1, 5000) <= 0) return false;
        std::uint8_t buf[512];
        const ssize_t n = ::recv(udp.fd, buf, sizeof buf, 0);
        if (n <= 0) return false;
        return osc::decodeOscPacket(buf, static_cast<std::size_t>(n), [&](const osc::OscMessage& m) { out = m.args[0].f; });
    };
    float y = 0.0f;
    int before = 0;
    // Fusion settles first; then the yaw is near ±180.
    for (int i = 0; i < 2000 && before < 20; ++i) {
        if (!nextYaw(y)) break;
        before = std::fabs(y) > 170.0f ? before + 1 : 0;
    }
    CHECK(before == 20);
    ::kill(pid, SIGUSR1);
    bool zeroed = false;
    for (int i = 0; i < 2000 && !zeroed; ++i) {
        if (!nextYaw(y)) break;
        zeroed = std::fabs(y) < 5.0f;
    }
    CHECK(zeroed);
    ::kill(pid, SIGTERM);
    int status = 0;
    ::waitpid(pid, &status, 0);
    CHECK(WIFEXITED(status));
}

TEST_CASE("render --map --osc-out: the issue example's OSC destination sends out over in, per row", "[cli][mapping]")
{
    std::vector<Row> rows;
    for (int i = 0; i < 200; ++i) rows.push_back({i * 0.005, -80.0 + 0.8 * i, 45.0, 0.0});
    Loopback udp;
    const Run r = runArmadillo("render --scene monitor --motion '" + file("osc-poses.csv", posesCsv(rows)) + "' --map '" + file("issue-map-2.json", kIssueExample) +
                               "' --osc-out 127.0.0.1:" + std::to_string(udp.port) + " --midi-out '" + path("osc.mid") + "'");
    INFO(r.err);
    REQUIRE(r.code == 0);
    const auto packets = udp.drain();
    REQUIRE(packets.size() == rows.size());   // every row changes the elevation: one message each
    for (std::size_t i = 0; i < packets.size(); ++i) {
        REQUIRE(osc::decodeOscPacket(packets[i].data(), packets[i].size(), [&](const osc::OscMessage& m) {
            CHECK(m.address == "/synth/cutoff");
            REQUIRE(m.types == "f");
            CHECK(m.args[0].f == Approx((rows[i].el + 90.0) / 180.0).margin(1e-6));
        }));
    }
}

TEST_CASE("render --motion-left --map: each arm's sources from its own file, the angle between the forearms, both arms raised", "[cli][mapping][twoarms]")
{
    // 4 s at 100 Hz. The right arm rises (−20 → 60°) in the first 2 s and then holds; the left
    // arm holds 45° and then falls (45 → −30°) in the last 2 s. Right points north, left east.
    std::vector<Row> right, left;
    for (int i = 0; i <= 400; ++i) {
        const double t = i * 0.01;
        right.push_back({t, t < 2.0 ? -20.0 + 40.0 * t : 60.0, 0.0, 0.0});
        left.push_back({t, t < 2.0 ? 45.0 : 45.0 - 37.5 * (t - 2.0), 90.0, 0.0});
    }
    const std::string map = file("two-arm-map.json", R"({"version": 1, "mappings": [
        {"source": "elevation", "to": {"midi": "cc", "channel": 1, "cc": 1}},
        {"source": "left.elevation", "to": {"midi": "cc", "channel": 1, "cc": 2}},
        {"source": "arms.angle", "in": [0, 180], "to": {"midi": "cc14", "channel": 2, "cc": 3}},
        {"source": "arms.raised", "to": {"midi": "note", "channel": 3, "note": 40}}]})");
    Run r = runArmadillo("map check '" + map + "'");
    CHECK(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("\"two_arm_mappings\":3"));
    r = runArmadillo("map show '" + map + "'");   // written back with the same names, and read back
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("\"left.elevation\"") && Catch::Contains("\"arms.angle\"") && Catch::Contains("\"arms.raised\""));
    CHECK(runArmadillo("map check '" + file("two-arm-map-shown.json", r.out) + "'").code == 0);
    r = runArmadillo("map check '" + file("two-arm-bad.json", "{\"version\": 1, \"mappings\": [\n  {\"source\": \"left.arms.angle\", \"to\": {\"macro\": 1}}]}") + "'");
    CHECK(r.code == 3);
    CHECK_THAT(r.err, Catch::Contains("two-arm-bad.json:2: column 14: mappings[0].source") && Catch::Contains("unknown source \"left.arms.angle\""));
    const std::string mid = path("two-arms.mid");
    r = runArmadillo("render --scene theremin-duo --motion '" + file("two-right.csv", posesCsv(right)) + "' --motion-left '" +
                     file("two-left.csv", posesCsv(left)) + "' --map '" + map + "' --midi-out '" + mid + "'");
    INFO(r.err);
    REQUIRE(r.code == 0);
    const Smf smf = readSmf(readBytes(mid));
    int cc1 = 0, cc2 = 0, msb = -1, lsb = -1;
    double noteOn = -1.0, noteOff = -1.0, worstAngle = 0.0;
    std::vector<std::vector<const armadillo::mapping::test::SmfEvent*>> byRow(right.size());
    for (const auto& e : smf.events) {
        double d = 0.0;
        byRow[nearestRow(right, e.seconds, d)].push_back(&e);
        if (e.bytes[0] == 0xB0 && e.bytes[1] == 1) {   // the right arm's CC: only while it moves (and its first value)
            ++cc1;
            CHECK((e.seconds <= 2.0 + 0.011 || e.seconds == 0.0));
        }
        if (e.bytes[0] == 0xB0 && e.bytes[1] == 2) {   // the left arm's: only while it moves
            ++cc2;
            CHECK((e.seconds >= 2.0 - 0.011 || e.seconds == 0.0));
        }
        if (e.bytes[0] == 0x92 && e.bytes[2] > 0) noteOn = e.seconds;
        if (e.bytes[0] == 0x82) noteOff = e.seconds;
    }
    CHECK(cc1 > 50);
    CHECK(cc2 > 50);
    // The angle between the forearms, row by row, against the spherical law of cosines on the
    // two files' poses (azimuths 0° and 90°: cos θ = sin e₁ sin e₂).
    for (std::size_t i = 0; i < right.size(); ++i) {
        for (const auto* e : byRow[i]) {
            if (e->bytes[0] == 0xB1 && e->bytes[1] == 3) msb = e->bytes[2];
            if (e->bytes[0] == 0xB1 && e->bytes[1] == 35) lsb = e->bytes[2];
        }
        const double d = 3.14159265358979323846 / 180.0;
        const double truth = std::acos(std::sin(right[i].el * d) * std::sin(left[i].el * d)) / d;
        const double got = (128 * msb + lsb) / 16383.0 * 180.0;
        worstAngle = std::max(worstAngle, std::fabs(got - truth));
    }
    std::printf("render two arms: arms.angle from the MIDI file vs the files' geometry, largest difference %.4f deg\n", worstAngle);
    CHECK(worstAngle < 0.03);   // one 14-bit step over 180° is 0.011°
    // Both arms raised (≥ 30°) once the right arm passes 30° at 1.25 s; over once the left arm
    // falls below 30 − 3 = 27° at 2.48 s.
    CHECK(noteOn == Approx(1.25).margin(0.011));
    CHECK(noteOff == Approx(2.48).margin(0.011));

    // With one arm the same file sends only the right arm's CC.
    r = runArmadillo("render --scene theremin --motion '" + path("two-right.csv") + "' --map '" + map + "' --midi-out '" + path("one-arm.mid") + "'");
    REQUIRE(r.code == 0);
    const Smf one = readSmf(readBytes(path("one-arm.mid")));
    REQUIRE_FALSE(one.events.empty());
    for (const auto& e : one.events) CHECK((e.bytes[0] == 0xB0 && e.bytes[1] == 1));
}

TEST_CASE("play with two simulated arms --map: the left arm's and the relative sources reach the mapping", "[cli][mapping][twoarms]")
{
    Loopback udp;
    const std::string map = file("play-two.json", R"({"version": 1, "mappings": [
        {"source": "elevation", "to": {"osc": "/right", "args": ["$elevation"]}},
        {"source": "left.elevation", "to": {"osc": "/left", "args": ["$left.elevation"]}},
        {"source": "arms.angle", "to": {"osc": "/angle", "args": ["$arms.angle"]}}]})");
    const std::string rightFile = file("play-two-right.csv", posesCsv({{0.0, 30.0, 0.0, 0.0}, {1.0, 30.0, 0.0, 0.0}}));
    const std::string leftFile = file("play-two-left.csv", posesCsv({{0.0, -40.0, 90.0, 0.0}, {1.0, -40.0, 90.0, 0.0}}));
    const Run r = runArmadillo("play --scene theremin-duo --simulate --motion '" + rightFile + "' --motion-left '" + leftFile +
                               "' --seconds 2.5 --no-audio --map '" + map + "' --osc-out 127.0.0.1:" + std::to_string(udp.port));
    INFO(r.err);
    REQUIRE(r.code == 0);
    std::map<std::string, double> last;
    std::map<std::string, int> count;
    for (const auto& p : udp.drain())
        osc::decodeOscPacket(p.data(), p.size(), [&](const osc::OscMessage& m) {
            last[std::string(m.address)] = static_cast<double>(m.args[0].f);
            ++count[std::string(m.address)];
        });
    REQUIRE(count["/right"] > 0);
    REQUIRE(count["/left"] > 0);
    REQUIRE(count["/angle"] > 0);
    // Each arm as its file holds it (the fusion's accuracy), the angle as the geometry says.
    const double d = 3.14159265358979323846 / 180.0;
    const double angle = std::acos(std::sin(30.0 * d) * std::sin(-40.0 * d)) / d;   // azimuths 0° and 90°
    std::printf("play two arms --map: last right %.2f (30), left %.2f (-40), angle %.2f (%.2f) deg\n", last["/right"], last["/left"], last["/angle"], angle);
    CHECK(std::fabs(last["/right"] - 30.0) < 3.0);
    CHECK(std::fabs(last["/left"] + 40.0) < 3.0);
    CHECK(std::fabs(last["/angle"] - angle) < 4.0);
}
