// Posture learning by example: recording, the nearest-neighbour classifier with its hysteresis
// and confidence, and a learned posture driving a mapping from the file.
#include "Core/Errors.h"
#include "Mapping/MappingHelpers.h"
#include "Mapping/Posture.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::mapping;
using namespace armadillo::mapping::test;

namespace {
Eigen::Quaterniond at(double el, double az, double roll) { return poseToQuaternion(Pose {el, az, roll}); }

PostureSpec record(const std::string& name, double el, double az, double roll, std::mt19937& rng)
{
    std::normal_distribution<double> jitter(0.0, 1.0);   // ±1° of hand tremor and fusion noise
    PostureRecorder r;
    for (int i = 0; i < 400; ++i) r.add(at(el + jitter(rng), az + jitter(rng), roll + jitter(rng)), 5.0);
    return r.finish(name);
}
} // namespace

TEST_CASE("Quaternion distance is the rotation angle between two orientations, sign-free", "[mapping][posture]")
{
    const Eigen::Quaterniond a = at(0, 0, 0);
    const Eigen::Quaterniond b = a * Eigen::Quaterniond(Eigen::AngleAxisd(degToRad(37.0), Eigen::Vector3d::UnitX()));
    CHECK(quaternionDistanceDeg(a, b) == Approx(37.0));
    const Eigen::Quaterniond minusB(-b.w(), -b.x(), -b.y(), -b.z());
    CHECK(quaternionDistanceDeg(a, minusB) == Approx(37.0));
}

TEST_CASE("Recorded postures are recognised, with closeness, confidence and hysteresis", "[mapping][posture]")
{
    std::mt19937 rng(5);
    const PostureSpec up = record("up", 60, 0, 0, rng);
    const PostureSpec side = record("side", 0, 90, 0, rng);
    CHECK(up.examples.size() == static_cast<std::size_t>(kMaxPostureExamples));
    CHECK(up.radiusDeg >= 15.0);
    PostureClassifier c({up, side});
    REQUIRE(c.size() == 2);
    CHECK(c.indexOf("side") == 1);
    CHECK(c.indexOf("none") == -1);

    c.update(at(60, 0, 0), 0.0);
    CHECK(c.current() == 0);
    CHECK(c.state(0).inside);
    CHECK(c.state(0).closeness > 0.8);
    CHECK(c.confidence() > 0.8);
    c.update(at(0, 90, 0), 0.0);
    CHECK(c.current() == 1);
    // Moving fast: no posture is held.
    c.update(at(0, 90, 0), 500.0);
    CHECK(c.current() == -1);
    CHECK(c.state(1).closeness == 0.0);
    // Hysteresis: at the radius edge, wiggling by less than the hysteresis does not chatter.
    c.reset();
    const double r = up.radiusDeg;
    c.update(at(60.0 - (r - 5.0), 0, 0), 0.0);   // well inside (distance ≈ radius − 5° from the nearest example)
    REQUIRE(c.current() == 0);
    int changes = 0, last = c.current();
    for (int i = 0; i < 200; ++i) {
        c.update(at(60.0 - r - 0.9 * std::sin(i * 0.8), 0, 0), 0.0);   // ±0.9° about the radius
        if (c.current() != last) ++changes;
        last = c.current();
    }
    CHECK(changes <= 1);
    c.update(at(-30, 180, 0), 0.0);
    CHECK(c.current() == -1);
}

TEST_CASE("Recording refuses a posture without enough still samples", "[mapping][posture]")
{
    PostureRecorder r;
    for (int i = 0; i < 100; ++i) r.add(at(0, 0, 0), 400.0);
    CHECK_THROWS_AS(r.finish("blur"), InputError);
    CHECK_THROWS_WITH(r.finish("blur"), Catch::Contains("blur") && Catch::Contains("still"));
}

TEST_CASE("A learned posture in the mapping file plays a note on enter and ends it on leave", "[mapping][posture]")
{
    std::mt19937 rng(9);
    MappingDocument doc = parseMappingDocument(R"({"version": 1, "mappings": [
        {"source": "posture:salute", "to": {"midi": "note", "channel": 4, "note": 70}},
        {"source": "posture:salute", "to": {"macro": 5}}],
        "postures": [{"name": "salute", "examples": [[1, 0, 0, 0]]}]})", "p.json");
    doc.postures[0] = record("salute", 45, 300, 30, rng);
    const MappingDocument reread = parseMappingDocument(toJson(doc), "saved.json");   // postures are saved in the file
    REQUIRE(reread.postures.at(0).examples.size() == doc.postures[0].examples.size());
    Rig rig(reread);
    rig.pose(-20, 100, 0, 0.0);
    CHECK(rig.midi.empty());
    CHECK(rig.macro[4] == Approx(0.0f));
    rig.pose(45, 300, 30, 0.005);
    REQUIRE(rig.midi.size() == 1);
    CHECK(rig.midi[0].bytes == std::array<std::uint8_t, 3> {0x93, 70, 100});
    CHECK(rig.macro[4] > 0.8f);
    rig.pose(46, 301, 29, 0.010);
    CHECK(rig.midi.size() == 1);
    rig.pose(-20, 100, 0, 0.015);
    REQUIRE(rig.midi.size() == 2);
    CHECK(rig.midi[1].bytes[0] == 0x83);
}
