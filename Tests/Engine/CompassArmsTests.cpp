// The compass through the whole engine (scene → shaping → left-arm mirroring → safety), on both
// arms: the turn cue must be on the side of the body the arm should turn toward, and the clicks
// must play at compass.level, not at the jump-start spike's level.
#include "Core/Pose.h"
#include "Engine/Engine.h"
#include <catch2/catch.hpp>
#include <algorithm>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;

namespace {
/// Physical motor columns as the board drives them (after the engine's mirroring). The motor
/// layout's columns are the arm's sides: on the right arm column 0 is the thumb side, and the
/// left arm is the mirror image (column 2 the thumb side). With the palm down the right arm's
/// thumb is on the body's left and the left arm's thumb on the body's right, so the physical
/// column on the body's right is the one that does NOT hold the right arm's thumb, i.e.
/// column 2 on the right arm (fifth finger) and column 2 on the left arm (thumb).
int bodySideColumn(ArmSide arm, bool bodyRight)
{
    const int thumbColumn = arm == ArmSide::Right ? 0 : 2;
    const bool thumbOnBodyRight = arm == ArmSide::Left;   // palm down
    return (bodyRight == thumbOnBodyRight) ? thumbColumn : 2 - thumbColumn;
}

struct Felt {
    std::array<int, kMaxMotors> peak {};
    std::array<int, kMaxMotors> onPackets {};
};

/// Holds a palm-down pose with the forearm at `forearmAzimuth` for `seconds` at 200 Hz.
Felt hold(Engine& engine, double forearmAzimuth, double seconds)
{
    Felt f;
    const Eigen::Quaterniond q = poseToQuaternion(Pose {0.0, forearmAzimuth, 0.0});
    for (int i = 0; i < static_cast<int>(seconds * 200.0); ++i) {
        ArmState arm;
        arm.valid = true;
        arm.t = i / 200.0;
        arm.q = q;
        const MotorLevels out = engine.control(arm, Transport {}, 1.0 / 200.0);
        for (int m = 0; m < kMaxMotors; ++m) {
            f.peak[static_cast<std::size_t>(m)] = std::max<int>(f.peak[static_cast<std::size_t>(m)], out[static_cast<std::size_t>(m)]);
            if (out[static_cast<std::size_t>(m)] > 0) ++f.onPackets[static_cast<std::size_t>(m)];
        }
    }
    return f;
}
} // namespace

TEST_CASE("compass: on both arms the turn cue is on the side of the body to turn toward", "[engine][compass]")
{
    for (ArmSide arm : {ArmSide::Right, ArmSide::Left}) {
        CAPTURE(arm == ArmSide::Right ? "right arm" : "left arm");
        EngineConfig config;
        config.scene = "compass";
        config.sceneConfig.side = arm;
        config.parameters = {"compass.target=90"};
        Engine engine(config);
        // With the palm down the thumb points 90° left of the forearm on the right arm and 90°
        // right of it on the left arm. Put the thumb at 50°: 40° short of the target, a
        // clockwise turn (to the body's right). Then at 130°: a turn to the left.
        const double thumbOffset = arm == ArmSide::Right ? -90.0 : 90.0;
        for (const bool turnRight : {true, false}) {
            CAPTURE(turnRight);
            const double thumb = turnRight ? 50.0 : 130.0;
            const Felt f = hold(engine, wrapDeg360(thumb - thumbOffset), 1.0);
            const int cue = motorIndex(1, bodySideColumn(arm, turnRight));
            const int other = motorIndex(1, bodySideColumn(arm, !turnRight));
            CHECK(f.onPackets[static_cast<std::size_t>(cue)] > 0);
            CHECK(f.onPackets[static_cast<std::size_t>(other)] == 0);
        }
    }
}

TEST_CASE("compass: clicks shorter than the jump-start spike play at compass.level", "[engine][compass]")
{
    for (const int level : {2, 5, 9}) {
        CAPTURE(level);
        EngineConfig config;
        config.scene = "compass";
        config.parameters = {"compass.target=90", "compass.level=" + std::to_string(level)};
        Engine engine(config);
        const Felt f = hold(engine, 140.0, 2.0);   // right arm, thumb at 50°: clicks, turn right
        const int cue = motorIndex(1, 2);
        CHECK(f.onPackets[static_cast<std::size_t>(cue)] > 0);
        CHECK(f.peak[static_cast<std::size_t>(cue)] == level);
    }
}
