#pragma once
// The built-in simulated forearm: a slow, smooth wander through the space the scenes use, with a
// quick roll flick every few seconds so gesture scenes have something to react to. The user can
// take the arm (mouse/keyboard in the arm view); it then eases to the requested pose and stays
// there until wandering is switched back on. Used until the device module's simulator lands.
#include "Core/Pose.h"
#include <Eigen/Geometry>

namespace armadillo::plugin {

class WanderingMotion {
public:
    /// Advances the simulated arm by dt s and returns its orientation (device → earth).
    Eigen::Quaterniond advance(double dt);

    /// The user steers: ease toward this pose and stop wandering.
    void steerTo(const Pose& target) noexcept;
    void setWandering(bool on) noexcept { wandering_ = on; }
    bool wandering() const noexcept { return wandering_; }
    Pose pose() const noexcept { return current_; }
    double time() const noexcept { return t_; }

private:
    Pose wanderPose(double t) const;
    double t_ = 0.0;            ///< s since start
    bool wandering_ = true;
    Pose target_ {};
    Pose current_ {20.0, 0.0, 0.0};
};

} // namespace armadillo::plugin
