// The offline clock (Live/Session/RowClock.h, issue 45): `render` runs the live instrument's one
// step once per row of a motion file. What the rows' clock needs of the step, shown on the step
// itself: a recording's rows are fused whole and in full precision (a live mailbox keeps floats
// and drops a burst's oldest samples), and the first source's first step plays as any other
// (only a switch of source turns the old arm's motors off).
#include "Core/Pose.h"
#include "Engine/RenderSettings.h"
#include "Fusion/ArmTracker.h"
#include "Live/Session/Instrument.h"
#include "Live/Session/RowClock.h"
#include "LoopSlots.h"
#include <catch2/catch.hpp>
#include <cmath>

using namespace armadillo;
using namespace armadillo::live;

namespace {

/// IMU rows of a forearm turning slowly about gravity, at 200 Hz, with values no float holds.
engine::MotionRows turningImu(int rows)
{
    engine::MotionRows m;
    m.kind = core::MotionKind::Imu;
    for (int i = 0; i < rows; ++i) {
        core::ImuSample s;
        s.t = i * 0.005;
        s.gyro = Eigen::Vector3d(0.0, 0.3 + 1e-9 * i, 0.0);
        s.accel = Eigen::Vector3d(0.01 / 3.0, 9.80665, -0.02 / 7.0);
        s.mag = Eigen::Vector3d(0.4 / 3.0, -0.3, 0.1 / 7.0);
        m.imu.push_back(s);
    }
    return m;
}

bool anyOn(const core::MotorLevels& levels)
{
    for (float l : levels)
        if (l > 0.0f) return true;
    return false;
}

} // namespace

TEST_CASE("row clock: a recording's rows are fused whole and in full precision, where a live mailbox drops and rounds",
          "[live][render]")
{
    const int burst = 3 * ControlLoop::kMaxImuPerStep;
    const engine::MotionRows rows = turningImu(40 + burst);

    fusion::ArmTracker direct;   // the recording as the fusion would take it alone
    for (const core::ImuSample& s : rows.imu) direct.update(s);

    // The rows' clock: 40 steps of one row, then the burst in one step.
    ControlLoop recorded;
    recorded.replace(test::loopSlot("monitor"));
    ControlStep step;
    step.source = SourceKind::Device;
    ControlResult r;
    for (std::size_t i = 0; i < 40; ++i) {
        step.recorded = {&rows, i, i + 1};
        r = recorded.tick(step);
    }
    step.recorded = {&rows, 40, rows.size()};
    r = recorded.tick(step);
    REQUIRE(r.arm.valid);
    CHECK(recorded.droppedImu() == 0);
    CHECK(r.arm.t == rows.imu.back().t);
    CHECK(r.arm.q.coeffs() == direct.state().q.coeffs());   // bit for bit

    // The probe: the same samples through the live mailbox (the source's clock) are not the same.
    ControlLoop live;
    live.replace(test::loopSlot("monitor"));
    ControlStep liveStep;
    liveStep.source = SourceKind::Device;
    for (std::size_t i = 0; i < 40; ++i) {
        live.input(SourceKind::Device).pushImu(rows.imu[i]);
        live.tick(liveStep);
    }
    for (std::size_t i = 40; i < rows.size(); ++i) live.input(SourceKind::Device).pushImu(rows.imu[i]);
    const ControlResult l = live.tick(liveStep);
    CHECK(live.droppedImu() == static_cast<std::uint64_t>(burst - ControlLoop::kMaxImuPerStep));
    CHECK(l.arm.q.coeffs() != direct.state().q.coeffs());
}

TEST_CASE("row clock: the first source's first step plays; a switch of source turns the old arm's motors off", "[live][render]")
{
    engine::MotionRows rows;
    rows.kind = core::MotionKind::Quaternion;
    for (int i = 0; i < 4; ++i) rows.orientations.push_back({i * 0.005, core::poseToQuaternion(core::Pose {10.0, 0.0, 0.0})});

    Instrument instrument;
    instrument.loop().replace(test::loopSlot("theremin"));
    ControlStep step;
    step.source = SourceKind::Device;
    step.dt = 0.005;
    step.recorded = {&rows, 0, 1};
    instrument.beginStage();
    const Instrument::Stepped first = instrument.step(step, 0.0, true);
    REQUIRE(first.result.ran);
    CHECK(first.result.arm.valid);
    CHECK(anyOn(first.result.levels));   // the render's first row is felt

    for (std::size_t i = 1; i < rows.size(); ++i) {
        step.recorded = {&rows, i, i + 1};
        CHECK(anyOn(instrument.step(step, 0.005 * static_cast<double>(i), true).result.levels));
    }
    ControlStep automation;   // another arm: host automation at the same pose
    automation.source = SourceKind::HostAutomation;
    automation.automation = core::Pose {10.0, 0.0, 0.0};
    automation.dt = 0.005;
    CHECK_FALSE(anyOn(instrument.step(automation, 0.02, true).result.levels));
}

TEST_CASE("row clock: render drives the instrument's stage: a set list's cue changes at their rows, cue indices checked",
          "[live][render]")
{
    std::string csv = "t,elevation,azimuth,roll\n";
    for (int i = 0; i <= 200; ++i) csv += std::to_string(i * 0.005) + ",10,0,0\n";
    const core::CsvTable motion = core::CsvTable::parse(csv, "still.csv");
    SetList list;
    list.source = "two.json";
    list.cues.push_back({"A", "theremin", {}, {}, {}, {}, {}, 1});
    list.cues.push_back({"B", "monitor", {}, {}, {}, {}, {}, 2});   // the monitor's motors stay off
    engine::RenderSettings settings;
    settings.engine.sceneConfig.sampleRate = 48000.0;
    const engine::RenderResult r = renderOffline(motion, settings, list, {{0.5, 1}});
    REQUIRE(r.tactile.size() == 202);
    CHECK(anyOn(r.tactile[0].levels));       // cue A from the first row
    CHECK(anyOn(r.tactile[99].levels));      // t = 0.495: still A
    CHECK_FALSE(anyOn(r.tactile[100].levels));   // t = 0.5: B has the motors
    CHECK_THROWS_WITH(renderOffline(motion, settings, list, {{0.5, 2}}), Catch::Contains("cue 2 does not exist"));
}
