#pragma once
// Turns whatever a source gives (IMU samples, orientations, poses) into ArmState for the scenes:
// the SR-UKF for IMU streams, features of thesis §2.6.3 for all. Control thread only.
#include "Core/ArmState.h"
#include "Core/Types.h"
#include <memory>

namespace armadillo {

class OrientationFilter;

class ArmTracker {
public:
    ArmTracker();
    ~ArmTracker();
    /// IMU stream (calibrated SI values): fusion, then features.
    ArmState update(const ImuSample& sample);
    /// Sources that fuse themselves (OSC /armadillo/orientation, quaternion or pose files, host
    /// automation): angular velocity is derived from successive orientations.
    ArmState updateOrientation(double t, const Eigen::Quaterniond& q);
    void reset();
    const ArmState& state() const noexcept { return state_; }

private:
    std::unique_ptr<OrientationFilter> filter_;
    ArmState state_ {};
    bool haveOrientation_ = false;
};

} // namespace armadillo
