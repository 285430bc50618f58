#include "Braille/ArmPush.h"
#include <algorithm>
#include <cmath>

namespace armadillo::braille {

bool PushDetector::update(double t, double a, double rate) noexcept
{
    if (!std::isfinite(t) || !std::isfinite(a) || !std::isfinite(rate)) return false;
    if (!primed_) {
        primed_ = true;
        baseline_ = a;
        lastT_ = t;
        return false;
    }
    const double dt = std::clamp(t - lastT_, 0.0, 0.1);
    lastT_ = t;
    const double e = a - baseline_;
    const bool turning = std::abs(rate) > p_.maxRate;
    if (sign_ != 0) {
        // The baseline holds still during a push: it is the gravity the push departs from.
        if (turning || t - firstAt_ > p_.maxPush) {   // a swing, or no stop in time: no push
            sign_ = 0;
            armed_ = false;
            return false;
        }
        if (e * sign_ < -p_.accel) {   // the stop: the other way
            sign_ = 0;
            armed_ = false;
            if (t - firstAt_ < p_.minPush) return false;   // too soon: a tap
            firedAt_ = t;
            return true;
        }
        return false;
    }
    baseline_ += std::min(1.0, dt / p_.baselineTau) * (a - baseline_);
    if (!armed_) {
        if (!turning && std::abs(a - baseline_) < 0.5 * p_.accel && t - firedAt_ >= p_.refractory) armed_ = true;
        return false;
    }
    if (turning || std::abs(e) <= p_.accel) return false;
    sign_ = e > 0.0 ? 1 : -1;
    firstAt_ = t;
    return false;
}

} // namespace armadillo::braille
