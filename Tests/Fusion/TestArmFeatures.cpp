// Arm features of thesis §2.6.3 in the frames of INTERFACES.md.
#include "Core/Pose.h"
#include "Fusion/ArmFeatures.h"
#include "Fusion/Quaternion.h"
#include <catch2/catch.hpp>
#include <cmath>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::fusion;
using Eigen::Quaterniond;
using Eigen::Vector3d;

TEST_CASE("features: vectors and pose at rest and at known poses", "[fusion][features]")
{
    const Vector3d up(0.0, kStandardGravity, 0.0);
    ArmFeatures f = computeArmFeatures(restOrientation(), Vector3d::Zero(), quat::rotateInverse(restOrientation(), up));
    CHECK((f.axis - Vector3d(0, 0, -1)).norm() < 1e-12);    // forearm north
    CHECK((f.normal - Vector3d(0, 1, 0)).norm() < 1e-12);   // board face up
    CHECK((f.edge - Vector3d(1, 0, 0)).norm() < 1e-12);     // device z east
    CHECK(std::abs(f.pose.elevationDeg) < 1e-9);
    CHECK(std::abs(f.punch) < 1e-9);
    CHECK(f.rollTrigger == 0.0);

    const Pose p {30.0, 120.0, -45.0};
    f = computeArmFeatures(poseToQuaternion(p), Vector3d::Zero(), Vector3d(kNaN, kNaN, kNaN));
    CHECK(f.pose.elevationDeg == Approx(30.0));
    CHECK(f.pose.azimuthDeg == Approx(120.0));
    CHECK(f.pose.rollDeg == Approx(-45.0));
    CHECK(f.axis.y() == Approx(std::sin(degToRad(30.0))));   // elevation = forearm axis above horizontal
    CHECK(f.punch == 0.0);                                    // no accelerometer: no punch
}

TEST_CASE("features: flux, leading side and roll trigger (division by zero guarded)", "[fusion][features]")
{
    const Quaterniond q = poseToQuaternion({0.0, 70.0, 30.0});
    // Turning about the face normal (device y): the hand sweeps toward −z, the thumb of a right arm.
    ArmFeatures f = computeArmFeatures(q, Vector3d(0.0, 2.0, 0.0), Vector3d(kNaN, kNaN, kNaN));
    CHECK(f.fluxFace == Approx(2.0));
    CHECK(std::abs(f.fluxEdge) < 1e-12);
    CHECK(leadingSide(f, ArmSide::Right) == FluxSide::Thumb);
    CHECK(leadingSide(f, ArmSide::Left) == FluxSide::FifthFinger);
    f = computeArmFeatures(q, Vector3d(0.0, -2.0, 0.0), Vector3d(kNaN, kNaN, kNaN));
    CHECK(leadingSide(f, ArmSide::Right) == FluxSide::FifthFinger);
    // About the edge normal (device z): the hand moves toward +y (board face) or −y (palm).
    f = computeArmFeatures(q, Vector3d(0.0, 0.0, -1.5), Vector3d(kNaN, kNaN, kNaN));
    CHECK(f.fluxEdge == Approx(-1.5));
    CHECK(leadingSide(f) == FluxSide::Palm);
    f = computeArmFeatures(q, Vector3d(0.0, 0.0, 1.5), Vector3d(kNaN, kNaN, kNaN));
    CHECK(leadingSide(f) == FluxSide::Back);
    CHECK(leadingSide(computeArmFeatures(q, Vector3d(0.0, 0.01, 0.0), Vector3d::Zero())) == FluxSide::None);

    // A pure roll: no flux at all, the trigger stays finite (floor on the denominator).
    f = computeArmFeatures(q, Vector3d(3.0, 0.0, 0.0), Vector3d(kNaN, kNaN, kNaN));
    CHECK(std::isfinite(f.rollTrigger));
    CHECK(f.rollTrigger == Approx(3.0 / kRollTriggerFluxFloor));
    // A sweep with some roll: the ratio is small.
    f = computeArmFeatures(q, Vector3d(0.5, 2.0, 1.0), Vector3d(kNaN, kNaN, kNaN));
    CHECK(f.rollTrigger == Approx(0.5 / std::hypot(2.0, 1.0)));
    f = computeArmFeatures(q, Vector3d::Zero(), Vector3d::Zero());
    CHECK(f.rollTrigger == 0.0);
}

TEST_CASE("features: punch is the forearm-axis acceleration beyond gravity while the arm is still", "[fusion][features]")
{
    const Quaterniond q = poseToQuaternion({20.0, 10.0, 0.0});
    const Vector3d gravity = quat::rotateInverse(q, Vector3d(0.0, kStandardGravity, 0.0));
    ArmFeatures f = computeArmFeatures(q, Vector3d(0.1, 0.0, 0.0), gravity + Vector3d(15.0, 0.0, 0.0));
    CHECK(f.punch == Approx(15.0));
    f = computeArmFeatures(q, Vector3d(0.1, 0.0, 0.0), gravity + Vector3d(0.0, 15.0, 0.0));
    CHECK(std::abs(f.punch) < 1e-9);   // across the axis: not a punch
    f = computeArmFeatures(q, Vector3d(0.0, 3.0, 0.0), gravity + Vector3d(15.0, 0.0, 0.0));
    CHECK(f.punch == 0.0);             // swinging: centripetal, not a punch
}
