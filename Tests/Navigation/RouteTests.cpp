// Routes: GPX 1.1 (route, track, waypoints), JSON, the example route, and every kind of bad file
// giving an InputError that names the file and the line; mutated files never crash.
#include "Core/Errors.h"
#include "Core/Resources.h"
#include "Navigation/Route.h"
#include <catch2/catch.hpp>
#include <random>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::navigation;

namespace {

const char* kGpxRoute = R"(<?xml version="1.0" encoding="UTF-8"?>
<gpx version="1.1" creator="test" xmlns="http://www.topografix.com/GPX/1/1">
  <wpt lat="1" lon="1"><name>ignored</name></wpt>
  <rte>
    <name>Library walk</name>
    <rtept lat="48.13710" lon="11.57540"><name>Start</name></rtept>
    <rtept lat="48.13800" lon="11.57540"><name>Entrance</name></rtept>
    <rtept lat="+48.13800" lon="11.57700"/>
  </rte>
</gpx>
)";

/// The message of the InputError `f` throws ("" when it throws none).
template <typename F>
std::string errorOf(F&& f)
{
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST_CASE("GPX route: <rtept>s in order with names, the route's name, line numbers", "[route]")
{
    const Route r = parseGpx(kGpxRoute, "walk.gpx");
    REQUIRE(r.points.size() == 3);
    CHECK(r.name == "Library walk");
    CHECK(r.points[0].name == "Start");
    CHECK(r.points[1].name == "Entrance");
    CHECK(r.points[2].name.empty());
    CHECK(r.points[1].pos.lat == Approx(48.138));
    CHECK(r.points[2].pos.lon == Approx(11.577));
    CHECK(r.points[0].line == 6);
    CHECK(r.points[2].line == 8);
    CHECK(r.lengthM() == Approx(distanceM(r.points[0].pos, r.points[1].pos) + distanceM(r.points[1].pos, r.points[2].pos)));
}

TEST_CASE("GPX track: segments joined in order, thinned to points 15 m apart, named points and the end kept", "[route]")
{
    std::string gpx = R"(<gpx version="1.1"><trk><name>T</name><trkseg>)";
    // 40 points 2 m apart going north, one named in the middle, in two segments.
    for (int i = 0; i < 40; ++i) {
        if (i == 20) gpx += "</trkseg><trkseg>";
        const LatLon p = destination({48.0, 11.0}, 0.0, 2.0 * i);
        gpx += "<trkpt lat=\"" + std::to_string(p.lat) + "\" lon=\"" + std::to_string(p.lon) + "\">";
        if (i == 25) gpx += "<name>Exit</name>";
        gpx += "</trkpt>\n";
    }
    gpx += "</trkseg></trk></gpx>";
    const Route r = parseGpx(gpx, "t.gpx");
    CHECK(r.name == "T");
    // kept: 0 (0 m), 8 (16 m), 16 (32 m), 24 (48 m), 25 (named), 33 (66 m), 39 (the last, 78 m)
    REQUIRE(r.points.size() == 7);
    CHECK(r.points[4].name == "Exit");
    for (std::size_t i = 1; i < r.points.size(); ++i) CHECK(distanceM(r.points[i - 1].pos, r.points[i].pos) >= kMinLegM);
    CHECK(distanceM(r.points.back().pos, destination({48.0, 11.0}, 0.0, 78.0)) < 0.2);
}

TEST_CASE("GPX waypoints: <wpt>s in file order when there is no route or track", "[route]")
{
    const Route r = parseGpx(R"(<gpx version="1.0"><metadata><name>M</name></metadata>
<wpt lat="0" lon="0"><name>a</name></wpt><wpt lat="0.001" lon="0"><name>b</name></wpt></gpx>)", "w.gpx");
    REQUIRE(r.points.size() == 2);
    CHECK(r.points[1].name == "b");
    CHECK(r.name == "M");
}

TEST_CASE("GPX errors name the file and the line", "[route][errors]")
{
    CHECK_THAT(errorOf([] { parseGpx("<gpx version=\"1.1\">\n<rte>\n<rtept lat=\"1\" lon=\"2\">\n</rte></gpx>", "bad.gpx"); }),
               Catch::StartsWith("bad.gpx:4") && Catch::Contains("not well-formed XML"));
    CHECK_THAT(errorOf([] { parseGpx("<gpx>\n<rte>\n<rtept lon=\"2\"/><rtept lat=\"1\" lon=\"2\"/></rte></gpx>", "a.gpx"); }),
               Catch::StartsWith("a.gpx:3") && Catch::Contains("no lat attribute"));
    CHECK_THAT(errorOf([] { parseGpx("<gpx>\n\n<rte><rtept lat=\"north\" lon=\"2\"/><rtept lat=\"1\" lon=\"2\"/></rte></gpx>", "a.gpx"); }),
               Catch::StartsWith("a.gpx:3") && Catch::Contains("not a number"));
    CHECK_THAT(errorOf([] { parseGpx("<gpx><rte><rtept lat=\"91\" lon=\"2\"/><rtept lat=\"1\" lon=\"2\"/></rte></gpx>", "a.gpx"); }),
               Catch::Contains("outside"));
    CHECK_THAT(errorOf([] { parseGpx("<gpx><rte><rtept lat=\"1\" lon=\"200\"/><rtept lat=\"1\" lon=\"2\"/></rte></gpx>", "a.gpx"); }),
               Catch::Contains("longitude"));
    CHECK_THAT(errorOf([] { parseGpx("<kml/>", "k.gpx"); }), Catch::Contains("not a GPX file"));
    CHECK_THAT(errorOf([] { parseGpx("<gpx version=\"2.0\"/>", "v.gpx"); }), Catch::Contains("GPX version"));
    CHECK_THAT(errorOf([] { parseGpx("<gpx version=\"1.1\"></gpx>", "e.gpx"); }), Catch::Contains("no route"));
    CHECK_THAT(errorOf([] { parseGpx("<gpx><wpt lat=\"1\" lon=\"1\"/></gpx>", "one.gpx"); }), Catch::Contains("at least 2 points"));
    CHECK_THAT(errorOf([] { parseGpx("<gpx><wpt lat=\"1\" lon=\"1\"/>\n<wpt lat=\"1\" lon=\"1.000001\"/></gpx>", "d.gpx"); }),
               Catch::StartsWith("d.gpx:2") && Catch::Contains("at least 1 m"));
    CHECK_THAT(errorOf([] { parseGpx("<gpx><wpt lat=\"1\" lon=\"1\"><name>" + std::string(80, 'x') + "</name></wpt><wpt lat=\"2\" lon=\"1\"/></gpx>", "n.gpx"); }),
               Catch::Contains("at most 64 bytes"));
    CHECK_THAT(errorOf([] { parseGpx("", "empty.gpx"); }), Catch::StartsWith("empty.gpx"));
}

TEST_CASE("JSON routes: a list or an object with a name; errors with lines and members", "[route][errors]")
{
    const Route a = parseRouteJson(R"([{"lat": 48.1, "lon": 11.5, "name": "Start"}, {"lat": 48.101, "lon": 11.5}])", "r.json");
    REQUIRE(a.points.size() == 2);
    CHECK(a.points[0].name == "Start");
    const Route b = parseRouteJson("{\"name\": \"Park\",\n \"waypoints\": [\n{\"lat\": 0, \"lon\": 0},\n{\"lat\": 0, \"lon\": 0.001, \"name\": \"Exit\"}]}", "p.json");
    CHECK(b.name == "Park");
    CHECK(b.points[1].line == 4);
    CHECK_THAT(errorOf([] { parseRouteJson("[{\"lat\": 0, \"lon\": 0},\n{\"lat\": 0}]", "m.json"); }), Catch::StartsWith("m.json:2") && Catch::Contains("no \"lon\""));
    CHECK_THAT(errorOf([] { parseRouteJson("[{\"lat\": 0, \"lon\": 0, \"alt\": 3}, {\"lat\": 1, \"lon\": 0}]", "m.json"); }), Catch::Contains("unknown member \"alt\""));
    CHECK_THAT(errorOf([] { parseRouteJson("[{\"lat\": \"0\", \"lon\": 0}]", "m.json"); }), Catch::Contains("must be a number"));
    CHECK_THAT(errorOf([] { parseRouteJson("{\"waypoints\": 3}", "m.json"); }), Catch::Contains("list of waypoints"));
    CHECK_THAT(errorOf([] { parseRouteJson("{\"points\": []}", "m.json"); }), Catch::Contains("unknown member"));
    CHECK_THAT(errorOf([] { parseRouteJson("[1, 2]", "m.json"); }), Catch::Contains("a waypoint is an object"));
    CHECK_THAT(errorOf([] { parseRouteJson("[{\"lat\": 0, \"lon\": 0}", "m.json"); }), Catch::StartsWith("m.json:1"));
}

TEST_CASE("readRouteFile: by extension or content; a missing file is an IoError", "[route][errors]")
{
    CHECK_THROWS_AS(readRouteFile("/nonexistent/route.gpx"), IoError);
}

TEST_CASE("the shipped example route reads, starts at its first point and has named signs", "[route]")
{
    const ResourceFile file = readResource("Examples/route.gpx");
    const Route r = parseGpx(file.bytes, file.origin);
    CHECK(r.points.size() >= 9);   // the start and at least 8 waypoints
    int named = 0;
    for (const auto& p : r.points) named += p.name.empty() ? 0 : 1;
    CHECK(named >= 3);
}

TEST_CASE("fuzz: mutated GPX and JSON routes parse or throw InputError naming the file, never crash", "[route][fuzz]")
{
    const std::string seeds[] = {kGpxRoute, R"({"name": "x", "waypoints": [{"lat": 1, "lon": 2, "name": "a"}, {"lat": 1.001, "lon": 2}]})"};
    std::mt19937_64 rng(34);
    int parsed = 0, refused = 0;
    for (int round = 0; round < 3000; ++round) {
        std::string s = seeds[round % 2];
        const int edits = 1 + static_cast<int>(rng() % 4);
        for (int e = 0; e < edits && !s.empty(); ++e) {
            const std::size_t at = rng() % s.size();
            switch (rng() % 4) {
            case 0: s[at] = static_cast<char>(rng() % 256); break;                       // flip a byte
            case 1: s.erase(at, 1 + rng() % 8); break;                                   // drop bytes
            case 2: s.insert(at, 1, "<>\"{}[]:,&0-9.e"[rng() % 15]); break;              // insert syntax
            case 3: s.resize(at); break;                                                 // truncate
            }
        }
        try {
            const Route r = round % 2 == 0 ? parseGpx(s, "fuzz.gpx") : parseRouteJson(s, "fuzz.json");
            REQUIRE(r.points.size() >= 2);
            for (const auto& p : r.points) REQUIRE(validLatLon(p.pos));
            ++parsed;
        } catch (const InputError& e) {
            REQUIRE_THAT(std::string(e.what()), Catch::StartsWith("fuzz."));
            ++refused;
        }
    }
    CHECK(parsed > 0);    // the probe: mutations that keep a file valid still read
    CHECK(refused > 0);
}
