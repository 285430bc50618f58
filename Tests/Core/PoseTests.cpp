#include "Core/Pose.h"
#include "Core/Types.h"
#include <catch2/catch.hpp>
#include <random>

using namespace armadillo;
using namespace armadillo::core;

namespace {
Eigen::Vector3d earth(const Eigen::Quaterniond& q, const Eigen::Vector3d& v) { return q * v; }
const Eigen::Vector3d kNorth(0, 0, -1), kEast(1, 0, 0), kUp(0, 1, 0);
} // namespace

TEST_CASE("Pose: the rest pose of INTERFACES.md", "[pose]")
{
    const Eigen::Quaterniond q = restOrientation();
    CHECK(q.w() == Approx(std::cos(kPi / 4)));
    CHECK(q.y() == Approx(std::sin(kPi / 4)));
    CHECK(q.x() == Approx(0.0).margin(1e-12));
    CHECK(q.z() == Approx(0.0).margin(1e-12));
    CHECK(earth(q, Eigen::Vector3d::UnitX()).isApprox(kNorth, 1e-12));   // forearm points north
    CHECK(earth(q, Eigen::Vector3d::UnitY()).isApprox(kUp, 1e-12));      // board face up
}

TEST_CASE("Pose: angles mean what INTERFACES.md says", "[pose]")
{
    // Azimuth clockwise from north seen from above: 90° points the forearm east.
    CHECK(earth(poseToQuaternion({0, 90, 0}), Eigen::Vector3d::UnitX()).isApprox(kEast, 1e-12));
    // Elevation raises the forearm axis.
    const Eigen::Vector3d up30 = earth(poseToQuaternion({30, 0, 0}), Eigen::Vector3d::UnitX());
    CHECK(up30.y() == Approx(0.5));
    // Roll is clockwise looking from elbow to hand: with the forearm north, +90° turns the
    // board face (up) toward east.
    CHECK(earth(poseToQuaternion({0, 0, 90}), Eigen::Vector3d::UnitY()).isApprox(kEast, 1e-12));
}

TEST_CASE("Pose: quaternion → pose → quaternion is exact away from the poles", "[pose]")
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> el(-89.0, 89.0), az(0.0, 360.0), ro(-179.9, 179.9);
    for (int i = 0; i < 2000; ++i) {
        const Pose p {el(rng), az(rng), ro(rng)};
        const Pose back = quaternionToPose(poseToQuaternion(p));
        CHECK(back.elevationDeg == Approx(p.elevationDeg).margin(1e-7));
        CHECK(wrapDeg180(back.azimuthDeg - p.azimuthDeg) == Approx(0.0).margin(1e-6));
        CHECK(wrapDeg180(back.rollDeg - p.rollDeg) == Approx(0.0).margin(1e-6));
    }
    // At the pole the quaternion still round-trips, though azimuth and roll share the turn.
    const Eigen::Quaterniond pole = poseToQuaternion({90, 40, 10});
    CHECK(poseToQuaternion(quaternionToPose(pole)).angularDistance(pole) < 1e-6);
}

TEST_CASE("Pose: angle wrapping", "[pose]")
{
    CHECK(wrapDeg180(190.0) == Approx(-170.0));
    CHECK(wrapDeg180(-180.0) == Approx(-180.0));
    CHECK(wrapDeg360(-10.0) == Approx(350.0));
    CHECK(wrapDeg360(720.0) == Approx(0.0));
}
