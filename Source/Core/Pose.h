#pragma once
// Pose = (elevation, azimuth, roll) in degrees and its quaternion, exactly as INTERFACES.md
// defines them: q = qY(90° − azimuth) · qz(elevation) · qx(roll), q maps device → earth
// (earth: X east, Y up, Z south). The one conversion every module uses.
#include <Eigen/Geometry>
#include <cmath>

namespace armadillo::core {

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
/// A quaternion that comes from outside (a motion file, `/armadillo/orientation`) stands for a
/// rotation only when its length is within 10 % of 1: float rounding and files written with three
/// decimals stay far inside, while a length of 1e-300 or 1e200 is a broken writer, not a direction
/// to normalise (0.5.0; the OSC dialects already used this bound). Computed as a plain sum of
/// squares, so lengths that overflow or underflow fail the test too.
constexpr double kRotationLengthTolerance = 0.1;
inline bool isRotationLength(double w, double x, double y, double z)
{
    const double n = std::sqrt(w * w + x * x + y * y + z * z);
    return std::abs(n - 1.0) <= kRotationLengthTolerance;   // false for NaN
}

/// Wraps an angle in degrees to [-180, 180).
double wrapDeg180(double deg);
/// Wraps an angle in degrees to [0, 360).
double wrapDeg360(double deg);

} // namespace armadillo::core
