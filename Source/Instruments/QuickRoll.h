#pragma once
// "Select by a quick roll" (thesis §3.4, §3.7): a fast turn about the forearm axis that
// dominates the other rotation (the roll trigger of §2.6.3), with hysteresis on the rate so one
// roll selects once.
#include "Tactile/Hysteresis.h"
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace armadillo::instruments {

struct QuickRollParams {
    double enterRate = 3.0;     ///< rad/s about the forearm axis that starts a roll
    double exitRate = 1.0;      ///< rad/s below which the roll has ended
    double dominance = 1.5;     ///< |ωx| / |ω across| needed (dialling sweeps do not select)
};

class QuickRoll {
public:
    /// ω in the device frame (rad/s); true once per roll, at its start. `direction` gets ±1.
    bool update(const Eigen::Vector3d& omegaDevice, const QuickRollParams& p, int* direction = nullptr) noexcept
    {
        rolling_.setThresholds(p.enterRate, p.exitRate);
        const double across = std::hypot(omegaDevice.y(), omegaDevice.z());
        const double rate = std::fabs(omegaDevice.x());
        const bool dominant = rate > p.dominance * std::max(across, 0.05);
        const bool was = rolling_.on();
        // Only a dominant roll may start one; any slow-down ends it.
        const bool now = rolling_.update(was || dominant ? rate : 0.0);
        if (now && !was) {
            if (direction) *direction = omegaDevice.x() >= 0.0 ? 1 : -1;
            return true;
        }
        return false;
    }
    void reset() noexcept { rolling_.reset(false); }

private:
    tactile::Hysteresis rolling_ {3.0, 1.0};
};

} // namespace armadillo::instruments
