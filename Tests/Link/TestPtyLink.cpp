// The real link and transport code (SerialPort on the termios path, DeviceLink's thread, the
// HostLink state machine) against the simulated forearm over a pseudo-terminal pair, with and
// without faults. Waits are event-driven with generous timeouts; nothing sleeps to pass time.
#include "Core/Errors.h"
#include "Link/DeviceLink.h"
#include "Link/Simulator.h"
#include <catch2/catch.hpp>
#include <atomic>
#include <fstream>
#include <mutex>
#include <sys/ioctl.h>
#include <unistd.h>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::link;
using Clock = std::chrono::steady_clock;

namespace {

std::string tempPortPath()
{
    static std::atomic<int> n {0};
    return std::string(ARMADILLO_BINARY_DIR) + "/armadillo-sim-" + std::to_string(::getpid()) + "-" + std::to_string(n++);
}

/// Records every good packet's sequence stamp (ax) and arrival, and answers with levels derived
/// from it so the test can check the motor packets that reached the device.
struct Recorder {
    std::mutex mutex;
    std::vector<int> seqs;
    std::vector<Clock::time_point> times;
    DeviceLink::Handler handler()
    {
        return [this](const SensorCounts& c, double) {
            std::lock_guard<std::mutex> lock(mutex);
            seqs.push_back(c[kAx]);
            times.push_back(Clock::now());
            MotorLevels m {};
            m[0] = static_cast<std::uint8_t>(c[kAx] % 16);
            m[8] = 15;
            return m;
        };
    }
    std::vector<int> snapshot()
    {
        std::lock_guard<std::mutex> lock(mutex);
        return seqs;
    }
};

/// Device packets lost around each gap in the host's sequence (the 12-bit stamp wraps).
std::vector<int> gaps(const std::vector<int>& seqs)
{
    std::vector<int> out;
    for (std::size_t i = 1; i < seqs.size(); ++i) {
        const int step = (seqs[i] - seqs[i - 1] + 4096) % 4096;
        if (step != 1) out.push_back(step - 1);
    }
    return out;
}

SimulatorOptions stamped()
{
    SimulatorOptions o;
    o.stampSequence = true;
    return o;
}

} // namespace

TEST_CASE("pty: clean lock-step link, termios chosen automatically, levels reach the device", "[device][pty]")
{
    const std::string path = tempPortPath();
    SimulatedForearm sim(std::make_shared<WanderingMotion>(), stamped());
    sim.startPty(path);
    // Debian's libserialport 0.1.1 refuses pseudo-terminals: the automatic choice must not.
    SerialPort strict(path, 57600, SerialPort::Backend::LibSerialPort);
    CHECK_THROWS_AS(strict.open(), IoError);

    Recorder rec;
    DeviceLink link(std::make_unique<SerialPort>(path, 57600), rec.handler());
    link.start();
    REQUIRE(link.waitFor([](const LinkStats& s) { return s.packets >= 500; }, 20.0));
    CHECK(link.backend() == "termios");
    CHECK(link.connected());
    link.stop();
    const LinkStats s = link.stats();
    CHECK(s.badPackets == 0);
    CHECK(s.resyncs == 0);
    CHECK(s.reconnects == 0);
    CHECK(gaps(rec.snapshot()).empty());
    // stop() ends with an all-off packet after the handler's last one (the handler always asks
    // 15 of motor 9, so only that packet can leave the device with every motor off).
    CHECK(sim.waitFor([&](const SimulatorStats& st) { return st.levels == ProtocolLevels {}; }, 10.0));
    const SimulatorStats d = sim.stats();
    // The start-up 0x8 stream can leave one stray byte in front of the first motor packet (the
    // device then waits for its 0x8 end and answers that): at most one bad motor packet.
    CHECK(d.badMotorPackets <= 1);
    CHECK(d.motorPackets >= s.packets);   // one per answer, and the all-off (minus at most the stray one)
    const LatencySummary lat = link.latency();
    CHECK(lat.count == s.packets);
}

TEST_CASE("pty: after corruption the link is back in sync within two packets", "[device][pty]")
{
    enum Fault { EndNibble, Drop, Insert };
    for (const Fault fault : {EndNibble, Drop, Insert}) {
        CAPTURE(static_cast<int>(fault));
        const std::string path = tempPortPath();
        SimulatedForearm sim(std::make_shared<WanderingMotion>(), stamped());
        sim.startPty(path);
        Recorder rec;
        DeviceLink link(std::make_unique<SerialPort>(path, 57600), rec.handler());
        link.start();
        for (int round = 0; round < 5; ++round) {
            const std::uint64_t before = link.stats().packets;
            REQUIRE(link.waitFor([&](const LinkStats& s) { return s.packets >= before + 40; }, 20.0));
            if (fault == EndNibble) sim.corruptNextEndNibble();
            if (fault == Drop) sim.dropNextByte();
            if (fault == Insert) sim.insertNextByte(0x37);   // shifts the frame; its end nibble check fails
        }
        const std::uint64_t before = link.stats().packets;
        REQUIRE(link.waitFor([&](const LinkStats& s) { return s.packets >= before + 40; }, 20.0));
        link.stop();
        const auto g = gaps(rec.snapshot());
        CHECK(g.size() == 5);
        for (const int lost : g) CHECK(lost <= 2);
        const LinkStats s = link.stats();
        CHECK(s.resyncs == 5);
        if (fault == EndNibble) CHECK(s.badPackets == 5);
        if (fault == Drop) CHECK(s.silences == 5);
    }
}

TEST_CASE("pty: a stalled device is resynced by the 10 ms rule", "[device][pty]")
{
    const std::string path = tempPortPath();
    SimulatedForearm sim(std::make_shared<WanderingMotion>(), stamped());
    sim.startPty(path);
    Recorder rec;
    DeviceLink link(std::make_unique<SerialPort>(path, 57600), rec.handler());
    link.start();
    REQUIRE(link.waitFor([](const LinkStats& s) { return s.packets >= 50; }, 20.0));
    sim.stallFor(0.15);
    REQUIRE(link.waitFor([](const LinkStats& s) { return s.silences >= 1; }, 20.0));
    const std::uint64_t after = link.stats().packets;
    REQUIRE(link.waitFor([&](const LinkStats& s) { return s.packets >= after + 50 && s.inSync; }, 20.0));
    link.stop();
    for (const int lost : gaps(rec.snapshot())) CHECK(lost <= 2);
    // The resync stream the host sent while the device stalled did not confuse it for long.
    CHECK(link.stats().resyncs >= 1);
}

TEST_CASE("pty: unplug and replug — the host reconnects within one second of the port returning", "[device][pty]")
{
    const std::string path = tempPortPath();
    SimulatedForearm sim(std::make_shared<WanderingMotion>(), stamped());
    sim.startPty(path);
    Recorder rec;
    DeviceLink link(std::make_unique<SerialPort>(path, 57600), rec.handler());
    link.start();
    for (int round = 1; round <= 3; ++round) {
        REQUIRE(link.waitFor([](const LinkStats& s) { return s.packets >= 20 && s.inSync; }, 20.0));
        const std::uint64_t before = link.stats().packets;
        sim.disconnectFor(0.4);
        REQUIRE(sim.waitFor([&](const SimulatorStats& s) { return s.connections == static_cast<std::uint64_t>(round + 1); }, 20.0));
        const Clock::time_point plugged = sim.stats().lastPlug;
        REQUIRE(link.waitFor([&](const LinkStats& s) { return s.reconnects == static_cast<std::uint64_t>(round) && s.packets > before + 10; }, 20.0));
        // The first packet after the port returned.
        Clock::time_point first {};
        {
            std::lock_guard<std::mutex> lock(rec.mutex);
            for (const auto& t : rec.times)
                if (t > plugged) {
                    first = t;
                    break;
                }
        }
        REQUIRE(first > plugged);
        const double seconds = std::chrono::duration<double>(first - plugged).count();
        CAPTURE(seconds);
        CHECK(seconds < 1.0);
    }
    link.stop();
    CHECK(link.stats().reconnects == 3);
}

TEST_CASE("pty: random faults of every kind — no crash, no hang, bounded memory, link keeps going", "[device][pty][soak]")
{
    auto rssKb = [] {
        std::ifstream f("/proc/self/statm");
        long pages = 0, resident = 0;
        f >> pages >> resident;
        return resident * (::sysconf(_SC_PAGESIZE) / 1024);
    };
    const std::string path = tempPortPath();
    SimulatorOptions o = stamped();
    o.faults.corruptPacket = 0.02;
    o.faults.dropByte = 0.02;
    o.faults.insertByte = 0.01;
    o.faults.corruptHostByte = 0.002;
    o.faults.stall = 0.003;
    o.faults.stallSeconds = 0.03;
    o.faults.disconnect = 0.0005;
    o.faults.disconnectSeconds = 0.2;
    SimulatedForearm sim(std::make_shared<WanderingMotion>(), o);
    sim.startPty(path);
    Recorder rec;
    DeviceLink link(std::make_unique<SerialPort>(path, 57600), rec.handler());
    link.start();
    REQUIRE(link.waitFor([](const LinkStats& s) { return s.packets >= 1000; }, 30.0));
    const long rss0 = rssKb();
    REQUIRE(link.waitFor([](const LinkStats& s) { return s.packets >= 6000; }, 60.0));
    const long rss1 = rssKb();
    const auto t0 = Clock::now();
    link.stop();
    sim.stop();
    CHECK(std::chrono::duration<double>(Clock::now() - t0).count() < 2.0);
    const LinkStats s = link.stats();
    CHECK(s.badPackets > 0);
    CHECK(s.resyncs > 0);
    CHECK(sim.stats().faults > 100);
    // Memory: the recorder grows by design (~40 bytes a packet); the link itself must not.
    CHECK(rss1 - rss0 < 8 * 1024);
}

TEST_CASE("in-process simulator: same link, unplug and replug", "[device][simulator]")
{
    SimulatedForearm sim(std::make_shared<WanderingMotion>(), stamped());
    Recorder rec;
    DeviceLink link(sim.startInProcess(), rec.handler());
    link.start();
    REQUIRE(link.waitFor([](const LinkStats& s) { return s.packets >= 300; }, 20.0));
    CHECK(link.backend() == "simulator");
    sim.disconnectFor(0.2);
    REQUIRE(link.waitFor([](const LinkStats& s) { return s.reconnects >= 1 && s.inSync; }, 20.0));
    const std::uint64_t after = link.stats().packets;
    REQUIRE(link.waitFor([&](const LinkStats& s) { return s.packets >= after + 100; }, 20.0));
    link.stop();
    sim.stop();
    CHECK(link.stats().badPackets == 0);
}

TEST_CASE("negotiateV2 against a v1-only board falls back: the wire after the query is exactly v1's", "[device][simulator][v2]")
{
    // The same stamped simulator, once with v2 off and once with it on.
    struct Run { LinkStats stats; SimulatorStats sim; std::vector<int> seqs; std::vector<SentMotorPacket> sent; };
    auto run = [](bool v2) {
        SimulatedForearm sim(std::make_shared<WanderingMotion>(), stamped());
        Recorder rec;
        DeviceLinkOptions options;
        options.link.negotiateV2 = v2;
        DeviceLink link(sim.startInProcess(), rec.handler(), options);
        link.enableSentLog();
        link.start();
        const bool ok = link.waitFor([](const LinkStats& s) { return s.packets >= 300; }, 20.0);
        link.stop();
        sim.stop();
        REQUIRE(ok);
        Run r {link.stats(), sim.stats(), rec.snapshot(), {}};
        SentMotorPacket p;
        while (link.sentLog().pop(p)) r.sent.push_back(p);
        return r;
    };
    const Run v1 = run(false), v2 = run(true);
    for (const Run* r : {&v1, &v2}) {
        CHECK_FALSE(r->stats.v2);
        CHECK(r->stats.badPackets == 0);
        CHECK(r->stats.resyncs == 0);
        CHECK(r->stats.seqGaps == 0);
        CHECK(r->stats.crcFailures == 0);
        CHECK(gaps(r->seqs).empty());
        CHECK(r->sim.badMotorPackets == 0);
        CHECK(r->sim.resyncAnswers == 1);   // the one burst (v2: the one behind the query) was answered
        // One all-off resync burst, then only the handler's motor packets: seq % 16 on motor 1, 15 on motor 9.
        REQUIRE(r->sent.size() >= 300);
        CHECK(r->sent.front().resync);
        // stop() ends with an all-off packet, after the handler's last one.
        CHECK(r->sent.back().levels == ProtocolLevels {});
        const std::size_t handlerPackets = r->sent.size() - 2;
        std::size_t matching = 0;
        for (std::size_t i = 1; i <= handlerPackets && i - 1 < r->seqs.size(); ++i)
            if (!r->sent[i].resync && r->sent[i].levels[0] == r->seqs[i - 1] % 16 && r->sent[i].levels[8] == 15) ++matching;
        CHECK(matching == std::min(handlerPackets, r->seqs.size()));
    }
    std::printf("[v2 fallback] v1: %llu packets, %llu bytes out; v2 on: %llu packets, %llu bytes out\n",
                static_cast<unsigned long long>(v1.stats.packets), static_cast<unsigned long long>(v1.stats.bytesOut),
                static_cast<unsigned long long>(v2.stats.packets), static_cast<unsigned long long>(v2.stats.bytesOut));
}

TEST_CASE("negotiateV2 with a board that never answers gives up on v2 and keeps resyncing in v1", "[device][v2]")
{
    struct Peer : LinkPeer {
        std::vector<std::vector<std::uint8_t>> writes;
        MotorLevels onSensorPacket(const SensorCounts&, double) override { return {}; }
        void send(const std::uint8_t* b, std::size_t n) override { writes.emplace_back(b, b + n); }
    } peer;
    LinkConfig cfg;
    cfg.negotiateV2 = true;
    HostLink link(cfg);
    link.reset(0.0);
    link.poll(0.0, peer);
    REQUIRE(peer.writes.size() == 1);
    CHECK(peer.writes[0] == std::vector<std::uint8_t> {0x41, 0x52, 0x4D, 0x76, 0x32, 0x00, 0x00, 0x00, 0x00, 0x08});
    CHECK(link.state() == HostLink::State::Negotiating);
    link.poll(cfg.v2AnswerTimeout - 0.001, peer);
    CHECK(peer.writes.size() == 1);
    link.poll(cfg.v2AnswerTimeout, peer);
    REQUIRE(peer.writes.size() == 2);
    CHECK(peer.writes[1] == std::vector<std::uint8_t>(kResyncPacket.begin(), kResyncPacket.end()));
    CHECK(link.state() == HostLink::State::Resyncing);
    CHECK_FALSE(link.stats().v2);
}

TEST_CASE("serial port: missing ports and non-ttys are refused clearly; the link keeps retrying", "[device][pty]")
{
    SerialPort missing("/nonexistent/ttyARM0");
    try {
        missing.open();
        FAIL("opened a missing port");
    } catch (const IoError& e) {
        CHECK(std::string(e.what()).find("/nonexistent/ttyARM0") != std::string::npos);
    }
    const std::string file = std::string(ARMADILLO_BINARY_DIR) + "/device-test-not-a-tty";
    std::ofstream(file) << "x";
    SerialPort notTty(file);
    try {
        notTty.open();
        FAIL("opened a regular file as a serial port");
    } catch (const IoError& e) {
        CHECK(std::string(e.what()).find("not a tty") != std::string::npos);
    }
    std::remove(file.c_str());
    CHECK_THROWS_AS(SerialPort("/dev/null", 0), IoError);

    DeviceLink link(std::make_unique<SerialPort>("/nonexistent/ttyARM0"), {});
    link.start();
    const auto deadline = Clock::now() + std::chrono::seconds(10);
    while (link.lastError().empty() && Clock::now() < deadline) std::this_thread::yield();
    CHECK(link.lastError().find("no serial port") != std::string::npos);
    CHECK_FALSE(link.connected());
    const auto t0 = Clock::now();
    link.stop();
    CHECK(std::chrono::duration<double>(Clock::now() - t0).count() < 1.0);
    CHECK(link.stats().packets == 0);
}

TEST_CASE("serial port: an open port is taken on the device itself (flock + TIOCEXCL) until closed", "[device][pty]")
{
    const std::string path = tempPortPath();
    SimulatedForearm sim(std::make_shared<WanderingMotion>(), stamped());
    sim.startPty(path);
    SerialPort first(path, 57600);
    first.open();
    REQUIRE(first.isOpen());
    int exclusive = 0;
    REQUIRE(::ioctl(first.fd(), TIOCGEXCL, &exclusive) == 0);
    CHECK(exclusive == 1);   // other programs' open() gets EBUSY (root excepted)
    // Another opener (another program, or a second ARMadillo) sees the lock, with a clear reason.
    SerialPort second(path, 57600);
    try {
        second.open();
        FAIL("opened a port another process holds");
    } catch (const IoError& e) {
        CHECK(std::string(e.what()).find("in use by another program") != std::string::npos);
    }
    CHECK_FALSE(second.isOpen());
    first.close();
    second.open();   // free again once closed
    CHECK(second.isOpen());
    REQUIRE(::ioctl(second.fd(), TIOCGEXCL, &exclusive) == 0);
    CHECK(exclusive == 1);
}
