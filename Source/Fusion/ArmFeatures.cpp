#include "Fusion/ArmFeatures.h"
#include "Fusion/Quaternion.h"
#include <algorithm>
#include <cmath>

namespace armadillo::fusion {

core::ArmFeatures computeArmFeatures(const Eigen::Quaterniond& qIn, const Eigen::Vector3d& gyro,
                               const Eigen::Vector3d& accel)
{
    core::ArmFeatures f;
    const Eigen::Quaterniond q = quat::normalised(qIn);
    f.axis = quat::rotate(q, Eigen::Vector3d::UnitX());
    f.normal = quat::rotate(q, Eigen::Vector3d::UnitY());
    f.edge = quat::rotate(q, Eigen::Vector3d::UnitZ());
    f.pose = core::quaternionToPose(q);
    if (!gyro.allFinite()) return f;
    // N·ω with both in the earth frame equals the device-frame component: the rotation cancels.
    const Eigen::Vector3d omegaEarth = quat::rotate(q, gyro);
    f.fluxFace = f.normal.dot(omegaEarth);
    f.fluxEdge = f.edge.dot(omegaEarth);
    const double flux = std::hypot(f.fluxFace, f.fluxEdge);
    f.rollTrigger = f.axis.dot(omegaEarth) / std::max(flux, kRollTriggerFluxFloor);
    if (accel.allFinite() && omegaEarth.norm() < kPunchMaxRate) {
        // e = a − q⁻¹ g q with g the specific force of gravity (+g up), along the forearm axis.
        const Eigen::Vector3d e = accel - quat::rotateInverse(q, Eigen::Vector3d(0.0, core::kStandardGravity, 0.0));
        f.punch = e.x();
    }
    return f;
}

FluxSide leadingSide(const core::ArmFeatures& f, core::ArmSide arm, double minRate)
{
    const double alongY = f.fluxEdge;    // hand velocity along device +y (board face / back)
    const double alongZ = -f.fluxFace;   // hand velocity along device +z
    if (std::max(std::abs(alongY), std::abs(alongZ)) < minRate) return FluxSide::None;
    if (std::abs(alongY) >= std::abs(alongZ)) return alongY > 0.0 ? FluxSide::Back : FluxSide::Palm;
    // Right arm, palm down, forearm north: device z points east, the thumb west (−z).
    const bool towardThumb = (arm == core::ArmSide::Right) ? alongZ < 0.0 : alongZ > 0.0;
    return towardThumb ? FluxSide::Thumb : FluxSide::FifthFinger;
}

} // namespace armadillo::fusion
