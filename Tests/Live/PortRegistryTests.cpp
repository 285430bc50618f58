// One owner per serial port (PortRegistry): a second claim, from this process or another, is
// refused with a message saying who owns it, and the port is free again once the owner lets go.
#include "Live/Sources/PortRegistry.h"
#include <catch2/catch.hpp>
#include <cstdlib>
#include <string>
#include <unistd.h>

using armadillo::live::PortRegistry;

TEST_CASE("PortRegistry: one owner per port, in this process and across processes")
{
    const std::string port = "/dev/ttyARMADILLO-TEST-" + std::to_string(getpid());
    std::string why;
    auto first = PortRegistry::claim(port, why);
    REQUIRE(first != nullptr);
    CHECK(why.empty());

    auto second = PortRegistry::claim(port, why);
    CHECK(second == nullptr);
    CHECK(why.find("owned by another ARMadillo instance") != std::string::npos);
    CHECK(why.find("in this program") != std::string::npos);

    // Another process sees the claim too (a kernel lock, not a table in this process): util-linux
    // flock(1) on the same lock file fails while we hold it and succeeds once we let go.
    const std::string probe = "flock -n '" + PortRegistry::lockFileFor(port) + "' true";
    CHECK(std::system(probe.c_str()) != 0);

    first.reset();
    CHECK(std::system(probe.c_str()) == 0);
    auto again = PortRegistry::claim(port, why);
    CHECK(again != nullptr);
    again.reset();
    unlink(PortRegistry::lockFileFor(port).c_str());

    CHECK(PortRegistry::claim("", why) == nullptr);
    CHECK_FALSE(why.empty());
}
