// `--web` and `--web-bind` on the command line (issue 47, docs/INTERFACES.md "The web page"):
// mistakes are bad usage (exit 2) before anything runs, a port that cannot be had is exit 4, and
// the address printed is where the page answers. The page itself: Tests/Web.
#include "Cli/CliRun.h"
#include "Common/FreePort.h"
#include <catch2/catch.hpp>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <regex>
#include <sys/socket.h>
#include <unistd.h>

using namespace armadillo;
using namespace armadillo::cli;

TEST_CASE("cli: --web mistakes are exit 2, a port that is taken exit 4", "[cli][web]")
{
    const std::string play = "play --simulate --scene theremin --seconds 1 --no-audio ";
    struct Case {
        std::string args, says;
        int code;
    };
    const Case cases[] = {
        {play + "--web-bind 127.0.0.1", "give --web PORT too", 2},
        {play + "--web 70000", "--web", 2},
        {play + "--web 0 --web-bind example.org", "is not an IPv4 or IPv6 address", 2},
        {play + "--web 0 --calibrate " + path("cal.json"), "--calibrate and --web", 2},
        {"navigate --route " + std::string(ARMADILLO_SOURCE_DIR) + "/Resources/Examples/route.gpx --simulate-walk --simulate --web 0",
         "--simulate-walk runs offline", 2},
        {play + "--web 0 --web-bind 198.51.100.254", "cannot listen on 198.51.100.254", 4},   // TEST-NET: not this machine's
    };
    for (const Case& c : cases) {
        INFO(c.args);
        const Run r = runArmadilloWithin(30, c.args);
        CHECK(r.code == c.code);
        CHECK(r.err.find(c.says) != std::string::npos);
    }

    // A port another socket holds.
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a {};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    REQUIRE(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
    REQUIRE(::listen(fd, 1) == 0);
    REQUIRE(::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) == 0);
    const Run taken = runArmadilloWithin(30, play + "--web " + std::to_string(ntohs(a.sin_port)));
    ::close(fd);
    CHECK(taken.code == 4);
    CHECK(taken.err.find("web page: cannot listen on 127.0.0.1 port") != std::string::npos);
}

TEST_CASE("cli: play --web prints the page's loopback address; read takes it too", "[cli][web]")
{
    const Run r = runArmadilloWithin(30, "play --simulate --scene theremin --seconds 1 --no-audio --web 0");
    CHECK(r.code == 0);
    std::smatch m;
    const std::string err = r.err;
    CHECK(std::regex_search(err, m, std::regex("armadillo play: web: http://127\\.0\\.0\\.1:[0-9]+/\n")));
    const Run help = runArmadillo("read --help");
    CHECK(help.out.find("--web PORT") != std::string::npos);
    CHECK(help.out.find("--web-bind ADDR") != std::string::npos);
}
