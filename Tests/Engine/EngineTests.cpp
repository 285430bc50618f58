#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Engine/ArmTracker.h"
#include "Engine/Engine.h"
#include "Engine/OfflineRenderer.h"
#include <catch2/catch.hpp>
#include <cmath>

using namespace armadillo;

namespace {
std::string poseMotion(double seconds, double rate, double elevationDeg)
{
    std::string s = "t,elevation,azimuth,roll\n";
    for (int i = 0; i <= static_cast<int>(seconds * rate); ++i) {
        s += std::to_string(i / rate) + "," + std::to_string(elevationDeg) + ",10,0\n";
    }
    return s;
}
} // namespace

TEST_CASE("Engine: scene names are those of INTERFACES.md; unknown names are refused", "[engine]")
{
    const std::vector<std::string> expected {"monitor", "theremin", "cymbal", "panel", "sound-design", "compass", "braille", "score"};
    CHECK(sceneNames() == expected);
    CHECK_THROWS_AS(createScene("kazoo"), InputError);
    CHECK(createScene("monitor")->name() == "monitor");
}

TEST_CASE("Engine: the monitor scene is silent and keeps every motor off", "[engine]")
{
    RenderSettings settings;
    settings.engine.scene = "monitor";
    const auto r = renderOffline(CsvTable::parse(poseMotion(2.0, 200.0, 20.0), "m.csv"), settings);
    CHECK(r.controlUpdates == 401);
    CHECK(r.tactile.size() == 401);
    CHECK(r.audio.frames() == static_cast<std::size_t>(2.0 * 48000) + 1);
    for (const auto& row : r.tactile)
        for (auto level : row.levels) REQUIRE(level == 0);
    for (const auto& ch : r.audio.channels)
        for (float x : ch) REQUIRE(x == 0.0f);
}

TEST_CASE("Engine: a file that is not motion is refused with its name", "[engine]")
{
    RenderSettings settings;
    CHECK_THROWS_AS(renderOffline(CsvTable::parse("t,foo\n0,1\n", "nomotion.csv"), settings), InputError);
}

TEST_CASE("ArmTracker: angular velocity from successive orientations is the body rate", "[engine][tracker]")
{
    ArmTracker tracker;
    const double rate = 1.5;   // rad/s about the forearm axis (roll)
    ArmState s;
    for (int i = 0; i <= 100; ++i) {
        const double t = i / 200.0;
        s = tracker.updateOrientation(t, poseToQuaternion({10.0, 30.0, radToDeg(rate * t)}));
    }
    CHECK(s.valid);
    CHECK(s.gyro.x() == Approx(rate).epsilon(1e-6));
    CHECK(s.gyro.y() == Approx(0.0).margin(1e-6));
    CHECK(s.gyro.z() == Approx(0.0).margin(1e-6));
    // Gravity alone, expressed in the device frame: |a| = g and the pose's elevation is kept.
    CHECK(s.accel.norm() == Approx(kStandardGravity));
    CHECK(s.features.pose.elevationDeg == Approx(10.0).margin(1e-9));
}

TEST_CASE("Engine: the same motion and seed render the same result", "[engine]")
{
    RenderSettings settings;
    settings.engine.scene = "monitor";
    const auto table = CsvTable::parse(poseMotion(0.5, 100.0, -10.0), "m.csv");
    const auto a = renderOffline(table, settings), b = renderOffline(table, settings);
    CHECK(a.audio.channels == b.audio.channels);
    CHECK(a.tactile.size() == b.tactile.size());
}

TEST_CASE("Engine: scene parameters are set by stable id, by number or choice name", "[engine][params]")
{
    EngineConfig config;
    config.scene = "braille";
    config.sceneConfig.text = "exit";
    Engine engine(config);
    CHECK_NOTHROW(engine.setSceneParameter("braille.mode", "passive"));
    CHECK_NOTHROW(engine.setSceneParameter("braille.step", "20"));
    CHECK_THROWS_AS(engine.setSceneParameter("braille.step", "200"), InputError);     // out of range
    CHECK_THROWS_AS(engine.setSceneParameter("braille.mode", "dancing"), InputError); // no such choice
    CHECK_THROWS_AS(engine.setSceneParameter("theremin.range", "12"), InputError);    // another scene's
    CHECK_THROWS_AS(engine.setSceneParameters({"braille.step"}), InputError);         // not id=value

    // Passive mode draws the text with the arm held still; active mode waits for a roll.
    const auto motorsOnStill = [](const std::string& mode) {
        RenderSettings settings;
        settings.engine.scene = "braille";
        settings.engine.sceneConfig.text = "exit";
        settings.engine.parameters = {"braille.mode=" + mode};
        std::string rows = "t,elevation,azimuth,roll\n";
        for (int i = 0; i <= 2000; ++i) rows += std::to_string(i / 200.0) + ",-80,0,0\n";
        const auto r = renderOffline(CsvTable::parse(rows, "still.csv"), settings);
        int on = 0;
        for (const auto& row : r.tactile)
            for (int m = 0; m < kGridMotors; ++m) on += row.levels[static_cast<std::size_t>(m)] > 0;
        return on;
    };
    CHECK(motorsOnStill("passive") > 100);
    CHECK(motorsOnStill("passive") > 10 * motorsOnStill("active"));
}
