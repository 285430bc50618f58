#include "Plugin/WanderingMotion.h"
#include "Core/Types.h"
#include <algorithm>
#include <cmath>

namespace armadillo::plugin {

Pose WanderingMotion::wanderPose(double t) const
{
    // Incommensurate frequencies: the path never repeats exactly but stays smooth (< 1 rad/s).
    Pose p;
    p.elevationDeg = 30.0 * std::sin(0.23 * t) + 18.0 * std::sin(0.71 * t + 1.0);
    p.azimuthDeg = wrapDeg360(60.0 * std::sin(0.13 * t) + 25.0 * std::sin(0.47 * t + 0.3));
    p.rollDeg = 35.0 * std::sin(0.31 * t + 0.5);
    // A quick roll flick (±45° in 0.2 s) every 7 s: thesis §3.4 "select by a quick roll".
    const double phase = std::fmod(t, 7.0);
    if (phase < 0.4) p.rollDeg += 45.0 * std::sin(kPi * phase / 0.4);
    return p;
}

void WanderingMotion::steerTo(const Pose& target) noexcept
{
    wandering_ = false;
    target_.elevationDeg = std::clamp(target.elevationDeg, -90.0, 90.0);
    target_.azimuthDeg = wrapDeg360(target.azimuthDeg);
    target_.rollDeg = wrapDeg180(target.rollDeg);
}

Eigen::Quaterniond WanderingMotion::advance(double dt)
{
    dt = std::clamp(dt, 0.0, 0.1);
    t_ += dt;
    const Pose goal = wandering_ ? wanderPose(t_) : target_;
    // Ease toward the goal (time constant 80 ms) so steering by keyboard is not a step.
    const double k = wandering_ ? 1.0 : 1.0 - std::exp(-dt / 0.08);
    current_.elevationDeg += k * (goal.elevationDeg - current_.elevationDeg);
    current_.azimuthDeg = wrapDeg360(current_.azimuthDeg + k * wrapDeg180(goal.azimuthDeg - current_.azimuthDeg));
    current_.rollDeg = wrapDeg180(current_.rollDeg + k * wrapDeg180(goal.rollDeg - current_.rollDeg));
    return poseToQuaternion(current_);
}

} // namespace armadillo::plugin
