// OSC 1.0 codec against hand-computed bytes, and the UDP input/output over loopback.
#include "Core/Errors.h"
#include "Core/Pose.h"
#include "Osc/Osc.h"
#include "Osc/OscIo.h"
#include <catch2/catch.hpp>
#include <condition_variable>
#include <mutex>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::osc;

TEST_CASE("osc: encoding matches the 1.0 spec byte for byte", "[device][osc]")
{
    // "/oscillator/4/frequency" ,f 440.0 — the spec's own example.
    const auto bytes = encodeOscMessage("/oscillator/4/frequency", {OscArg::float32(440.0f)});
    const std::vector<std::uint8_t> expected {'/', 'o', 's', 'c', 'i', 'l', 'l', 'a', 't', 'o', 'r', '/', '4', '/', 'f', 'r',
                                              'e', 'q', 'u', 'e', 'n', 'c', 'y', 0, ',', 'f', 0, 0, 0x43, 0xdc, 0x00, 0x00};
    CHECK(bytes == expected);
    // "/foo" ,iisff 1000 -1 "hello" 1.234 5.678 — the spec's second example.
    const auto foo = encodeOscMessage("/foo", {OscArg::int32(1000), OscArg::int32(-1), OscArg::string("hello"), OscArg::float32(1.234f), OscArg::float32(5.678f)});
    const std::vector<std::uint8_t> fooExpected {'/', 'f', 'o', 'o', 0, 0, 0, 0, ',', 'i', 'i', 's', 'f', 'f', 0, 0,
                                                 0x00, 0x00, 0x03, 0xe8, 0xff, 0xff, 0xff, 0xff, 'h', 'e', 'l', 'l', 'o', 0, 0, 0,
                                                 0x3f, 0x9d, 0xf3, 0xb6, 0x40, 0xb5, 0xb2, 0x2d};
    CHECK(foo == fooExpected);
    // Refusals: no leading '/', embedded NUL, unknown type, too small a buffer.
    std::uint8_t small[8];
    const OscArg f = OscArg::float32(1.0f);
    CHECK(encodeOscMessage("nope", &f, 1, small, sizeof small) == 0);
    CHECK(encodeOscMessage("/a", &f, 1, small, sizeof small) == 0);
    OscArg weird;
    weird.type = 'Q';
    std::uint8_t big[64];
    CHECK(encodeOscMessage("/a", &weird, 1, big, sizeof big) == 0);
}

TEST_CASE("osc: every argument type and nested bundles round-trip", "[device][osc]")
{
    OscArg h;
    h.type = 'h';
    h.h = -1234567890123LL;
    OscArg t;
    t.type = 'T';
    const auto msg = encodeOscMessage("/all", {OscArg::int32(-7), OscArg::float32(2.5f), OscArg::float64(-1e300), OscArg::string("abc"),
                                               OscArg::blob(std::string_view("\x01\x00\x02", 3)), h, t});
    const auto bundle = encodeOscBundle(1, {msg, encodeOscBundle(5, {encodeOscMessage("/inner", {OscArg::string("")})})});
    std::vector<std::string> addresses;
    std::string error;
    REQUIRE(decodeOscPacket(bundle.data(), bundle.size(), [&](const OscMessage& m) {
        addresses.emplace_back(m.address);
        if (m.address == "/all") {
            REQUIRE(m.count == 7);
            CHECK(m.types == "ifdsbhT");
            CHECK(m.args[0].i == -7);
            CHECK(m.args[1].f == 2.5f);
            CHECK(m.args[2].d == -1e300);
            CHECK(m.args[3].bytes == "abc");
            CHECK(m.args[4].bytes == std::string_view("\x01\x00\x02", 3));
            CHECK(m.args[5].h == -1234567890123LL);
            double v = 0;
            CHECK(m.args[6].asNumber(v));
            CHECK(v == 1.0);
            CHECK_FALSE(m.args[3].asNumber(v));
        } else {
            CHECK(m.count == 1);
            CHECK(m.args[0].bytes.empty());
        }
    }, &error));
    CHECK(addresses == std::vector<std::string> {"/all", "/inner"});

    // Malformed: unpadded, bad tags, truncated argument, bundle element overrunning, too deep.
    auto refused = [](const std::vector<std::uint8_t>& b) {
        std::string e;
        return !decodeOscPacket(b.data(), b.size(), [](const OscMessage&) {}, &e) && !e.empty();
    };
    std::vector<std::uint8_t> truncated = msg;
    truncated.resize(msg.size() - 4);
    CHECK(refused(truncated));
    CHECK(refused({'/', 'a', 0}));
    CHECK(refused({'/', 'a', 0, 0, 'f', 'f', 0, 0}));
    CHECK(refused({'#', 'b', 'u', 'n', 'd', 'l', 'e', 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 64}));
    std::vector<std::uint8_t> deep = encodeOscMessage("/d", {});
    for (int i = 0; i < kOscMaxBundleDepth + 1; ++i) deep = encodeOscBundle(1, {deep});
    CHECK(refused(deep));
}

TEST_CASE("osc: host:port parsing", "[device][osc]")
{
    CHECK(parseHostPort("192.168.1.5:9000").host == "192.168.1.5");
    CHECK(parseHostPort("192.168.1.5:9000").port == 9000);
    CHECK(parseHostPort("9001").host == "127.0.0.1");
    CHECK(parseHostPort("[::1]:7000").host == "::1");
    CHECK_THROWS_AS(parseHostPort("host:"), std::invalid_argument);
    CHECK_THROWS_AS(parseHostPort("host:70000"), std::invalid_argument);
    CHECK_THROWS_AS(parseHostPort("::1:7000"), std::invalid_argument);
    CHECK_THROWS_AS(OscSender(HostPort {"no-such-host.invalid", 9000}), IoError);
}

TEST_CASE("osc: UDP input drives IMU and orientation handlers; sender speaks the address space", "[device][osc]")
{
    std::mutex m;
    std::condition_variable cv;
    std::vector<ImuSample> imu;
    std::vector<Eigen::Quaterniond> qs;
    OscReceiver rx(0, [&](const ImuSample& s) {
        std::lock_guard<std::mutex> l(m);
        imu.push_back(s);
        cv.notify_all();
    }, [&](double, const Eigen::Quaterniond& q) {
        std::lock_guard<std::mutex> l(m);
        qs.push_back(q);
        cv.notify_all();
    });
    rx.start();
    REQUIRE(rx.port() > 0);
    OscSender tx(HostPort {"127.0.0.1", rx.port()});
    std::vector<OscArg> nine;
    for (int i = 0; i < 9; ++i) nine.push_back(OscArg::float32(static_cast<float>(i) + 0.5f));
    REQUIRE(tx.send("/armadillo/imu", nine.data(), nine.size()));
    REQUIRE(tx.sendOrientation(Eigen::Quaterniond(1.05, 0.0, 0.0, 0.0)));   // rounding: normalised on arrival
    const OscArg wrong[] = {OscArg::float32(1.0f), OscArg::string("x")};
    REQUIRE(tx.send("/armadillo/imu", wrong, 2));
    REQUIRE(tx.sendGesture("roll"));
    const OscArg fin[] = {OscArg::float32(1.0f), OscArg::float32(0.0f), OscArg::float32(0.0f), OscArg::float32(0.0f)};
    REQUIRE(tx.send("/armadillo/orientation", fin, 4));
    {
        std::unique_lock<std::mutex> l(m);
        REQUIRE(cv.wait_for(l, std::chrono::seconds(10), [&] { return imu.size() == 1 && qs.size() == 2; }));
    }
    CHECK(imu[0].gyro == Eigen::Vector3d(0.5, 1.5, 2.5));
    CHECK(imu[0].accel == Eigen::Vector3d(3.5, 4.5, 5.5));
    CHECK(imu[0].mag == Eigen::Vector3d(6.5, 7.5, 8.5));
    CHECK(qs[0].w() == Approx(1.0));
    rx.stop();
    const OscInputStats s = rx.stats();
    CHECK(s.imu == 1);
    CHECK(s.orientation == 2);
    CHECK(s.bad == 1);
    CHECK(s.ignored == 1);
    CHECK(rx.lastError().find("/armadillo/imu needs") != std::string::npos);

    // A taken port is refused with the port number.
    try {
        OscReceiver again(rx.port(), {}, {});
        FAIL("bound a taken port");
    } catch (const IoError& e) {
        CHECK(std::string(e.what()).find(std::to_string(rx.port())) != std::string::npos);
    }
    CHECK(tx.sent() == 5);
}

TEST_CASE("osc: the receiver takes IPv6 senders as well as IPv4 on the same port", "[device][osc]")
{
    // One receiver per sender: the merger follows one device at a time (docs/DEVICE.md §6).
    for (const char* host : {"127.0.0.1", "::1"}) {   // ::1 exists wherever the kernel has IPv6, as here and in CI
        INFO(host);
        std::mutex m;
        std::condition_variable cv;
        int orientations = 0;
        OscReceiver rx(0, {}, [&](double, const Eigen::Quaterniond&) {
            std::lock_guard<std::mutex> l(m);
            ++orientations;
            cv.notify_all();
        });
        rx.start();
        REQUIRE(rx.port() > 0);
        const OscArg q[] = {OscArg::float32(1.0f), OscArg::float32(0.0f), OscArg::float32(0.0f), OscArg::float32(0.0f)};
        OscSender tx(HostPort {host, rx.port()});
        REQUIRE(tx.send("/armadillo/orientation", q, 4));
        {
            std::unique_lock<std::mutex> l(m);
            REQUIRE(cv.wait_for(l, std::chrono::seconds(10), [&] { return orientations == 1; }));
        }
        rx.stop();
        CHECK(rx.stats().orientation == 1);
    }
}
