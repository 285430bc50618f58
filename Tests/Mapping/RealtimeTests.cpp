// Mapper::process is real-time (Mapping/Mapper.h): with 64 mappings of every source and
// destination kind — zones crossing, gestures, postures, MPE, OSC, macros, scene parameters, a
// set hand-over, note-offs falling due — it allocates, frees, locks and throws nothing. The guard
// first proves it sees an allocation, so its zero means something.
#define ARMADILLO_REALTIME_GUARD_IMPLEMENTATION
#include "Common/RealtimeGuard.h"
#include "Mapping/MappingHelpers.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::mapping;
using namespace armadillo::mapping::test;
using armadillo::test::RealtimeGuard;

namespace {

/// 64 mappings: eight of each family below, cycling channels, numbers and ranges.
std::string sixtyFour()
{
    const char* families[] {
        R"({"source": "elevation", "in": [-45, 45], "smoothMs": 15, "to": {"midi": "cc14", "channel": %C, "cc": %N}})",
        R"({"source": "roll", "curve": "exp", "shape": 2, "deadZone": 3, "to": {"midi": "pitchbend", "channel": %C}})",
        R"({"source": "azimuth", "forward": true, "to": {"midi": "notes", "channel": %C, "velocity": {"source": "speed", "in": [0, 200]},
            "zones": [[0, 90, 60], [90, 180, 62], [180, 270, 64], [270, 360, 65]]}})",
        R"({"source": "yaw", "to": {"osc": "/arm/{zone}/yaw", "args": ["$value", "-$pitch", "$ypr.qw", "$zone", "$on", 7, "tag"], "types": "ffffiis",
            "zones": [[-180, 0, 1], [0, 180, 2]]}})",
        R"({"source": "gesture:*", "to": {"midi": "note", "channel": %C, "note": %N, "velocity": {"source": "value", "in": [0, 1], "abs": true}}})",
        R"({"source": "posture:up", "to": {"macro": %M}})",
        R"({"source": "azimuth", "zones": [[0, 120, 60], [120, 240, 64], [240, 360, 67]],
            "to": {"midi": "mpe", "members": 4, "bend": {"source": "roll", "in": [-90, 90]}, "pressure": {"source": "elevation", "in": [0, 90]},
                   "timbre": {"source": "speed", "in": [0, 300]}}})",
        R"({"source": "speed", "curve": "table", "table": [[0, 0], [0.3, 0.7], [1, 1]], "scale": "minor", "out": [40, 80], "steps": 20,
            "to": {"param": "p%N"}})",
    };
    std::string s = R"({"version": 1, "postures": [{"name": "up", "examples": [[0.5, 0.5, 0.5, 0.5]], "radius": 40}], "mappings": [)";
    for (int i = 0; i < 64; ++i) {
        std::string m = families[i % 8];
        const auto put = [&](const std::string& key, int v) {
            for (std::size_t at = m.find(key); at != std::string::npos; at = m.find(key)) m.replace(at, key.size(), std::to_string(v));
        };
        put("%C", 1 + i % 16);
        put("%N", i % 32);
        put("%M", 1 + i % 8);
        s += (i ? ",\n" : "") + m;
    }
    return s + "]}";
}

} // namespace

TEST_CASE("The guard sees an allocation (so its zeros below mean something)", "[mapping][realtime]")
{
    ARMADILLO_REQUIRE_GUARD();
    RealtimeGuard guard;
    auto p = std::make_unique<std::vector<int>>(100);
    CHECK(guard.allocations() >= 2);
    p.reset();
    CHECK(guard.deallocations() >= 2);
}

TEST_CASE("64 mappings run without allocation, free, lock or throw", "[mapping][realtime]")
{
    ARMADILLO_REQUIRE_GUARD();
    const MappingDocument doc = parseMappingDocument(sixtyFour(), "sixty-four.json");
    REQUIRE(doc.mappings.size() == 64);
    Mapper mapper;
    mapper.replace(MappingSet::build(doc));
    auto out = std::make_unique<MappingOutput>();
    std::unique_ptr<MappingSet> next = MappingSet::build(doc);   // handed over mid-run

    const char* names[] {"roll", "punch", "strike", "fret", "select"};
    std::uint64_t allocations = 0, frees = 0, locks = 0, throws = 0;
    std::size_t midi = 0, osc = 0, params = 0, macros = 0;
    const Eigen::Quaterniond up(0.5, 0.5, 0.5, 0.5);
    for (int i = 0; i < 4000; ++i) {
        const double t = i * 0.005;
        ArmState arm = armAt(60.0 * std::sin(t * 0.9), std::fmod(t * 40.0, 360.0), 100.0 * std::sin(t * 1.7), t);
        if (i % 500 > 400) arm.q = up;   // hold the learned posture now and then
        arm.gyro = Eigen::Vector3d(std::sin(t), 2.0 * std::cos(t * 3.0), 0.5);
        GestureIn g[2] {{names[i % 5], 0.8f}, {"other", -0.3f}};
        MappingInput in;
        in.t = t;
        in.arm[0] = &arm;
        in.gestures = g;
        in.gestureCount = i % 37 == 0 ? 2 : 0;
        in.scene.pitch = static_cast<float>(60 + 10 * std::sin(t));
        if (i == 2000) REQUIRE(mapper.offer(next));   // the builder's side, outside the guard
        if (i == 900) mapper.requestForward();
        if (i == 1500) mapper.active()->setMuted(3, true);
        {
            RealtimeGuard guard;
            mapper.process(in, *out);
            if (i % 100 == 99) mapper.flush(t + 0.004, *out);
            if (i == 3999) mapper.allNotesOff(t, *out);
            allocations += guard.allocations();
            frees += guard.deallocations();
            locks += guard.locks();
            throws += guard.throws();
        }
        midi += static_cast<std::size_t>(out->midiCount);
        osc += static_cast<std::size_t>(out->oscCount);
        params += static_cast<std::size_t>(out->paramCount);
        macros += out->macroChanged != 0;
        CHECK(out->dropped == 0);
        out->clear();
    }
    CHECK(allocations == 0);
    CHECK(frees == 0);
    CHECK(locks == 0);
    CHECK(throws == 0);
    // Everything really ran (a silent mapper would pass the guard trivially).
    CHECK(midi > 10000);
    CHECK(osc > 50);
    CHECK(params > 100);
    CHECK(macros > 10);
    mapper.collect();
}

TEST_CASE("Two-arm sources (left.*, arms.*) run without allocation, free, lock or throw", "[mapping][realtime][twoarms]")
{
    ARMADILLO_REQUIRE_GUARD();
    const MappingDocument doc = parseMappingDocument(R"({"version": 1, "mappings": [
        {"source": "left.elevation", "smoothMs": 10, "to": {"midi": "cc14", "channel": 2, "cc": 1}},
        {"source": "left.azimuth", "to": {"midi": "notes", "channel": 3, "zones": [[0, 120, 60], [120, 240, 64], [240, 360, 67], [350, 10, 70]]}},
        {"source": "left.roll", "to": {"osc": "/left/{arm}/roll", "args": ["$value", "$left.ypr.qw", "$arms.angle"]}},
        {"source": "arms.angle", "to": {"midi": "cc", "channel": 4, "cc": 20}},
        {"source": "arms.roll", "smoothMs": 20, "to": {"midi": "pitchbend", "channel": 5}},
        {"source": "arms.raised", "to": {"midi": "note", "channel": 6, "note": 40, "velocity": {"source": "left.speed", "in": [0, 300]}}},
        {"source": "elevation", "to": {"midi": "cc", "channel": 1, "cc": 7}}]})",
                                                     "two-arms.json");
    Mapper mapper;
    mapper.replace(MappingSet::build(doc));
    auto out = std::make_unique<MappingOutput>();
    std::uint64_t allocations = 0, frees = 0, locks = 0, throws = 0;
    std::size_t midi = 0, osc = 0;
    for (int i = 0; i < 3000; ++i) {
        const double t = i * 0.005;
        ArmState right = armAt(50.0 * std::sin(t * 0.7), std::fmod(t * 30.0, 360.0), 90.0 * std::sin(t * 1.3), t);
        ArmState left = armAt(50.0 * std::sin(t * 0.5 + 1.0), std::fmod(300.0 + t * 50.0, 360.0), 170.0 * std::sin(t * 0.9), t);
        left.gyro = Eigen::Vector3d(std::sin(t), 1.0, 0.2);
        MappingInput in;
        in.t = t;
        in.arm[0] = &right;
        in.arm[1] = i % 700 < 50 ? nullptr : &left;   // the second arm drops out now and then
        {
            RealtimeGuard guard;
            mapper.process(in, *out);
            allocations += guard.allocations();
            frees += guard.deallocations();
            locks += guard.locks();
            throws += guard.throws();
        }
        midi += static_cast<std::size_t>(out->midiCount);
        osc += static_cast<std::size_t>(out->oscCount);
        out->clear();
    }
    CHECK(allocations == 0);
    CHECK(frees == 0);
    CHECK(locks == 0);
    CHECK(throws == 0);
    CHECK(midi > 3000);
    CHECK(osc > 1000);
}
