#include "Core/Pose.h"
#include "Core/Types.h"
#include <algorithm>
#include <cmath>

namespace armadillo::core {
namespace {
Eigen::Quaterniond aboutAxis(double deg, const Eigen::Vector3d& axis)
{
    return Eigen::Quaterniond(Eigen::AngleAxisd(degToRad(deg), axis));
}
} // namespace

double wrapDeg180(double deg)
{
    double w = std::fmod(deg + 180.0, 360.0);
    if (w < 0.0) w += 360.0;
    return w - 180.0;
}

double wrapDeg360(double deg)
{
    double w = std::fmod(deg, 360.0);
    if (w < 0.0) w += 360.0;
    return w >= 360.0 ? 0.0 : w;
}

Eigen::Quaterniond restOrientation()
{
    // Every default ArmState starts here, several per control step: the sines and cosines are
    // taken once (at the first ArmState, built long before any real-time thread runs).
    static const Eigen::Quaterniond rest = poseToQuaternion({});
    return rest;
}

Eigen::Quaterniond poseToQuaternion(const Pose& p)
{
    return aboutAxis(90.0 - p.azimuthDeg, Eigen::Vector3d::UnitY())
         * aboutAxis(p.elevationDeg, Eigen::Vector3d::UnitZ())
         * aboutAxis(p.rollDeg, Eigen::Vector3d::UnitX());
}

Pose quaternionToPose(const Eigen::Quaterniond& qIn)
{
    const Eigen::Quaterniond q = qIn.normalized();
    const Eigen::Vector3d axis = q * Eigen::Vector3d::UnitX();
    Pose p;
    p.elevationDeg = radToDeg(std::asin(std::clamp(axis.y(), -1.0, 1.0)));
    const double horizontal = std::hypot(axis.x(), axis.z());
    p.azimuthDeg = horizontal > 1e-9 ? wrapDeg360(radToDeg(std::atan2(axis.x(), -axis.z()))) : 0.0;
    // What is left after heading and elevation is a pure turn about device x: the roll.
    const Eigen::Quaterniond headingElevation =
        aboutAxis(90.0 - p.azimuthDeg, Eigen::Vector3d::UnitY()) * aboutAxis(p.elevationDeg, Eigen::Vector3d::UnitZ());
    const Eigen::Quaterniond r = headingElevation.conjugate() * q;
    p.rollDeg = wrapDeg180(radToDeg(2.0 * std::atan2(r.x(), r.w())));
    return p;
}

} // namespace armadillo::core
