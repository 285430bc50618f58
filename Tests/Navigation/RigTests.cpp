// The app's walk, below JUCE (navigation::NavigationRig): a route that is not one, a port that is not
// one and a gpsd that is not there are refused with the reason and leave nothing running; a walk
// on a real UDP port takes positions into the link the navigation scene reads, and its status
// says so; stop closes the port again.
#include "Common/Eventually.h"
#include "Common/FreePort.h"
#include "Common/ScratchDir.h"
#include "Core/AtomicFile.h"
#include "Navigation/NavigationRig.h"
#include "Osc/Osc.h"
#include <arpa/inet.h>
#include <catch2/catch.hpp>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::navigation;

namespace {

std::string scratchPath(const std::string& name)
{
    static test::ScratchDir dir("armadillo-nav-rig");
    return (dir.path() / name).string();
}

void send(int port, const std::vector<std::uint8_t>& packet)
{
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    REQUIRE(fd >= 0);
    sockaddr_in to {};
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<std::uint16_t>(port));
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::sendto(fd, packet.data(), packet.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
    ::close(fd);
}

} // namespace

TEST_CASE("navigation rig: bad routes, ports and gpsd are refused with the reason, nothing left running", "[rig]")
{
    const std::string route = scratchPath("walk.json"), bad = scratchPath("bad.json");
    writeFileAtomically(route, R"({"name": "Test walk", "waypoints": [{"lat": 48.1492, "lon": 11.5678}, {"lat": 48.1497, "lon": 11.5678}]})");
    writeFileAtomically(bad, R"([{"lat": 95, "lon": 0}, {"lat": 1, "lon": 1}])");
    NavigationRig rig;
    std::string why = rig.start(bad, NavigationRig::Source::Osc, "9004");
    CHECK_THAT(why, Catch::StartsWith("Navigation: ") && Catch::Contains("bad.json"));
    CHECK_FALSE(rig.running());
    CHECK(rig.route() == nullptr);
    CHECK_THAT(rig.start(scratchPath("nothing.json"), NavigationRig::Source::Osc, "9004"), Catch::Contains("nothing.json"));
    for (const char* port : {"0", "65536", "abc", "9004x", ""}) {
        INFO(port);
        CHECK(rig.start(route, NavigationRig::Source::Osc, port) == "Navigation: the OSC port must be 1 to 65535");
        CHECK_FALSE(rig.running());
    }
    const int nobody = test::freeTcpPort();
    why = rig.start(route, NavigationRig::Source::Gpsd, "127.0.0.1:" + std::to_string(nobody));
    CHECK_THAT(why, Catch::Contains(std::to_string(nobody)));
    CHECK_FALSE(rig.running());
    CHECK(rig.sourceStatus() == "no position source");
    CHECK(rig.routeName().empty());
}

TEST_CASE("navigation rig: a walk on a real UDP port feeds the link; stop closes the port", "[rig]")
{
    const std::string route = scratchPath("named.json"), unnamed = scratchPath("unnamed.json");
    writeFileAtomically(route, R"({"name": "Test walk", "waypoints": [{"lat": 48.1492, "lon": 11.5678}, {"lat": 48.1497, "lon": 11.5678}]})");
    writeFileAtomically(unnamed, R"([{"lat": 48.1492, "lon": 11.5678}, {"lat": 48.1497, "lon": 11.5678}])");
    const int port = test::freeUdpPort();
    REQUIRE(port > 0);
    NavigationRig rig;
    REQUIRE(rig.start(route, NavigationRig::Source::Osc, " " + std::to_string(port) + " ").empty());
    REQUIRE(rig.running());
    REQUIRE(rig.route() != nullptr);
    REQUIRE(rig.link() != nullptr);
    CHECK(rig.routeName() == "Test walk");
    CHECK(rig.sourceStatus() == "OSC UDP " + std::to_string(port) + ", 0 fixes");
    const auto fix = osc::encodeOscMessage("/armadillo/position", {osc::OscArg::float64(48.1494), osc::OscArg::float64(11.5678),
                                                                      osc::OscArg::float32(4.0f)});
    REQUIRE(testing::eventually([&] {
        send(port, fix);
        return rig.link()->position.latest().serial > 0;
    }, 10.0));
    CHECK(rig.link()->position.latest().pos.lat == Approx(48.1494));
    CHECK_THAT(rig.sourceStatus(), Catch::StartsWith("OSC UDP " + std::to_string(port) + ", ") && !Catch::EndsWith(", 0 fixes"));

    // A second walk replaces the first (its port closed: the same port opens again); a route
    // without a name is called by its file's name.
    REQUIRE(rig.start(unnamed, NavigationRig::Source::Osc, std::to_string(port)).empty());
    CHECK(rig.routeName() == "unnamed.json");
    rig.stop();
    CHECK_FALSE(rig.running());
    CHECK(rig.link() == nullptr);
    NavigationRig again;
    CHECK(again.start(route, NavigationRig::Source::Osc, std::to_string(port)).empty());
}
