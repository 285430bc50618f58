#pragma once
// Turns whatever a source gives (IMU samples, orientations, poses) into ArmState for the scenes:
// the SR-UKF for IMU streams, features of thesis §2.6.3 for all. Control thread only.
#include "Core/ArmState.h"
#include "Core/Types.h"
#include <memory>

namespace armadillo::fusion {

class OrientationFilter;

class ArmTracker {
public:
    ArmTracker();
    ~ArmTracker();
    /// IMU stream (calibrated SI values): fusion, then features.
    core::ArmState update(const core::ImuSample& sample);
    /// Sources that fuse themselves (OSC /armadillo/orientation, quaternion or pose files, host
    /// automation): angular velocity is derived from successive orientations.
    core::ArmState updateOrientation(double t, const Eigen::Quaterniond& q);
    void reset();
    const core::ArmState& state() const noexcept { return state_; }

private:
    std::unique_ptr<OrientationFilter> filter_;
    core::ArmState state_ {};
    bool haveOrientation_ = false;
};

} // namespace armadillo::fusion
