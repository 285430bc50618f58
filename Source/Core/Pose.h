#pragma once
// Pose = (elevation, azimuth, roll) in degrees and its quaternion, exactly as INTERFACES.md
// defines them: q = qY(90° − azimuth) · qz(elevation) · qx(roll), q maps device → earth
// (earth: X east, Y up, Z south). The one conversion every module uses.
#include <Eigen/Geometry>

namespace armadillo {

struct Pose {
    double elevationDeg = 0.0;   ///< forearm axis above horizontal, −90…90 (+ up)
    double azimuthDeg = 0.0;     ///< heading of the forearm axis, clockwise from north, 0…360
    double rollDeg = 0.0;        ///< about the forearm axis, clockwise looking elbow→hand, −180…180
};

/// Rest: forearm pointing north, level, board face up: q = (cos 45°, 0, sin 45°, 0).
Eigen::Quaterniond restOrientation();
Eigen::Quaterniond poseToQuaternion(const Pose& pose);
/// Inverse of poseToQuaternion; at ±90° elevation azimuth is taken as 0 and the turn goes to roll.
Pose quaternionToPose(const Eigen::Quaterniond& q);
/// Wraps an angle in degrees to [-180, 180).
double wrapDeg180(double deg);
/// Wraps an angle in degrees to [0, 360).
double wrapDeg360(double deg);

} // namespace armadillo
