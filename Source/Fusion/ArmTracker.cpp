#include "Fusion/ArmTracker.h"
#include "Fusion/ArmFeatures.h"
#include "Fusion/OrientationFilter.h"
#include <cmath>

namespace armadillo::fusion {

ArmTracker::ArmTracker() : filter_(std::make_unique<OrientationFilter>()) {}
ArmTracker::~ArmTracker() = default;

void ArmTracker::reset()
{
    filter_->reset();
    state_ = core::ArmState {};
    haveOrientation_ = false;
}

core::ArmState ArmTracker::update(const core::ImuSample& sample)
{
    filter_->update(sample);
    state_.t = sample.t;
    if (!filter_->initialised()) {
        state_.valid = false;
        return state_;
    }
    state_.q = filter_->orientation();
    state_.gyro = filter_->angularVelocity();
    state_.accel = sample.accel;
    state_.features = computeArmFeatures(state_.q, state_.gyro, state_.accel);
    state_.magDisturbedS = filter_->magneticDisturbedTime();
    state_.valid = true;
    return state_;
}

core::ArmState ArmTracker::updateOrientation(double t, const Eigen::Quaterniond& qIn)
{
    Eigen::Quaterniond q = qIn.normalized();
    if (haveOrientation_ && q.dot(state_.q) < 0.0) q.coeffs() = -q.coeffs();   // same hemisphere
    Eigen::Vector3d omega = Eigen::Vector3d::Zero();
    if (haveOrientation_ && t > state_.t) {
        // Body-frame rotation between the two orientations, as a rotation vector over dt.
        const Eigen::AngleAxisd delta(state_.q.conjugate() * q);
        double angle = delta.angle();
        if (angle > core::kPi) angle -= 2.0 * core::kPi;
        omega = delta.axis() * (angle / (t - state_.t));
    } else if (haveOrientation_) {
        omega = state_.gyro;   // same timestamp: keep the last rate
    }
    state_.t = t;
    state_.q = q;
    state_.gyro = omega;
    // A self-fused source gives no accelerometer: gravity alone (specific force, +g up).
    state_.accel = q.conjugate() * Eigen::Vector3d(0.0, core::kStandardGravity, 0.0);
    state_.features = computeArmFeatures(q, omega, state_.accel);
    state_.valid = true;
    haveOrientation_ = true;
    return state_;
}

} // namespace armadillo::fusion
