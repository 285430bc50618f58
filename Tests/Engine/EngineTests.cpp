#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Fusion/ArmTracker.h"
#include "Engine/Engine.h"
#include "Engine/RenderSettings.h"
#include "Live/Session/RowClock.h"
#include <catch2/catch.hpp>
#include <cmath>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;
using armadillo::live::renderOffline;
using namespace armadillo::fusion;

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
    const std::vector<std::string> expected {"monitor", "theremin", "cymbal", "panel", "sound-design", "compass", "braille", "score", "audio-touch", "layered-keyboard", "theremin-duo"};
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
    CHECK(r.tactile.size() == 402);   // one per row, then the all-off sent at the end
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

TEST_CASE("Engine: the same motion and seed render the same result, sample by sample and row by row", "[engine]")
{
    // A scene with sound and motors (the theremin: pitch from elevation, frets felt on the
    // motors) over a sweep of the arm, so a render that dropped audio, motors or input would be
    // caught: both runs must make sound and drive motors, match exactly, and a different motion
    // must give a different result.
    std::string sweep = "t,elevation,azimuth,roll\n", other = sweep;
    for (int i = 0; i <= 300; ++i) {
        const double t = i / 100.0;
        sweep += std::to_string(t) + "," + std::to_string(-50.0 + 100.0 * t / 3.0) + ",10,0\n";
        other += std::to_string(t) + "," + std::to_string(50.0 - 100.0 * t / 3.0) + ",10,0\n";
    }
    RenderSettings settings;
    settings.engine.scene = "theremin";
    const auto table = CsvTable::parse(sweep, "sweep.csv");
    const auto a = renderOffline(table, settings), b = renderOffline(table, settings);
    REQUIRE(a.audio.channels.size() == 2);
    REQUIRE(a.audio.frames() > 100000);
    double energy = 0.0;
    for (float x : a.audio.channels[0]) energy += double(x) * double(x);
    REQUIRE(energy > 1.0);                       // it made sound …
    std::size_t motorRows = 0;
    for (const auto& row : a.tactile) {
        bool on = false;
        for (auto l : row.levels) on = on || l > 0;
        motorRows += on;
    }
    REQUIRE(motorRows > a.tactile.size() / 2);   // … and drove motors
    REQUIRE(b.audio.channels.size() == 2);
    REQUIRE(a.audio.frames() == b.audio.frames());
    std::size_t sampleMismatches = 0;
    for (std::size_t c = 0; c < 2; ++c)
        for (std::size_t i = 0; i < a.audio.frames(); ++i) sampleMismatches += a.audio.channels[c][i] != b.audio.channels[c][i];
    CHECK(sampleMismatches == 0);
    REQUIRE(a.tactile.size() == b.tactile.size());
    std::size_t rowMismatches = 0;
    for (std::size_t r = 0; r < a.tactile.size(); ++r)
        rowMismatches += a.tactile[r].t != b.tactile[r].t || a.tactile[r].levels != b.tactile[r].levels;
    CHECK(rowMismatches == 0);
    CHECK(a.gestures.size() == b.gestures.size());

    const auto c = renderOffline(CsvTable::parse(other, "other.csv"), settings);
    std::size_t differ = 0;
    for (std::size_t r = 0; r < std::min(a.tactile.size(), c.tactile.size()); ++r) differ += a.tactile[r].levels != c.tactile[r].levels;
    CHECK(differ > 0);                           // the result depends on the motion
    CHECK(c.audio.channels[0] != a.audio.channels[0]);
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

TEST_CASE("renderOffline: a streamed render hands every frame to the sink and ends with the all-off; absurd spans are refused first",
          "[engine][render]")
{
    RenderSettings settings;
    settings.engine.scene = "theremin";
    const CsvTable motion = CsvTable::parse(poseMotion(1.0, 100.0, 30.0), "m.csv");
    const RenderResult collected = renderOffline(motion, settings);
    std::vector<float> left, right;
    int largestBlock = 0;
    settings.audioSink = [&](const float* l, const float* r, int n) {
        left.insert(left.end(), l, l + n);
        right.insert(right.end(), r, r + n);
        largestBlock = std::max(largestBlock, n);
    };
    const RenderResult streamed = renderOffline(motion, settings);
    CHECK(streamed.audio.channels.empty());
    CHECK(streamed.frames == collected.audio.frames());
    CHECK(left == collected.audio.channels[0]);   // the same engine, the same samples
    CHECK(right == collected.audio.channels[1]);
    CHECK(largestBlock <= settings.blockSize);
    REQUIRE(streamed.tactile.size() == streamed.controlUpdates + 1);
    CHECK(streamed.tactile.back().t == 1.0);
    for (auto level : streamed.tactile.back().levels) CHECK(level == 0);
    CHECK(streamed.peak > 0.0f);
    CHECK(silenceReason(streamed, settings).empty());

    // Two rows an hour and a second apart: too long to collect in memory, refused naming the row
    // before the engine runs; a day and a second: too long even to stream.
    const CsvTable hour = CsvTable::parse("t,elevation,azimuth,roll\n0,0,0,0\n3601,0,0,0\n", "hour.csv");
    RenderSettings inMemory;
    try {
        (void) renderOffline(hour, inMemory);
        FAIL("an hour and a second was collected in memory");
    } catch (const InputError& e) {
        CHECK(std::string(e.what()).rfind("hour.csv:3: column 't': the file would render 3601 s", 0) == 0);
    }
    settings.audioSink = [](const float*, const float*, int) {};
    CHECK_THROWS_AS(renderOffline(CsvTable::parse("t,elevation,azimuth,roll\n0,0,0,0\n86401,0,0,0\n", "day.csv"), settings), InputError);

    RenderSettings monitor;
    monitor.engine.scene = "monitor";
    const RenderResult silent = renderOffline(motion, monitor);
    CHECK(silent.peak == 0.0f);
    CHECK(silenceReason(silent, monitor).find("monitor scene makes no sound") != std::string::npos);
}
