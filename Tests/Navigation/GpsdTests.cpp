// gpsd for real (issue 34 "Done when"): the test writes an NMEA log of a walk along a route,
// starts its own gpsd through gpsfake (Debian's gpsd-clients) on a free loopback port, and checks
// GpsdSource and `armadillo navigate --gpsd … --simulate --log --tactile` against the positions it
// wrote: distances and bearings within 2 m and 2°, the waypoint switched inside the arrival
// radius, and the motor packets spelling each waypoint's name by the rows method. A gpsd that is
// not there is exit 4; a receiver without a fix is felt as "fix lost".
#include "Common/OscCounter.h"
#include "Common/Eventually.h"
#include "Common/FreePort.h"
#include "Common/ScratchDir.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include "Navigation/GpsdSource.h"
#include "Navigation/Route.h"
#include "Osc/Osc.h"
#include "RowsDecoder.h"
#include <arpa/inet.h>
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <csignal>
#include <fcntl.h>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <netinet/in.h>
#include <spawn.h>
#include <sstream>
#include <sys/socket.h>
#include <sys/wait.h>
#include <thread>
#include <atomic>
#include <unistd.h>

extern char** environ;

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::navigation;

namespace {

test::ScratchDir& scratch()
{
    static test::ScratchDir dir("armadillo-nav");
    return dir;
}
std::string path(const std::string& name) { return (scratch().path() / name).string(); }

bool listening(int port)
{
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a {};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const bool ok = ::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
    ::close(fd);
    return ok;
}

bool haveGpsfake() { return std::system("command -v gpsfake >/dev/null 2>&1 && command -v gpsd >/dev/null 2>&1") == 0; }

/// gpsfake (and the gpsd it starts) in a process group of its own, ended by that group's id.
class GpsFake {
public:
    GpsFake(const std::string& nmea, int port, double cycle)
    {
        const std::string portText = std::to_string(port), cycleText = std::to_string(cycle);
        const std::string log = path("gpsfake-" + portText + ".txt");
        posix_spawn_file_actions_t files;
        posix_spawn_file_actions_init(&files);
        posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        posix_spawn_file_actions_adddup2(&files, STDOUT_FILENO, STDERR_FILENO);
        posix_spawnattr_t attr;
        posix_spawnattr_init(&attr);
        posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
        posix_spawnattr_setpgroup(&attr, 0);
        std::vector<std::string> argv {"gpsfake", "-q", "-1", "-n", "-P", portText, "-c", cycleText, nmea};
        std::vector<char*> args;
        for (auto& a : argv) args.push_back(a.data());
        args.push_back(nullptr);
        if (posix_spawnp(&pid_, "gpsfake", &files, &attr, args.data(), environ) != 0) pid_ = -1;
        posix_spawn_file_actions_destroy(&files);
        posix_spawnattr_destroy(&attr);
    }
    ~GpsFake()
    {
        if (pid_ <= 0) return;
        ::kill(-pid_, SIGTERM);   // the group we made: gpsfake and its gpsd
        int status = 0;
        for (int i = 0; i < 300 && ::waitpid(pid_, &status, WNOHANG) == 0; ++i) ::usleep(10000);
        ::kill(-pid_, SIGKILL);
        ::waitpid(pid_, &status, 0);
    }
    bool started() const { return pid_ > 0; }

private:
    pid_t pid_ = -1;
};

std::string nmeaLine(const std::string& body)
{
    unsigned sum = 0;
    for (char c : body) sum ^= static_cast<unsigned char>(c);
    char cs[8];
    std::snprintf(cs, sizeof cs, "*%02X", sum);
    return "$" + body + cs + "\r\n";
}

/// ddmm.mmmmm / dddmm.mmmmm with the hemisphere; the value the receiver "measured" is read back
/// from the text, so the truth is what gpsd was told.
std::string nmeaAngle(double deg, bool lat, double& written)
{
    const double a = std::fabs(deg);
    const int d = static_cast<int>(a);
    const double m = (a - d) * 60.0;
    char buf[32];
    std::snprintf(buf, sizeof buf, lat ? "%02d%08.5f,%c" : "%03d%08.5f,%c", d, m, lat ? (deg >= 0 ? 'N' : 'S') : (deg >= 0 ? 'E' : 'W'));
    double mm = 0.0;
    std::sscanf(buf + (lat ? 2 : 3), "%lf", &mm);
    written = (d + mm / 60.0) * (deg >= 0 ? 1 : -1);
    return buf;
}

struct Truth {
    std::vector<LatLon> positions;
};

/// A walk from the route's start through every point at 1.4 m/s, one epoch a second (RMC + GGA).
/// `fixUntil` epochs have a fix; later ones (if any) report none.
std::string writeWalk(const Route& route, const std::string& file, Truth& truth, int noFixEpochs = 0)
{
    std::string out = "#Date: 2026-11-28\n";
    int epoch = 0;
    auto emit = [&](const LatLon& p, double track, bool fix) {
        const int hh = 10, mm = (epoch / 60) % 60, ss = epoch % 60;
        char time[16];
        std::snprintf(time, sizeof time, "%02d%02d%02d.00", hh, mm, ss);
        double wlat = 0, wlon = 0;
        const std::string la = nmeaAngle(p.lat, true, wlat), lo = nmeaAngle(p.lon, false, wlon);
        char rmc[160], gga[160];
        if (fix) {
            std::snprintf(rmc, sizeof rmc, "GPRMC,%s,A,%s,%s,%.2f,%.1f,281126,,,A", time, la.c_str(), lo.c_str(), 1.4 / 0.514444, track);
            std::snprintf(gga, sizeof gga, "GPGGA,%s,%s,%s,1,08,0.9,520.0,M,47.0,M,,", time, la.c_str(), lo.c_str());
        } else {   // no position at all (gpsd 3.22 still reports a fix for 'V' sentences that carry one)
            std::snprintf(rmc, sizeof rmc, "GPRMC,%s,V,,,,,,,281126,,,N", time);
            std::snprintf(gga, sizeof gga, "GPGGA,%s,,,,,0,00,99.9,,M,,M,,", time);
        }
        out += nmeaLine(rmc) + nmeaLine(gga);
        if (fix) truth.positions.push_back({wlat, wlon});
        ++epoch;
    };
    for (std::size_t k = 1; k < route.points.size(); ++k) {
        const LatLon a = route.points[k - 1].pos, b = route.points[k].pos;
        const double len = distanceM(a, b), brg = initialBearingDeg(a, b);
        for (double s = 0.0; s < len; s += 1.4) emit(destination(a, brg, s), brg, true);
    }
    for (int i = 0; i < 4; ++i) emit(route.points.back().pos, 0.0, true);
    for (int i = 0; i < noFixEpochs; ++i) emit(route.points.back().pos, 0.0, false);
    writeFileAtomically(file, out);
    return file;
}

Route testRoute()
{
    const std::string gpx = R"(<gpx version="1.1"><rte>
<rtept lat="48.1492000" lon="11.5678000"><name>Start</name></rtept>
<rtept lat="48.1496500" lon="11.5678000"><name>Entrance</name></rtept>
<rtept lat="48.1496500" lon="11.5684000"><name>Exit</name></rtept>
</rte></gpx>)";
    writeFileAtomically(path("route.gpx"), gpx);
    return parseGpx(gpx, path("route.gpx"));
}

std::vector<std::vector<std::string>> readCsv(const std::string& file)
{
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(readWholeFile(file));
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> cells;
        std::string cell;
        std::istringstream ls(line);
        while (std::getline(ls, cell, ',')) cells.push_back(cell);
        if (!line.empty() && line.back() == ',') cells.emplace_back();
        rows.push_back(cells);
    }
    return rows;
}

int run(const std::string& args, std::string& err)
{
    const std::string errFile = path("navigate-stderr.txt");
    const int status = std::system(("timeout -s KILL 120 '" + std::string(ARMADILLO_BIN) + "' " + args + " >'" + path("navigate-stdout.txt") + "' 2>'" + errFile + "'").c_str());
    err = readWholeFile(errFile);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

} // namespace

TEST_CASE("gpsd: a gpsd that is not there is an IoError naming host and port; bad endpoints are refused", "[gpsd]")
{
    const int port = test::freeTcpPort();
    REQUIRE(port > 0);
    PositionMailbox box;
    try {
        GpsdSource source(parseGpsdEndpoint("127.0.0.1:" + std::to_string(port)), box);
        FAIL("connected to nothing");
    } catch (const IoError& e) {
        CHECK_THAT(std::string(e.what()), Catch::Contains("127.0.0.1:" + std::to_string(port)) && Catch::Contains("cannot connect"));
    }
    CHECK(parseGpsdEndpoint("").port == "2947");
    CHECK(parseGpsdEndpoint("gps.local").host == "gps.local");
    CHECK(parseGpsdEndpoint(":3000").host == "localhost");
    CHECK(parseGpsdEndpoint("[::1]:2948").host == "::1");
    CHECK_THROWS_AS(parseGpsdEndpoint("host:http"), InputError);
    CHECK_THROWS_AS(parseGpsdEndpoint("host:70000"), InputError);
    std::string err;
    (void) testRoute();   // a readable route: the exit code is gpsd's
    CHECK(run("navigate --route '" + path("route.gpx") + "' --gpsd 127.0.0.1:" + std::to_string(port) + " --simulate --seconds 5", err) == 4);
    CHECK_THAT(err, Catch::Contains("cannot connect"));
}

TEST_CASE("gpsd for real: GpsdSource receives the fixes gpsfake replays, then 'no fix'", "[gpsd]")
{
    if (!haveGpsfake()) FAIL("gpsfake and gpsd are needed (Debian gpsd-clients, gpsd: scripts/install-deps.sh)");
    const Route route = testRoute();
    Truth truth;
    const std::string nmea = writeWalk(route, path("walk-source.nmea"), truth, 5);
    const int port = test::freeTcpPort();
    GpsFake fake(nmea, port, 0.05);
    REQUIRE(fake.started());
    REQUIRE(testing::eventually([&] { return listening(port); }, 90.0));   // gpsfake starts gpsd; seconds on a loaded machine
    PositionMailbox box;
    GpsdSource source(parseGpsdEndpoint("127.0.0.1:" + std::to_string(port)), box);
    source.start();
    std::vector<PositionFix> seen;
    std::uint64_t last = 0;
    testing::eventually([&] {
        const PositionFix f = box.latest();
        if (f.serial != last) {
            last = f.serial;
            seen.push_back(f);
        }
        return source.noFix() > 0 && source.fixes() > truth.positions.size() / 2;
    }, 60.0);
    source.stop();
    REQUIRE(source.fixes() > 10);
    CHECK(source.noFix() > 0);
    int matched = 0, fixes = 0;
    for (const PositionFix& f : seen) {
        if (f.quality == FixQuality::None) continue;
        ++fixes;
        double best = 1e9;
        for (const LatLon& p : truth.positions) best = std::min(best, distanceM(p, f.pos));
        matched += best < 0.05 ? 1 : 0;
        if (std::isfinite(f.speedMps)) CHECK(f.speedMps == Approx(1.4).margin(0.05));
    }
    CHECK(fixes > 10);
    CHECK(matched == fixes);
}

TEST_CASE("gpsd for real: `armadillo navigate --gpsd --simulate --log` follows the NMEA walk within 2 m and 2°, switches waypoints inside the radius, spells the names", "[gpsd]")
{
    if (!haveGpsfake()) FAIL("gpsfake and gpsd are needed (Debian gpsd-clients, gpsd: scripts/install-deps.sh)");
    const Route route = testRoute();
    Truth truth;
    const std::string nmea = writeWalk(route, path("walk.nmea"), truth);
    const int port = test::freeTcpPort();
    GpsFake fake(nmea, port, 0.1);   // 0.2 s per epoch: 5× a real walk
    REQUIRE(fake.started());
    REQUIRE(testing::eventually([&] { return listening(port); }, 90.0));   // gpsfake starts gpsd; seconds on a loaded machine
    std::string err;
    const int code = run("navigate --route '" + path("route.gpx") + "' --gpsd 127.0.0.1:" + std::to_string(port) + " --simulate --log '" + path("nav.csv") +
                             "' --tactile '" + path("t.csv") + "' --speech 'capture:" + path("speech.txt") + "' --seconds 90",
                         err);
    INFO(err);
    REQUIRE(code == 0);
    const auto log = readCsv(path("nav.csv"));
    REQUIRE(log.size() > 100);
    CHECK(log[0][0] == "t");
    CHECK(log[0][1] == "lat");
    CHECK(log[0][4] == "waypoint");
    CHECK(log[0][7] == "heading_deg");
    int checked = 0, switches = 0;
    std::string lastWaypoint;
    double worstD = 0.0, worstB = 0.0;
    for (std::size_t i = 1; i < log.size(); ++i) {
        const auto& r = log[i];
        if (r[3] != "ok") continue;
        const LatLon p {std::stod(r[1]), std::stod(r[2])};
        double best = 1e9;
        LatLon truthPos {};
        for (const LatLon& q : truth.positions)
            if (distanceM(q, p) < best) best = distanceM(q, p), truthPos = q;
        REQUIRE(best < 0.05);   // every logged position is one the receiver reported
        const int w = std::stoi(r[4]);
        if (w >= 2 && w <= 3 && !r[5].empty()) {
            const LatLon target = route.points[static_cast<std::size_t>(w - 1)].pos;
            worstD = std::max(worstD, std::fabs(std::stod(r[5]) - distanceM(truthPos, target)));
            if (distanceM(truthPos, target) > 3.0) worstB = std::max(worstB, std::fabs(wrap180(std::stod(r[6]) - initialBearingDeg(truthPos, target))));
            ++checked;
        }
        if (!lastWaypoint.empty() && r[4] != lastWaypoint) {
            ++switches;
            const int reached = std::stoi(lastWaypoint);
            CHECK(distanceM(truthPos, route.points[static_cast<std::size_t>(reached - 1)].pos) <= 8.0);   // inside the arrival radius
        }
        lastWaypoint = r[4];
    }
    std::printf("gpsd end to end: %d rows checked, worst distance error %.3f m, worst bearing error %.3f°, %d waypoint switches\n", checked, worstD, worstB, switches);
    CHECK(checked > 50);
    CHECK(worstD <= 2.0);
    CHECK(worstB <= 2.0);
    CHECK(switches == 2);
    // The motor packets spell the names by the rows method: Entrance → "en", Exit → "ex".
    std::vector<test::MotorFrame> frames;
    const auto tactile = readCsv(path("t.csv"));
    for (std::size_t i = 1; i < tactile.size(); ++i) {
        test::MotorFrame f;
        f.t = std::stod(tactile[i][0]);
        for (int m = 0; m < 9; ++m)
            if (std::stoi(tactile[i][static_cast<std::size_t>(m + 1)]) > 0) f.mask |= static_cast<std::uint16_t>(1u << m);
        frames.push_back(f);
    }
    const auto names = test::decodeNames(frames);
    REQUIRE(names.size() == 2);
    CHECK(names[0] == "en");
    CHECK(names[1] == "ex");
    // --speech: the same events spoken for those who want it (a capture backend writes a line per utterance).
    const std::string speech = readWholeFile(path("speech.txt"));
    CHECK_THAT(speech, Catch::Contains("arrived: Entrance") && Catch::Contains("arrived: Exit. End of the route."));
}

TEST_CASE("gpsd for real: a receiver without a fix is felt as 'fix lost', never a direction", "[gpsd]")
{
    if (!haveGpsfake()) FAIL("gpsfake and gpsd are needed (Debian gpsd-clients, gpsd: scripts/install-deps.sh)");
    const Route route = testRoute();
    Truth truth;
    // Only "no fix" epochs.
    std::string out = "#Date: 2026-11-28\n";
    for (int s = 0; s < 40; ++s) {
        char time[16];
        std::snprintf(time, sizeof time, "1000%02d.00", s);
        out += nmeaLine(std::string("GPRMC,") + time + ",V,,,,,,,281126,,,N");
        out += nmeaLine(std::string("GPGGA,") + time + ",,,,,0,00,99.9,,M,,M,,");
    }
    writeFileAtomically(path("nofix.nmea"), out);
    const int port = test::freeTcpPort();
    GpsFake fake(path("nofix.nmea"), port, 0.1);
    REQUIRE(fake.started());
    REQUIRE(testing::eventually([&] { return listening(port); }, 90.0));   // gpsfake starts gpsd; seconds on a loaded machine
    std::string err;
    REQUIRE(run("navigate --route '" + path("route.gpx") + "' --gpsd 127.0.0.1:" + std::to_string(port) + " --simulate --log '" + path("nofix.csv") +
                    "' --tactile '" + path("nofix-t.csv") + "' --seconds 6",
                err) == 0);
    CHECK_THAT(err, Catch::Contains("fix lost"));
    const auto log = readCsv(path("nofix.csv"));
    REQUIRE(log.size() > 20);
    int lost = 0;
    for (std::size_t i = 1; i < log.size(); ++i) {
        CHECK(log[i][3] != "ok");
        CHECK(log[i][13] != "compass");
        lost += log[i][13] == "fix-lost" ? 1 : 0;
    }
    CHECK(lost > 0);
    // No side cue at all: motors 4 and 6 (the compass's) never on alone.
    const auto tactile = readCsv(path("nofix-t.csv"));
    for (std::size_t i = 1; i < tactile.size(); ++i) {
        CHECK(tactile[i][4] == "0");
        CHECK(tactile[i][6] == "0");
    }
}

TEST_CASE("navigate: bad usage is exit 2, a bad route 3 with file and line, a missing one 4; --simulate-walk writes the log", "[cli]")
{
    (void) testRoute();
    const std::string route = "--route '" + path("route.gpx") + "' ";
    std::string err;
    CHECK(run("navigate " + route + "--simulate", err) == 2);                                   // no position source
    CHECK_THAT(err, Catch::Contains("choose one position source"));
    CHECK(run("navigate " + route + "--gpsd localhost --simulate-walk --simulate", err) == 2);  // two
    CHECK(run("navigate " + route + "--simulate-walk", err) == 2);                              // no arm
    CHECK(run("navigate " + route + "--simulate-walk --port /dev/null", err) == 2);             // the walker needs the simulated arm
    CHECK(run("navigate " + route + "--simulate-walk --simulate --arrival-radius 0", err) == 2);
    CHECK(run("navigate " + route + "--simulate-walk --simulate --names braille", err) == 2);
    CHECK(run("navigate " + route + "--simulate-walk --simulate --speak", err) == 2);
    CHECK(run("navigate " + route + "--simulate-walk --simulate --session-log '" + path("s.csv") + "'", err) == 2);   // offline: no packets
    CHECK(run("navigate " + route + "--simulate-walk --simulate --osc-out 127.0.0.1:9", err) == 2);
    CHECK(run("navigate " + route + "--gpsd localhost --simulate --osc-out nowhere", err) == 2);
    CHECK(run("navigate " + route + "--gpsd localhost:http --simulate", err) == 3);
    CHECK(run("navigate --simulate-walk --simulate", err) == 2);                           // no route
    writeFileAtomically(path("bad.gpx"), "<gpx version=\"1.1\">\n<rte>\n<rtept lat=\"48\" lon=\"east\"/>\n</rte></gpx>\n");
    CHECK(run("navigate --route '" + path("bad.gpx") + "' --simulate-walk --simulate", err) == 3);
    CHECK_THAT(err, Catch::Contains("bad.gpx:3") && Catch::Contains("not a number"));
    CHECK(run("navigate --route '" + path("nothing.gpx") + "' --simulate-walk --simulate", err) == 4);
    CHECK(run("navigate " + route + "--simulate-walk --simulate --log '" + path("walk.csv") + "'", err) == 0);
    const std::string out = readWholeFile(path("navigate-stdout.txt"));
    CHECK_THAT(out, Catch::StartsWith("{\"finished\":true") && Catch::Contains("\"arrivals\":2"));
    const auto log = readCsv(path("walk.csv"));
    REQUIRE(log.size() > 100);
    CHECK(log[0] == std::vector<std::string> {"t", "lat", "lon", "fix", "waypoint", "distance_m", "bearing_deg", "heading_deg", "arm_heading_deg",
                                              "offset_deg", "leg_distance_m", "off_route", "arrived", "sensation", "mag_disturbed"});
}

TEST_CASE("navigate --osc-in without --port/--simulate: a phone's ZIG SIM motion and gps on one port", "[cli][osc]")
{
    (void) testRoute();
    const int port = test::freeUdpPort();
    REQUIRE(port > 0);
    std::atomic<bool> stop {false};
    std::thread sender([&] {
        const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
        sockaddr_in to {};
        to.sin_family = AF_INET;
        to.sin_port = htons(static_cast<std::uint16_t>(port));
        to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        using osc::OscArg;
        const auto quat = osc::encodeOscMessage("/ZIGSIM/phone1/quaternion", {OscArg::float32(0.0f), OscArg::float32(0.0f), OscArg::float32(0.0f), OscArg::float32(1.0f)});
        const auto gps = osc::encodeOscMessage("/ZIGSIM/phone1/gps", {OscArg::float32(48.1494f), OscArg::float32(11.5678f)});
        for (int i = 0; !stop.load() && i < 3000; ++i) {
            ::sendto(fd, quat.data(), quat.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
            if (i % 20 == 0) ::sendto(fd, gps.data(), gps.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
            ::usleep(10000);
        }
        ::close(fd);
    });
    std::string err;
    const int code = run("navigate --route '" + path("route.gpx") + "' --osc-in " + std::to_string(port) + " --seconds 4 --log '" + path("phone.csv") + "'", err);
    stop = true;
    sender.join();
    INFO(err);
    REQUIRE(code == 0);
    CHECK_THAT(readWholeFile(path("navigate-stdout.txt")), Catch::Contains("\"osc_fixes\":") && !Catch::Contains("\"osc_fixes\":0,"));
    const auto log = readCsv(path("phone.csv"));
    int ok = 0;
    for (std::size_t i = 1; i < log.size(); ++i) {
        if (log[i][3] != "ok") continue;
        ++ok;
        CHECK(std::stod(log[i][1]) == Approx(48.1494).margin(1e-5));
        CHECK(std::stod(log[i][5]) == Approx(distanceM({48.1494, 11.5678}, {48.14965, 11.5678})).margin(0.5));
    }
    CHECK(ok > 10);
}

TEST_CASE("gpsd: one JSON report read as the source reads it (readGpsdJson)", "[gpsd]")
{
    PositionFix fix;
    REQUIRE(readGpsdJson(R"({"class":"TPV","device":"/dev/ttyUSB0","mode":3,"time":"2026-11-29T06:00:00.000Z",)"
                         R"("lat":52.52,"lon":13.405,"eph":4.5,"speed":1.2,"track":90.0})", fix) == GpsdReport::Fix);
    CHECK(fix.pos.lat == Approx(52.52));
    CHECK(fix.pos.lon == Approx(13.405));
    CHECK(fix.quality == FixQuality::Fix3D);
    CHECK(fix.accuracyM == Approx(4.5));
    CHECK(fix.courseDeg == Approx(90.0));
    CHECK(readGpsdJson(R"({"class":"TPV","mode":1})", fix) == GpsdReport::NoFix);
    CHECK(readGpsdJson(R"({"class":"TPV","mode":2,"lat":91.5,"lon":13.4})", fix) == GpsdReport::Rejected);
    CHECK(fix.quality == FixQuality::None);
    CHECK(readGpsdJson(R"({"class":"VERSION","release":"3.22"})", fix) == GpsdReport::None);
    CHECK(readGpsdJson("not json", fix) == GpsdReport::None);
    // libgps 3.22's own reader never returns on these lines (found by fuzzing); ours reads them.
    CHECK(readGpsdJson(R"({"class":"DEVICES","devices":[{"class":"DEVICE"})", fix) == GpsdReport::None);
    CHECK(readGpsdJson(R"({"class":"VERSION","devices":[{"class":"DEVICE"}]})", fix) == GpsdReport::None);
    REQUIRE(readGpsdJson(R"({"class":"TPV","mode":2,"lat":-33.9,"lon":151.2,"devices":[{"class":"DEVICE"}]})", fix) == GpsdReport::Fix);
    CHECK(fix.quality == FixQuality::Fix2D);
    CHECK(fix.pos.lon == Approx(151.2));
    CHECK(std::isnan(fix.accuracyM));
    CHECK(std::isnan(fix.speedMps));
}

TEST_CASE("navigate is play's instrument: a live walk writes play's session log and sends play's OSC stream", "[cli][osc]")
{
    (void) testRoute();
    const int port = test::freeUdpPort();
    REQUIRE(port > 0);
    testing::OscCounter received;   // the receiver of --osc-out: counts what arrives, by address
    REQUIRE(received.port() > 0);
    const int outPort = received.port();
    std::atomic<bool> stop {false};
    std::thread sender([&] {   // positions over OSC, the arm is the simulated forearm
        const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
        sockaddr_in to {};
        to.sin_family = AF_INET;
        to.sin_port = htons(static_cast<std::uint16_t>(port));
        to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        const auto fix = osc::encodeOscMessage("/armadillo/position", {osc::OscArg::float32(48.1494f), osc::OscArg::float32(11.5678f)});
        for (int i = 0; !stop.load() && i < 400; ++i) {
            ::sendto(fd, fix.data(), fix.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
            ::usleep(20000);
        }
        ::close(fd);
    });
    std::string err;
    const int code = run("navigate --route '" + path("route.gpx") + "' --osc-in " + std::to_string(port) + " --simulate --seconds 3 --session-log '" +
                             path("session.csv") + "' --osc-out 127.0.0.1:" + std::to_string(outPort),
                         err);
    stop = true;
    sender.join();
    INFO(err);
    REQUIRE(code == 0);
    const auto log = readCsv(path("session.csv"));
    REQUIRE(log.size() > 100);   // ~3 s of the simulated forearm's packets
    CHECK(log[0][0] == "t");
    CHECK(std::find(log[0].begin(), log[0].end(), "qw") != log[0].end());
    CHECK(std::find(log[0].begin(), log[0].end(), "reconnects") != log[0].end());
    CHECK(received.count("/armadillo/orientation") > 100);
    CHECK(received.count("/armadillo/motors") > 100);
}
