// The transports around the OSC input: SLIP framing (RFC 1055) for the NGIMU over USB/serial,
// ZIG SIM's unframed TCP stream cut back into its units, and the receiver reading both for real
// (a pseudo-terminal through SerialPort's termios path; a loopback TCP connection). Waits are
// event-driven with generous timeouts; nothing sleeps to pass time.
#include "Core/Errors.h"
#include "Osc/Osc.h"
#include "Osc/OscIo.h"
#include "Osc/OscStream.h"
#include "Osc/Slip.h"
#include <arpa/inet.h>
#include <catch2/catch.hpp>
#include <condition_variable>
#include <fcntl.h>
#include <mutex>
#include <netinet/in.h>
#include <pty.h>
#include <sys/socket.h>
#include <termios.h>
#include <unistd.h>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::osc;
using Bytes = std::vector<std::uint8_t>;

namespace {

std::vector<OscArg> floats(std::initializer_list<double> v)
{
    std::vector<OscArg> out;
    for (double x : v) out.push_back(OscArg::float32(static_cast<float>(x)));
    return out;
}

/// An NGIMU /sensors bundle (gyro deg/s, accel g, mag uT, baro hPa) at NTP time t.
Bytes ngimuSensors(double t)
{
    const std::uint64_t tag = (std::uint64_t(3900000000u) << 32) + static_cast<std::uint64_t>(t * 4294967296.0);
    return encodeOscBundle(tag, {encodeOscMessage("/sensors", floats({0, 0, 0, 0, 0, 1, 20, 0, -40, 1013}))});
}

std::vector<Bytes> collect(OscStreamSplitter& s, const Bytes& stream, std::size_t chunk)
{
    std::vector<Bytes> units;
    for (std::size_t i = 0; i < stream.size(); i += chunk)
        s.feed(stream.data() + i, std::min(chunk, stream.size() - i),
               [](void* c, const std::uint8_t* p, std::size_t n) { static_cast<std::vector<Bytes>*>(c)->emplace_back(p, p + n); }, &units);
    return units;
}

struct Waiter {
    std::mutex m;
    std::condition_variable cv;
    int imu = 0;
    void add()
    {
        std::lock_guard<std::mutex> l(m);
        ++imu;
        cv.notify_all();
    }
    bool waitFor(int n)
    {
        std::unique_lock<std::mutex> l(m);
        return cv.wait_for(l, std::chrono::seconds(10), [&] { return imu >= n; });
    }
};

} // namespace

TEST_CASE("slip: RFC 1055 framing round-trips any bytes and resynchronises after damage", "[device][osc][slip]")
{
    // RFC 1055: END = 0xC0, ESC = 0xDB; END in data → DB DC, ESC in data → DB DD.
    const Bytes data = {0x01, 0xC0, 0x02, 0xDB, 0x03};
    const Bytes enc = slipEncode(data.data(), data.size());
    CHECK(enc == Bytes({0xC0, 0x01, 0xDB, 0xDC, 0x02, 0xDB, 0xDD, 0x03, 0xC0}));
    SlipDecoder d(64);
    std::vector<Bytes> got;
    auto sink = [&](const std::uint8_t* p, std::size_t n) { got.emplace_back(p, p + n); };
    // Byte by byte, after line noise, then a damaged packet (a bad escape), then a good one.
    const Bytes noise = {0x55, 0xAA};
    d.feed(noise.data(), noise.size(), sink);
    for (const std::uint8_t b : enc) d.feed(&b, 1, sink);
    const Bytes bad = {0x10, 0xDB, 0x11, 0x12, 0xC0};
    d.feed(bad.data(), bad.size(), sink);
    d.feed(enc.data(), enc.size(), sink);
    REQUIRE(got.size() == 3);   // the noise before the first END is a (garbage) packet of its own
    CHECK(got[1] == data);
    CHECK(got[2] == data);
    CHECK(d.badPackets() == 1);
    // An over-long packet is dropped, not grown without bound.
    Bytes big(100, 0x42);
    const Bytes bigEnc = slipEncode(big.data(), big.size());
    d.feed(bigEnc.data(), bigEnc.size(), sink);
    CHECK(got.size() == 3);
    CHECK(d.badPackets() == 2);
}

TEST_CASE("osc stream: ZIG SIM's unframed TCP payloads are cut back into JSON objects and OSC bundles", "[device][osc][tcp]")
{
    // ZIGSIMPlus NetworkAdapter.sendTCP writes each tick's getData() as is: objects back to back.
    const std::string a = R"({"sensordata":{"gyro":{"x":0,"y":0,"z":0}},"timestamp":"x}{"})";
    const std::string b = R"({"sensordata":{"compass":{"compass":1,"faceup":0}}})";
    Bytes json(a.begin(), a.end());
    json.insert(json.end(), b.begin(), b.end());
    json.push_back('\n');   // whitespace between objects is allowed
    json.insert(json.end(), a.begin(), a.end());
    for (const std::size_t chunk : {std::size_t(1), std::size_t(7), json.size()}) {
        OscStreamSplitter s;
        const auto units = collect(s, json, chunk);
        INFO("chunk " << chunk);
        REQUIRE(units.size() == 3);
        CHECK(std::string(units[0].begin(), units[0].end()) == a);   // the brace inside the string did not end it
        CHECK(std::string(units[1].begin(), units[1].end()) == b);
        CHECK(s.pending() == 0);
    }
    // OSC bundles back to back, cut anywhere: whole bundles come out.
    Bytes osc;
    std::vector<Bytes> bundles;
    for (int k = 0; k < 5; ++k) {
        bundles.push_back(ngimuSensors(0.01 * k));
        osc.insert(osc.end(), bundles.back().begin(), bundles.back().end());
    }
    for (const std::size_t chunk : {std::size_t(3), std::size_t(64), osc.size()}) {
        OscStreamSplitter s;
        const auto units = collect(s, osc, chunk);
        INFO("chunk " << chunk);
        std::size_t messages = 0;
        for (const Bytes& u : units)
            REQUIRE(decodeOscPacket(u.data(), u.size(), [&](const OscMessage& m) { messages += m.address == "/sensors"; }));
        CHECK(messages == 5);
    }
    // Junk is handed on as a unit of its own (the merger counts and lists it), then JSON again.
    OscStreamSplitter s;
    Bytes mixed = {'x', 'y', 'z'};
    mixed.insert(mixed.end(), b.begin(), b.end());
    const auto units = collect(s, mixed, mixed.size());
    REQUIRE(units.size() == 2);
    CHECK(units[0] == Bytes({'x', 'y', 'z'}));
}

TEST_CASE("osc receiver: NGIMU SLIP-framed OSC over a pseudo-terminal, through SerialPort's termios path", "[device][osc][slip][pty]")
{
    int master = -1, slave = -1;
    REQUIRE(::openpty(&master, &slave, nullptr, nullptr, nullptr) == 0);
    termios raw {};
    ::tcgetattr(slave, &raw);
    ::cfmakeraw(&raw);
    ::tcsetattr(slave, TCSANOW, &raw);
    const std::string path = ::ttyname(slave);
    Waiter w;
    std::vector<ImuSample> got;
    std::mutex gm;
    OscReceiver rx(OscSerialSource {path, 115200}, [&](const ImuSample& s) {
        {
            std::lock_guard<std::mutex> l(gm);
            got.push_back(s);
        }
        w.add();
    }, {});
    rx.start();
    for (int k = 0; k < 60; ++k) {
        const Bytes b = ngimuSensors(0.01 * k);
        const Bytes f = slipEncode(b.data(), b.size());
        REQUIRE(::write(master, f.data(), f.size()) == static_cast<ssize_t>(f.size()));
    }
    REQUIRE(w.waitFor(20));   // the first 0.3 s of the stream only show which sensors it sends
    rx.stop();
    CHECK(rx.format() == OscFormat::Ngimu);
    CHECK(rx.deviceName() == path);
    CHECK(rx.stats().bad == 0);
    std::lock_guard<std::mutex> l(gm);
    CHECK(got[1].t - got[0].t == Approx(0.01).margin(1e-4));   // the bundles' own time tags
    ::close(master);
    ::close(slave);
    // A port that is not there is refused with its name (exit 4 in the CLI).
    try {
        OscReceiver none(OscSerialSource {"/dev/armadillo-no-such-port", 115200}, {}, {});
        FAIL("opened a missing port");
    } catch (const IoError& e) {
        CHECK(std::string(e.what()).find("armadillo-no-such-port") != std::string::npos);
    }
}

TEST_CASE("osc receiver: ZIG SIM JSON over TCP on the same port number as UDP", "[device][osc][tcp]")
{
    Waiter w;
    OscReceiver rx(0, [&](const ImuSample&) { w.add(); }, {});
    REQUIRE(rx.tcpError().empty());
    rx.start();
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a {};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(static_cast<std::uint16_t>(rx.port()));
    REQUIRE(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
    std::string stream;
    for (int k = 0; k < 60; ++k) {
        char buf[256];
        std::snprintf(buf, sizeof buf, R"({"device":{"uuid":"T1"},"timestamp":"2024-03-01T00:00:%02d.%03dZ","sensordata":{"gravity":{"x":0,"y":0,"z":-1},"gyro":{"x":0,"y":0,"z":0.1}}})",
                      k / 60, (k % 60) * 1000 / 60);
        stream += buf;
    }
    REQUIRE(::send(fd, stream.data(), stream.size(), 0) == static_cast<ssize_t>(stream.size()));
    REQUIRE(w.waitFor(30));
    ::close(fd);
    rx.stop();
    CHECK(rx.format() == OscFormat::ZigSim);
    CHECK(rx.stats().json == 60);
    CHECK(rx.tcpConnections() == 1);
    CHECK(rx.deviceName() == "T1");
}
