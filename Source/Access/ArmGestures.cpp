#include "Access/ArmGestures.h"
#include <cmath>

namespace armadillo::access {

ArmGesture TwistDetector::update(double t, double w) noexcept
{
    ArmGesture out = ArmGesture::None;
    if (pending_ && t - pendingAt_ > p_.pairWindow) {
        pending_ = false;
        out = ArmGesture::Repeat;
    }
    if (!std::isfinite(w)) return out;
    const double a = std::abs(w);
    if (!armed_) {
        if (a < 0.5 * p_.rate) armed_ = true;
        return out;
    }
    if (sign_ != 0 && t - firstAt_ > p_.maxTurn) {   // it did not come back in time: no gesture,
        sign_ = 0;                                    // and none until the arm is calm again
        armed_ = false;
        return out;
    }
    if (a <= p_.rate) return out;
    const int s = w > 0.0 ? 1 : -1;
    if (sign_ == 0) {
        sign_ = s;
        firstAt_ = t;
        return out;
    }
    if (s == sign_) return out;   // still the first half
    // The way back: one twist.
    sign_ = 0;
    armed_ = false;
    if (pending_) {
        pending_ = false;
        return ArmGesture::Skip;
    }
    pending_ = true;
    pendingAt_ = t;
    return out;
}

} // namespace armadillo::access
