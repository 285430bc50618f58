#pragma once
// Angular velocity for the scenes: the gyro when the source has one, otherwise the change of
// orientation between control updates (host automation and pose files carry no gyro).
#include "Core/ArmState.h"
#include <Eigen/Geometry>

namespace armadillo::instruments {

class ArmMotion {
public:
    /// ω in the device frame, rad/s. Call once per control update.
    Eigen::Vector3d update(const core::ArmState& arm, double dt) noexcept
    {
        const Eigen::Quaterniond q = arm.q.normalized();
        Eigen::Vector3d w = Eigen::Vector3d::Zero();
        if (arm.gyro.allFinite() && arm.gyro.squaredNorm() > 0.0) {
            w = arm.gyro;
        } else if (havePrevious_ && dt > 0.0) {
            Eigen::Quaterniond d = previous_.conjugate() * q;
            if (d.w() < 0.0) d.coeffs() = -d.coeffs();
            const Eigen::AngleAxisd aa(d);
            w = aa.axis() * (aa.angle() / dt);
        }
        previous_ = q;
        havePrevious_ = true;
        return w.allFinite() ? w : Eigen::Vector3d::Zero();
    }
    void reset() noexcept { havePrevious_ = false; }

private:
    Eigen::Quaterniond previous_ = Eigen::Quaterniond::Identity();
    bool havePrevious_ = false;
};

} // namespace armadillo::instruments
