#include "Link/SteerableArm.h"
#include "Core/Types.h"
#include <algorithm>
#include <cmath>

namespace armadillo::link {

void SteerableArm::steerTo(const core::Pose& target) noexcept
{
    wandering_ = false;
    motion_.reset();
    target_.elevationDeg = std::clamp(target.elevationDeg, -90.0, 90.0);
    target_.azimuthDeg = core::wrapDeg360(target.azimuthDeg);
    target_.rollDeg = core::wrapDeg180(target.rollDeg);
}

void SteerableArm::follow(std::shared_ptr<const MotionSource> motion) noexcept
{
    motion_ = std::move(motion);
    motionStart_ = t_;
    wandering_ = true;   // (without a motion: the wandering path again)
}

Eigen::Quaterniond SteerableArm::advance(double dt)
{
    dt = std::clamp(dt, 0.0, 0.1);
    t_ += dt;
    if (motion_) {
        const Eigen::Quaterniond q = motion_->at(t_ - motionStart_).q;
        current_ = core::quaternionToPose(q);
        return q;
    }
    if (wandering_) {
        Eigen::Quaterniond q = path_.at(t_).q;
        const double phase = std::fmod(t_, kFlickEvery);
        if (phase < kFlickLength)   // roll is a turn about the forearm (device x)
            q = q * Eigen::Quaterniond(Eigen::AngleAxisd(core::kPi / 4.0 * std::sin(core::kPi * phase / kFlickLength), Eigen::Vector3d::UnitX()));
        current_ = core::quaternionToPose(q);
        return q;
    }
    // Ease toward the steered pose so steering by keyboard is not a step.
    const double k = 1.0 - std::exp(-dt / 0.08);
    current_.elevationDeg += k * (target_.elevationDeg - current_.elevationDeg);
    current_.azimuthDeg = core::wrapDeg360(current_.azimuthDeg + k * core::wrapDeg180(target_.azimuthDeg - current_.azimuthDeg));
    current_.rollDeg = core::wrapDeg180(current_.rollDeg + k * core::wrapDeg180(target_.rollDeg - current_.rollDeg));
    return poseToQuaternion(current_);
}

} // namespace armadillo::link
