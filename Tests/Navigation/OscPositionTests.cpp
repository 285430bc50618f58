// Positions over OSC: /armadillo/position and ZIG SIM's gps (OSC and JSON), decoded from packets
// the test encodes itself; garbage refused as "no fix"; and a real UDP socket on a free port.
#include "Common/Eventually.h"
#include "Common/FreePort.h"
#include "Navigation/OscPositionSource.h"
#include "Osc/Osc.h"
#include <arpa/inet.h>
#include <catch2/catch.hpp>
#include <random>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

using namespace armadillo;
using namespace armadillo::navigation;

namespace {

std::vector<std::uint8_t> msg(const std::string& address, const std::vector<osc::OscArg>& args) { return osc::encodeOscMessage(address, args); }

bool decode(const std::vector<std::uint8_t>& packet, PositionFix& fix, bool& rejected)
{
    return decodePositionDatagram(packet.data(), packet.size(), fix, rejected);
}

} // namespace

TEST_CASE("OSC positions: /armadillo/position with and without accuracy, in any numeric type", "[osc]")
{
    PositionFix f;
    bool rejected = true;
    REQUIRE(decode(msg("/armadillo/position", {osc::OscArg::float64(48.1372), osc::OscArg::float64(11.5756), osc::OscArg::float32(4.5f)}), f, rejected));
    CHECK_FALSE(rejected);
    CHECK(f.quality == FixQuality::Fix2D);
    CHECK(f.pos.lat == Approx(48.1372));
    CHECK(f.pos.lon == Approx(11.5756));
    CHECK(f.accuracyM == Approx(4.5));
    REQUIRE(decode(msg("/armadillo/position", {osc::OscArg::float32(-33.86f), osc::OscArg::float32(151.21f)}), f, rejected));
    CHECK_FALSE(rejected);
    CHECK(std::isnan(f.accuracyM));
    CHECK(f.pos.lat == Approx(-33.86).margin(1e-5));
}

TEST_CASE("OSC positions: ZIG SIM's gps in OSC (with and without the /ZIGSIM prefix) and JSON", "[osc]")
{
    PositionFix f;
    bool rejected = true;
    REQUIRE(decode(msg("/ZIGSIM/abc123/gps", {osc::OscArg::float32(35.6586f), osc::OscArg::float32(139.7454f)}), f, rejected));
    CHECK_FALSE(rejected);
    CHECK(f.pos.lon == Approx(139.7454).margin(1e-4));
    REQUIRE(decode(msg("/abc123/gps", {osc::OscArg::float32(35.6586f), osc::OscArg::float32(139.7454f)}), f, rejected));
    CHECK_FALSE(rejected);
    const std::string json = R"({"device":{"uuid":"abc"},"timestamp":"x","sensordata":{"gps":{"latitude":51.5007,"longitude":-0.1246}}})";
    REQUIRE(decodePositionDatagram(reinterpret_cast<const std::uint8_t*>(json.data()), json.size(), f, rejected));
    CHECK_FALSE(rejected);
    CHECK(f.pos.lat == Approx(51.5007));
    CHECK(f.pos.lon == Approx(-0.1246));
    // Other ZIG SIM data and other addresses are not positions.
    const std::string motion = R"({"sensordata":{"gyro":{"x":0,"y":0,"z":0}}})";
    CHECK_FALSE(decodePositionDatagram(reinterpret_cast<const std::uint8_t*>(motion.data()), motion.size(), f, rejected));
    CHECK_FALSE(decode(msg("/ZIGSIM/abc/gyro", {osc::OscArg::float32(0), osc::OscArg::float32(0), osc::OscArg::float32(0)}), f, rejected));
    CHECK_FALSE(decode(msg("/a/b/gps", {osc::OscArg::float32(1), osc::OscArg::float32(2)}), f, rejected));
    CHECK_FALSE(decode(msg("/armadillo/imu", {osc::OscArg::float32(1)}), f, rejected));
}

TEST_CASE("OSC positions: garbage is refused and reported as no fix, never as a place", "[osc]")
{
    PositionFix f;
    bool rejected = false;
    const auto nan = std::nanf("");
    for (const auto& packet : {msg("/armadillo/position", {osc::OscArg::float32(nan), osc::OscArg::float32(11.0f)}),
                               msg("/armadillo/position", {osc::OscArg::float32(95.0f), osc::OscArg::float32(11.0f)}),
                               msg("/armadillo/position", {osc::OscArg::float32(45.0f), osc::OscArg::float32(200.0f)}),
                               msg("/armadillo/position", {osc::OscArg::float32(45.0f)}),
                               msg("/armadillo/position", {osc::OscArg::string("north"), osc::OscArg::float32(11.0f)}),
                               msg("/armadillo/position", {osc::OscArg::float32(45.0f), osc::OscArg::float32(11.0f), osc::OscArg::float32(-3.0f)}),
                               msg("/armadillo/position", {osc::OscArg::float32(45.0f), osc::OscArg::float32(11.0f), osc::OscArg::float32(3.0f), osc::OscArg::float32(1.0f)}),
                               msg("/Z/gps", {osc::OscArg::string("x"), osc::OscArg::float32(1.0f)})}) {
        REQUIRE(decode(packet, f, rejected));
        CHECK(rejected);
        CHECK(f.quality == FixQuality::None);
    }
    const std::string json = R"({"sensordata":{"gps":{"latitude":"x","longitude":3}}})";
    REQUIRE(decodePositionDatagram(reinterpret_cast<const std::uint8_t*>(json.data()), json.size(), f, rejected));
    CHECK(rejected);
    const std::uint8_t junk[] = {0x2F, 0x61, 0x00, 0xFF, 0x01};
    CHECK_FALSE(decodePositionDatagram(junk, sizeof junk, f, rejected));
}

TEST_CASE("OSC positions: a real UDP socket hands fixes to the mailbox from its own thread", "[osc]")
{
    const int port = test::freeUdpPort();
    REQUIRE(port > 0);
    PositionMailbox box;
    OscPositionSource source(port, box);
    source.start();
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in to {};
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<std::uint16_t>(port));
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const auto good = msg("/armadillo/position", {osc::OscArg::float64(48.5), osc::OscArg::float64(9.25), osc::OscArg::float32(3.0f)});
    const auto bad = msg("/armadillo/position", {osc::OscArg::float32(200.0f), osc::OscArg::float32(9.0f)});
    const auto other = msg("/armadillo/imu", {osc::OscArg::float32(1.0f)});
    REQUIRE(testing::eventually([&] {
        ::sendto(fd, good.data(), good.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
        return box.latest().serial > 0;
    }, 10.0));
    CHECK(box.latest().pos.lat == Approx(48.5));
    CHECK(box.latest().accuracyM == Approx(3.0));
    ::sendto(fd, other.data(), other.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
    ::sendto(fd, bad.data(), bad.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
    CHECK(testing::eventually([&] { return source.rejected() == 1 && source.ignored() == 1; }, 10.0));
    CHECK(box.latest().quality == FixQuality::None);
    CHECK(box.rejected() == 1);
    ::close(fd);
    source.stop();
}

TEST_CASE("OSC positions: fuzzed datagrams never crash and never yield a place out of range", "[osc][fuzz]")
{
    const auto seedOsc = msg("/armadillo/position", {osc::OscArg::float64(48.1), osc::OscArg::float64(11.5), osc::OscArg::float32(3.0f)});
    const std::string seedJson = R"({"sensordata":{"gps":{"latitude":48.1,"longitude":11.5}}})";
    std::mt19937_64 rng(341);
    int positions = 0, fixes = 0;
    for (int round = 0; round < 20000; ++round) {
        std::vector<std::uint8_t> d = round % 2 ? seedOsc : std::vector<std::uint8_t>(seedJson.begin(), seedJson.end());
        const int edits = 1 + static_cast<int>(rng() % 3);
        for (int e = 0; e < edits && !d.empty(); ++e) {
            const std::size_t at = rng() % d.size();
            switch (rng() % 3) {
            case 0: d[at] = static_cast<std::uint8_t>(rng()); break;
            case 1: d.erase(d.begin() + static_cast<long>(at)); break;
            case 2: d.resize(at); break;
            }
        }
        PositionFix f;
        bool rejected = false;
        if (!decodePositionDatagram(d.data(), d.size(), f, rejected)) continue;
        ++positions;
        if (rejected) {
            REQUIRE(f.quality == FixQuality::None);
        } else {
            ++fixes;
            REQUIRE(validLatLon(f.pos));
            REQUIRE(!(f.accuracyM < 0.0));
        }
    }
    CHECK(positions > 100);   // the probe: many mutations still reach the position decoder
    CHECK(fixes > 0);
}
