// Jump-start only where it helps (docs/TACTILE.md): the tactile rows `armadillo render` writes
// hold no level-15 sample inside a soft intent — the cymbal's damping touch, the panel's
// fade-out pulses, the Rite of Spring's opening crescendo — while fast intents still get it.
#include "CliRun.h"
#include "Core/Csv.h"
#include "Core/Pose.h"
#include "SafetyBounds.h"
#include <catch2/catch.hpp>
#include <functional>

using namespace armadillo;
using namespace armadillo::core;

namespace {
struct Segment {
    double seconds;
    Pose from, to;
};

/// A pose file at 200 Hz through the segments (linear in each).
std::string motionFile(const std::string& name, const std::vector<Segment>& segments)
{
    std::string s = "t,elevation,azimuth,roll\n";
    double t0 = 0.0;
    for (const auto& seg : segments) {
        const int n = static_cast<int>(seg.seconds * 200.0 + 0.5);
        for (int i = 0; i < n; ++i) {
            const double f = double(i) / n;
            const Pose p {seg.from.elevationDeg + f * (seg.to.elevationDeg - seg.from.elevationDeg),
                          seg.from.azimuthDeg + f * (seg.to.azimuthDeg - seg.from.azimuthDeg),
                          seg.from.rollDeg + f * (seg.to.rollDeg - seg.from.rollDeg)};
            s += std::to_string(t0 + i / 200.0) + "," + std::to_string(p.elevationDeg) + "," + std::to_string(p.azimuthDeg) + "," +
                 std::to_string(p.rollDeg) + "\n";
        }
        t0 += n / 200.0;
    }
    return cli::file(name, s);
}

std::vector<TactileRow> render(const std::string& args, const std::string& name)
{
    const std::string tactile = cli::path(name + ".csv");
    const auto r = cli::runArmadillo("render " + args + " --out '" + cli::path(name + ".wav") + "' --tactile '" + tactile + "'");
    INFO(r.err);
    REQUIRE(r.code == 0);
    auto rows = readTactile(CsvTable::read(tactile));
    const auto report = armadillo::testing::checkSafety(rows, kGridMotors);
    INFO(report.worst);
    CHECK(report.ok());
    return rows;
}

int peakIn(const std::vector<TactileRow>& rows, double from, double to, int* onRows = nullptr)
{
    int peak = 0, on = 0;
    for (const auto& row : rows) {
        if (row.t < from || row.t >= to) continue;
        bool any = false;
        for (int m = 0; m < kGridMotors; ++m) {
            peak = std::max<int>(peak, row.levels[static_cast<std::size_t>(m)]);
            any = any || row.levels[static_cast<std::size_t>(m)] > 0;
        }
        on += any;
    }
    if (onRows) *onRows = on;
    return peak;
}
} // namespace

TEST_CASE("soft starts: the cymbal's strike kicks, its damping touch never does", "[e2e][soft][cymbal]")
{
    // Above, a strike (200 deg/s down through the surface), ringing inside, out above it, then
    // a gentle touch (15 deg/s) back in while it still rings: the damping touch.
    const Pose above {30.0, 0.0, 0.0}, inside {-20.0, 0.0, 0.0}, near {8.0, 0.0, 0.0}, touch {-5.0, 0.0, 0.0};
    const std::string motion = motionFile("cymbal-damp.csv", {{0.5, above, above}, {0.25, above, inside}, {1.0, inside, inside},
                                                                 {0.5, inside, near}, {0.3, near, near},
                                                                 {13.0 / 15.0, near, touch}, {1.5, touch, touch}});
    const auto rows = render("--scene cymbal --seed 3 --motion '" + motion + "'", "cymbal-damp");
    int strikeOn = 0, touchOn = 0;
    CHECK(peakIn(rows, 0.5, 1.75, &strikeOn) == 15);         // the strike's jolt: a fast start
    const double touchFrom = 0.5 + 0.25 + 1.0 + 0.5 + 0.3;  // the arm is above the surface here
    const int touchPeak = peakIn(rows, touchFrom, 1e9, &touchOn);
    CHECK(strikeOn > 0);
    CHECK(touchOn > 50);          // the touch is felt ...
    CHECK(touchPeak > 0);
    CHECK(touchPeak < 15);        // ... and never with the spike
    CHECK(touchPeak <= 5);        // the fade (4) and the idle vibration (1): nothing above the rating
}

TEST_CASE("soft starts: the panel's fade pulses never spike", "[e2e][soft][panel]")
{
    // Held in the lower level (fade-out pulses) and then the upper (fade-in pulses); the level
    // change between them is a jolt (a fast start) that is allowed its spike.
    const std::string motion = motionFile("panel.csv", {{3.0, {-40.0, 100.0, 0.0}, {-40.0, 100.0, 0.0}},
                                                          {0.2, {-40.0, 100.0, 0.0}, {40.0, 100.0, 0.0}},
                                                          {3.0, {40.0, 100.0, 0.0}, {40.0, 100.0, 0.0}}});
    const auto rows = render("--scene panel --motion '" + motion + "'", "panel");
    int lowerOn = 0, upperOn = 0;
    CHECK(peakIn(rows, 0.0, 3.0, &lowerOn) < 15);
    CHECK(peakIn(rows, 3.8, 6.2, &upperOn) < 15);
    CHECK(lowerOn > 100);
    CHECK(upperOn > 100);
    CHECK(peakIn(rows, 3.0, 3.8) == 15);   // the jolt on changing level
}

TEST_CASE("soft starts: the Rite's opening crescendo starts soft, the next notes are kicked", "[e2e][soft][score]")
{
    const std::string motion = motionFile("still-rite.csv", {{8.0, {}, {}}});
    const auto rows = render("--scene score --score rite-of-spring --motion '" + motion + "'", "rite-soft");
    int openingOn = 0;
    const int opening = peakIn(rows, 0.0, 4.8, &openingOn);   // beat 0..4 at 50 bpm: the held C
    CHECK(openingOn > 400);
    CHECK(opening > 0);
    CHECK(opening <= 6);
    CHECK(peakIn(rows, 4.8, 5.0) == 15);   // the B that follows starts with the spike
}
