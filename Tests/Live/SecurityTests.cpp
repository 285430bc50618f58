// Issue 48: listeners closed by default and recordings that survive a crash (docs/SECURITY.md).
// The stage-control port binds loopback unless told otherwise (checked in /proc/net/udp, where
// the kernel says what the socket is bound to), an allow-list refuses, counts and names other
// senders (tests on the loopback range: 127.0.0.1 refused, 127.0.0.2 obeyed), and a session
// killed with SIGKILL leaves its WAV and CSVs readable under their own names.
#include "Common/Eventually.h"
#include "Core/AtomicFile.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Core/Wav.h"
#include "Live/Stage/StageControl.h"
#include "Live/Stage/StageSession.h"
#include "Osc/AllowList.h"
#include "Osc/Osc.h"
#include "Osc/OscInput.h"
#include <catch2/catch.hpp>
#include <arpa/inet.h>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <netinet/in.h>
#include <signal.h>
#include <sstream>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

using namespace armadillo;
using armadillo::testing::eventually;

namespace {

std::string out(const std::string& name) { return std::string(ARMADILLO_BINARY_DIR) + "/security-test-" + std::to_string(::getpid()) + "-" + name; }

std::string slurp(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/// The local addresses of the UDP sockets on `port`, as the kernel lists them in /proc/net/udp
/// and /proc/net/udp6 ("127.0.0.1", "0.0.0.0", "::").
std::vector<std::string> udpListeners(int port)
{
    std::vector<std::string> found;
    for (const bool v6 : {false, true}) {
        std::ifstream in(v6 ? "/proc/net/udp6" : "/proc/net/udp");
        std::string line;
        std::getline(in, line);   // the header
        while (std::getline(in, line)) {
            std::istringstream fields(line);
            std::string slot, local;
            fields >> slot >> local;   // "0100007F:1F90": the address as the kernel stores it, the port in hex
            const auto colon = local.find(':');
            if (colon == std::string::npos || std::stoi(local.substr(colon + 1), nullptr, 16) != port) continue;
            const std::string hex = local.substr(0, colon);
            unsigned char bytes[16] {};
            const std::size_t words = hex.size() / 8;   // 32-bit words, each in the machine's byte order
            for (std::size_t w = 0; w < words && w < 4; ++w) {
                const std::uint32_t word = static_cast<std::uint32_t>(std::stoul(hex.substr(w * 8, 8), nullptr, 16));
                std::memcpy(bytes + 4 * w, &word, 4);
            }
            char text[INET6_ADDRSTRLEN] {};
            ::inet_ntop(v6 ? AF_INET6 : AF_INET, bytes, text, sizeof text);
            found.push_back(text);
        }
    }
    return found;
}

/// A UDP port nobody uses right now (bound to 0, read, closed).
int freeUdpPort()
{
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a {};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t len = sizeof a;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
    ::close(fd);
    return ntohs(a.sin_port);
}

/// Sends `packet` to 127.0.0.1:port from a socket bound to `from` (an address of the loopback range).
bool sendFrom(const char* from, int port, const std::vector<std::uint8_t>& packet)
{
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    if (fd < 0) return false;
    sockaddr_in source {};
    source.sin_family = AF_INET;
    ::inet_pton(AF_INET, from, &source.sin_addr);
    sockaddr_in to {};
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<std::uint16_t>(port));
    ::inet_pton(AF_INET, "127.0.0.1", &to.sin_addr);
    const bool ok = ::bind(fd, reinterpret_cast<sockaddr*>(&source), sizeof source) == 0 &&
                    ::sendto(fd, packet.data(), packet.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to) == static_cast<ssize_t>(packet.size());
    ::close(fd);
    return ok;
}

/// The armadillo binary as a child, stdout and stderr into files.
struct Child {
    pid_t pid = -1;
    std::string stdoutPath, stderrPath;

    Child(const std::vector<std::string>& args, const std::string& name) : stdoutPath(out(name + ".stdout")), stderrPath(out(name + ".stderr"))
    {
        std::vector<char*> argv;
        const std::string bin = std::string(ARMADILLO_BINARY_DIR) + "/bin/armadillo";
        argv.push_back(const_cast<char*>(bin.c_str()));
        for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        pid = ::fork();
        REQUIRE(pid >= 0);
        if (pid == 0) {
            const int o = ::open(stdoutPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            const int e = ::open(stderrPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            const int n = ::open("/dev/null", O_RDONLY);
            ::dup2(o, 1);
            ::dup2(e, 2);
            ::dup2(n, 0);
            ::execv(bin.c_str(), argv.data());
            ::_exit(127);
        }
    }
    ~Child()
    {
        if (pid > 0) {
            ::kill(pid, SIGKILL);
            ::waitpid(pid, nullptr, 0);
        }
        std::remove(stdoutPath.c_str());
        std::remove(stderrPath.c_str());
    }
    /// Sends `signal` and waits; the exit code, or −signal when killed.
    int stop(int signal)
    {
        ::kill(pid, signal);
        int status = 0;
        ::waitpid(pid, &status, 0);
        pid = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
    }
    std::string err() const { return slurp(stderrPath); }
    std::string summary() const
    {
        std::string text = slurp(stdoutPath);
        while (!text.empty() && text.back() == '\n') text.pop_back();
        return text.substr(text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1);
    }
};

/// The last whole row's first column (t) of a CSV being written; −1 before the first row.
double lastRowTime(const std::string& path)
{
    const std::string text = slurp(path);
    const auto end = text.rfind('\n');
    if (end == std::string::npos) return -1.0;
    const auto start = text.rfind('\n', end - 1);
    if (start == std::string::npos) return -1.0;   // only the header so far
    const std::string row = text.substr(start + 1, end - start - 1);
    if (row.empty() || row[0] == 't') return -1.0;
    return std::atof(row.c_str());
}

} // namespace

TEST_CASE("allow-list: IPv4 and IPv6 networks, malformed lists refused with the item named", "[security]")
{
    const osc::AllowList list = osc::AllowList::parse("127.0.0.2, 10.1.0.0/16,fe80::/10");
    const auto v4 = [](const char* text) {
        sockaddr_in a {};
        a.sin_family = AF_INET;
        ::inet_pton(AF_INET, text, &a.sin_addr);
        return a;
    };
    const auto v6 = [](const char* text) {
        sockaddr_in6 a {};
        a.sin6_family = AF_INET6;
        ::inet_pton(AF_INET6, text, &a.sin6_addr);
        return a;
    };
    for (const char* yes : {"127.0.0.2", "10.1.0.0", "10.1.255.9"}) {
        const sockaddr_in a = v4(yes);
        CHECK(list.allows(reinterpret_cast<const sockaddr*>(&a)));
    }
    for (const char* no : {"127.0.0.1", "10.2.0.1", "0.0.0.0"}) {
        const sockaddr_in a = v4(no);
        CHECK_FALSE(list.allows(reinterpret_cast<const sockaddr*>(&a)));
    }
    const sockaddr_in6 linkLocal = v6("fe80::1"), global = v6("2001:db8::1"), mapped = v6("::ffff:127.0.0.2"), mappedNo = v6("::ffff:127.0.0.1");
    CHECK(list.allows(reinterpret_cast<const sockaddr*>(&linkLocal)));
    CHECK_FALSE(list.allows(reinterpret_cast<const sockaddr*>(&global)));
    CHECK(list.allows(reinterpret_cast<const sockaddr*>(&mapped)));   // an IPv4 sender on a dual-stack socket
    CHECK_FALSE(list.allows(reinterpret_cast<const sockaddr*>(&mappedNo)));
    CHECK(osc::addressName(reinterpret_cast<const sockaddr*>(&mapped)) == "127.0.0.2");
    CHECK(list.describe() == "127.0.0.2/32, 10.1.0.0/16, fe80::/10");
    const sockaddr_in anyone = v4("192.168.1.1");
    CHECK(osc::AllowList::parse("10.0.0.0/0").allows(reinterpret_cast<const sockaddr*>(&anyone)));

    for (const auto& [bad, says] : {std::pair<const char*, const char*> {"10.0.0.300", "'10.0.0.300' is not an IPv4 or IPv6 address"},
                                    {"10.0.0.1/33", "0..32"}, {"10.0.0.1/", "0..32"}, {"10.0.0.1/8x", "0..32"}, {"::1/129", "0..128"},
                                    {"127.0.0.1,,10.0.0.1", "empty entry"}, {"", "empty entry"}, {"tablet.local", "not an IPv4 or IPv6"}}) {
        INFO(bad);
        try {
            (void)osc::AllowList::parse(bad);
            FAIL("accepted");
        } catch (const std::invalid_argument& e) {
            CHECK(std::string(e.what()).find(says) != std::string::npos);
        }
    }
    CHECK(osc::isLoopbackAddress("127.0.0.1"));
    CHECK(osc::isLoopbackAddress("::1"));
    CHECK_FALSE(osc::isLoopbackAddress("0.0.0.0"));
    CHECK_FALSE(osc::isLoopbackAddress("::"));
}

TEST_CASE("stage control: loopback by default; an allow-list refuses, counts and names each sender once", "[security][stage]")
{
    std::atomic<int> panics {0};
    live::StageControlReceiver closed(0, [&](const core::StageCommand&) { ++panics; });
    CHECK(closed.boundAddress() == "127.0.0.1");
    const auto listeners = udpListeners(closed.port());
    CHECK(listeners == std::vector<std::string> {"127.0.0.1"});   // the kernel's word, not ours

    live::StageControlListen open;
    open.bind = "0.0.0.0";
    open.allow = osc::AllowList::parse("127.0.0.2");
    live::StageControlReceiver r(0, [&](const core::StageCommand&) { ++panics; }, open);
    CHECK(udpListeners(r.port()) == std::vector<std::string> {"0.0.0.0"});
    r.start();
    const auto panic = osc::encodeOscMessage("/armadillo/panic", {});
    REQUIRE(sendFrom("127.0.0.1", r.port(), panic));
    REQUIRE(sendFrom("127.0.0.1", r.port(), panic));
    REQUIRE(sendFrom("127.0.0.2", r.port(), panic));
    REQUIRE(eventually([&] { return panics.load() == 1 && r.notAllowed() == 2; }, 10.0));
    CHECK(r.commands() == 1);
    CHECK(r.takeRefusals() == std::vector<std::string> {"refused stage control from 127.0.0.1 (not in --control-allow)"});
    REQUIRE(sendFrom("127.0.0.1", r.port(), panic));
    REQUIRE(eventually([&] { return r.notAllowed() == 3; }, 10.0));
    CHECK(r.takeRefusals().empty());   // named once
    CHECK(r.summaryJson() == ",\"control_commands\":1,\"control_refused\":0,\"control_not_allowed\":3");
    r.stop();
}

TEST_CASE("armadillo play --control-in: loopback only; --control-bind 0.0.0.0 --control-allow 127.0.0.2 refuses 127.0.0.1 and obeys 127.0.0.2",
          "[security][stage][cli]")
{
    {
        const int port = freeUdpPort();
        Child play({"play", "--scene", "theremin", "--simulate", "--no-audio", "--seconds", "60", "--control-in", std::to_string(port)}, "closed");
        REQUIRE(eventually([&] { return !udpListeners(port).empty(); }));
        CHECK(udpListeners(port) == std::vector<std::string> {"127.0.0.1"});
        CHECK(play.stop(SIGINT) == 0);
    }
    const int port = freeUdpPort();
    const std::string tactile = out("allow-tactile.csv");
    Child play({"play", "--scene", "theremin", "--simulate", "--no-audio", "--seconds", "60", "--tactile", tactile, "--control-in",
                std::to_string(port), "--control-bind", "0.0.0.0", "--control-allow", "127.0.0.2"},
               "allow");
    REQUIRE(eventually([&] { return !udpListeners(port).empty() && lastRowTime(tactile) > 0.5; }));
    CHECK(udpListeners(port) == std::vector<std::string> {"0.0.0.0"});
    const auto panic = osc::encodeOscMessage("/armadillo/panic", {});
    REQUIRE(sendFrom("127.0.0.1", port, panic));
    REQUIRE(eventually([&] { return play.err().find("refused stage control from 127.0.0.1 (not in --control-allow)") != std::string::npos; }));
    CHECK(play.err().find("PANIC") == std::string::npos);   // refused: no panic
    REQUIRE(sendFrom("127.0.0.2", port, panic));
    REQUIRE(eventually([&] { return play.err().find("PANIC (command)") != std::string::npos; }));
    const double panickedBy = lastRowTime(tactile);
    REQUIRE(eventually([&] { return lastRowTime(tactile) > panickedBy + 0.5; }));   // half a second of rows after the panic
    CHECK(play.stop(SIGINT) == 0);
    const std::string summary = play.summary();
    INFO(summary);
    CHECK(summary.find("\"control_commands\":1,\"control_refused\":0,\"control_not_allowed\":1") != std::string::npos);
    CHECK(summary.find("\"panics\":1") != std::string::npos);
    // The motors are off from the panic on: the last rows of the tactile CSV are all zero.
    const core::CsvTable t = core::CsvTable::read(tactile);
    REQUIRE(t.rowCount() > 10);
    for (std::size_t row = t.rowCount() - 10; row < t.rowCount(); ++row)
        for (int m = 1; m < static_cast<int>(t.header().size()); ++m) CHECK(t.value(row, m) == 0.0);
    std::remove(tactile.c_str());

    // A malformed list or address is a usage error (exit 2) naming the option and the item.
    for (const auto& [args, says] : {std::pair<std::vector<std::string>, std::string> {{"--control-allow", "127.0.0.300"}, "--control-allow: '127.0.0.300'"},
                                     {{"--control-allow", "10.0.0.0/40"}, "--control-allow: '10.0.0.0/40'"},
                                     {{"--control-bind", "stage-pc"}, "--control-bind: 'stage-pc'"}}) {
        std::vector<std::string> a {"play", "--scene", "theremin", "--simulate", "--no-audio", "--seconds", "1", "--control-in", std::to_string(freeUdpPort())};
        a.insert(a.end(), args.begin(), args.end());
        Child bad(a, "bad");
        int status = 0;
        ::waitpid(bad.pid, &status, 0);
        bad.pid = -1;
        CHECK(WIFEXITED(status));
        CHECK(WEXITSTATUS(status) == 2);
        CHECK(bad.err().find(says) != std::string::npos);
    }
}

TEST_CASE("armadillo play killed with SIGKILL at 6 s leaves a readable WAV and whole CSV rows; a file already there is kept aside",
          "[security][recording][cli]")
{
    const std::string wav = out("A.wav"), log = out("L.csv"), tactile = out("T.csv");
    for (const auto& f : {wav, log, tactile, log + ".1"}) std::remove(f.c_str());
    { std::ofstream(log) << "an older log\n"; }
    Child play({"play", "--simulate", "--scene", "theremin", "--seconds", "30", "--out", wav, "--log", log, "--tactile", tactile}, "crash");
    // Killed once every file holds more than 5 s (the WAV's data by its size, the CSVs by their last row).
    const double rate = 48000.0;
    REQUIRE(eventually([&] {
        std::ifstream w(wav, std::ios::binary | std::ios::ate);
        const double audioSeconds = w ? (static_cast<double>(w.tellg()) - 80.0) / (rate * 2 * 2) : 0.0;
        return audioSeconds > 5.2 && lastRowTime(log) > 5.2 && lastRowTime(tactile) > 5.2;
    }, 60.0));
    CHECK(play.stop(SIGKILL) == -SIGKILL);
    CHECK(play.err().find("kept as '" + log + ".1'") != std::string::npos);
    CHECK(slurp(log + ".1") == "an older log\n");   // never half-replaced

    const core::AudioBuffer audio = core::readWav(wav);   // the header's sizes were written as it grew
    CHECK(audio.sampleRate == rate);
    REQUIRE(audio.channels.size() == 2);
    CHECK(audio.frames() >= static_cast<std::size_t>(4.0 * rate));
    double energy = 0.0;
    for (std::size_t i = 0; i < static_cast<std::size_t>(4.0 * rate) && i < audio.frames(); ++i) energy += static_cast<double>(audio.channels[0][i]) * static_cast<double>(audio.channels[0][i]);
    CHECK(std::sqrt(energy / (4.0 * rate)) > 1e-3);   // sound, not silence

    for (const auto& csv : {log, tactile}) {
        INFO(csv);
        const std::string text = slurp(csv);
        REQUIRE(!text.empty());
        CHECK(text.back() == '\n');   // whole rows only
        const core::CsvTable table = core::CsvTable::read(csv);   // every row has every column
        REQUIRE(table.rowCount() > 100);
        CHECK(table.value(table.rowCount() - 1, table.requireColumn("t")) >= 4.0);
    }
    for (const auto& f : {wav, log, tactile, log + ".1"}) std::remove(f.c_str());
}

TEST_CASE("OSC input: the first sender keeps the arm; who else tried is named", "[security][osc]")
{
    osc::OscSampleMerger m;
    std::size_t samples = 0;
    m.setSinks([](void* n, const core::ImuSample&) { ++*static_cast<std::size_t*>(n); }, [](void*, double, const Eigen::Quaterniond&) {}, &samples);
    const auto imu = [](double az) {
        std::vector<osc::OscArg> a;
        for (const double v : {0.0, 0.0, 0.0, 0.0, az, 0.0, 0.3, -0.5, -0.8}) a.push_back(osc::OscArg::float32(static_cast<float>(v)));
        return osc::encodeOscMessage("/armadillo/imu", a);
    };
    double t = 0.0;
    for (int i = 0; i < 100; ++i) {
        const auto p = imu(9.8);
        m.handleDatagram(p.data(), p.size(), t += 0.01, 7, "10.0.0.7:9000");
    }
    CHECK(m.otherDeviceName().empty());
    const std::size_t before = samples;
    const auto intruder = imu(-9.8);
    m.handleDatagram(intruder.data(), intruder.size(), t += 0.01, 99, "10.0.0.99:9000");
    CHECK(samples == before);   // the arm stays with the first sender
    CHECK(m.stats().otherDevice == 1);
    CHECK(m.otherDeviceName() == "10.0.0.99:9000");
    CHECK(m.deviceName() == "10.0.0.7:9000");
}

TEST_CASE("armadillo play that never gets data leaves no recording and puts the file it kept aside back", "[security][recording][cli]")
{
    const std::string log = out("nodata.csv");
    std::remove((log + ".1").c_str());
    { std::ofstream(log) << "an older log\n"; }
    Child play({"play", "--scene", "theremin", "--osc-in", std::to_string(freeUdpPort()), "--no-audio", "--data-timeout", "1", "--log", log}, "nodata");
    int status = 0;
    REQUIRE(eventually([&] { return ::waitpid(play.pid, &status, WNOHANG) == play.pid; }, 30.0));
    play.pid = -1;
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 4);
    CHECK(play.err().find("kept as '" + log + ".1'") != std::string::npos);   // said when it was kept aside…
    CHECK(slurp(log) == "an older log\n");                                      // …and put back: nothing was recorded
    CHECK_FALSE(std::ifstream(log + ".1").good());
    std::remove(log.c_str());
}

TEST_CASE("the app's stage commands: stageOscBind and stageOscAllow as StageSession takes them", "[security][stage]")
{
    live::Stage stage;
    live::StageSession session(stage);
    live::StageControlListen listen;
    REQUIRE(live::StageSession::listenFromSettings("", "", listen).empty());
    REQUIRE(session.setOsc(true, 0, listen).empty());
    int port = session.oscPort();
    REQUIRE(port > 0);
    CHECK(udpListeners(port) == std::vector<std::string> {"127.0.0.1"});   // this machine only by default

    REQUIRE(live::StageSession::listenFromSettings("0.0.0.0", "127.0.0.2", listen).empty());
    REQUIRE(session.setOsc(true, 0, listen).empty());   // a new address: opened again
    port = session.oscPort();
    CHECK(udpListeners(port) == std::vector<std::string> {"0.0.0.0"});
    const auto panic = osc::encodeOscMessage("/armadillo/panic", {});
    REQUIRE(sendFrom("127.0.0.1", port, panic));
    std::vector<std::string> refused;
    REQUIRE(eventually([&] {
        const auto r = session.tick().refused;
        refused.insert(refused.end(), r.begin(), r.end());
        return !refused.empty();
    }, 10.0));
    CHECK(refused == std::vector<std::string> {"refused stage control from 127.0.0.1 (not in the allow-list)"});
    CHECK_FALSE(stage.panicked());
    REQUIRE(sendFrom("127.0.0.2", port, panic));
    CHECK(eventually([&] { return stage.panicked(); }, 10.0));

    CHECK(live::StageSession::listenFromSettings("stage-pc", "", listen).find("not an IPv4 or IPv6 address") != std::string::npos);
    CHECK(live::StageSession::listenFromSettings("", "10.0.0.0/99", listen).find("allow-list: '10.0.0.0/99'") != std::string::npos);
    CHECK(session.setOsc(false, 0).empty());
    CHECK(session.oscPort() == 0);
}
