#include "Navigation/HeadingLearner.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace armadillo::navigation {
namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
} // namespace

void HeadingLearner::Sum::add(double rad) noexcept
{
    s += std::sin(rad);
    c += std::cos(rad);
    ++n;
}

void HeadingLearner::reset() noexcept
{
    *this = HeadingLearner(p_);
}

void HeadingLearner::arm(double t, double headingDeg, double elevationDeg) noexcept
{
    if (!std::isfinite(headingDeg) || !std::isfinite(elevationDeg)) return;
    cycle_.add(headingDeg * kDeg);
    // Peaks and troughs with swingMinDeg of hysteresis, so tremor makes none.
    if (!primed_) {   // start by looking for a trough
        runMax_ = runMin_ = elevationDeg;
        rising_ = false;
        primed_ = true;
        return;
    }
    if (rising_) {   // after a trough: the highest point, confirmed once the signal falls swingMinDeg below it
        runMax_ = std::max(runMax_, elevationDeg);
        if (runMax_ - elevationDeg >= p_.swingMinDeg) {
            if (lastPeakT_ >= 0.0) swingPeriod_ = t - lastPeakT_;
            lastPeakT_ = t;
            complete_.add(cycle_);
            cycle_ = {};
            rising_ = false;
            runMin_ = elevationDeg;
        }
    } else {   // after a peak: the lowest point, confirmed once the signal rises swingMinDeg above it
        runMin_ = std::min(runMin_, elevationDeg);
        if (elevationDeg - runMin_ >= p_.swingMinDeg) {
            rising_ = true;
            runMax_ = elevationDeg;
        }
    }
}

void HeadingLearner::learn(const Sum& arm, double walkingDeg) noexcept
{
    if (arm.n < 2) return;
    const double r = std::hypot(arm.s, arm.c) / arm.n;   // resultant length: 1 = no spread
    const double spreadDeg = r >= 1.0 ? 0.0 : std::sqrt(-2.0 * std::log(std::max(r, 1e-12))) / kDeg;   // circular std
    if (spreadDeg > p_.steadyArmDeg) return;   // turning: the arm and the path do not belong together
    const double armDeg = std::atan2(arm.s, arm.c) / kDeg;
    const double d = wrap180(armDeg - walkingDeg) * kDeg;
    walking_ = wrap360(walkingDeg);
    ++samples_;
    // A running mean for the first samples, then exponential forgetting.
    const double w = std::max(1.0 / samples_, p_.forget);
    offS_ = (1.0 - w) * offS_ + w * std::sin(d);
    offC_ = (1.0 - w) * offC_ + w * std::cos(d);
    offset_ = wrap180(std::atan2(offS_, offC_) / kDeg);
}

void HeadingLearner::fix(double t, double x, double y, double courseDeg, double speedMps) noexcept
{
    // The arm's heading since the previous fix: whole swing cycles when the arm swings (so the
    // swing's yaw cancels), everything when it does not.
    const bool swinging = lastPeakT_ >= 0.0 && t - lastPeakT_ <= p_.swingMaxPeriodS;
    if (!swinging && swingPeriod_ > 0.0 && t - lastPeakT_ > p_.swingMaxPeriodS) swingPeriod_ = 0.0;
    Sum interval = complete_;
    if (!swinging || interval.n == 0) interval.add(cycle_), cycle_ = {};
    complete_ = {};

    FixRow& row = ring_[static_cast<std::size_t>(fitHead_)];
    row = {t, x, y, interval};
    fitHead_ = (fitHead_ + 1) % kRing;
    fitCount_ = std::min(fitCount_ + 1, kRing);

    if (std::isfinite(courseDeg) && std::isfinite(speedMps)) {
        if (speedMps >= p_.minSpeedMps) learn(interval, courseDeg);
        return;
    }
    // No course from the source: a straight line through the last fitFixes fixes.
    const int n = std::clamp(p_.fitFixes, 3, kRing);
    if (fitCount_ < n) return;
    double mx = 0.0, my = 0.0;
    Sum armWindow {};
    for (int i = 0; i < n; ++i) {
        const FixRow& r = ring_[static_cast<std::size_t>((fitHead_ - 1 - i + kRing) % kRing)];
        mx += r.x;
        my += r.y;
        if (i < n - 1) armWindow.add(r.arm);   // the intervals between the first and the last fix
    }
    mx /= n;
    my /= n;
    double sxx = 0.0, syy = 0.0, sxy = 0.0;
    for (int i = 0; i < n; ++i) {
        const FixRow& r = ring_[static_cast<std::size_t>((fitHead_ - 1 - i + kRing) % kRing)];
        sxx += (r.x - mx) * (r.x - mx);
        syy += (r.y - my) * (r.y - my);
        sxy += (r.x - mx) * (r.y - my);
    }
    // The principal axis of the points (total least squares: east and north are alike).
    const double angle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
    const double ux = std::cos(angle), uy = std::sin(angle);
    double lo = 0.0, hi = 0.0, resid = 0.0;
    for (int i = 0; i < n; ++i) {
        const FixRow& r = ring_[static_cast<std::size_t>((fitHead_ - 1 - i + kRing) % kRing)];
        const double along = (r.x - mx) * ux + (r.y - my) * uy;
        const double across = -(r.x - mx) * uy + (r.y - my) * ux;
        lo = std::min(lo, along);
        hi = std::max(hi, along);
        resid += across * across;
    }
    resid = std::sqrt(resid / n);
    if (hi - lo < p_.minFitSpanM || resid > p_.maxFitResidualM) return;
    const FixRow& newest = ring_[static_cast<std::size_t>((fitHead_ - 1 + kRing) % kRing)];
    const FixRow& oldest = ring_[static_cast<std::size_t>((fitHead_ - n + kRing) % kRing)];
    const double duration = newest.t - oldest.t;
    if (duration <= 0.0 || (hi - lo) / duration < p_.minSpeedMps) return;
    // Direction along the axis, pointing from the oldest fix toward the newest.
    double dx = ux, dy = uy;
    if ((newest.x - oldest.x) * ux + (newest.y - oldest.y) * uy < 0.0) dx = -dx, dy = -dy;
    learn(armWindow, std::atan2(dx, dy) / kDeg);   // bearing: clockwise from north (y)
}

} // namespace armadillo::navigation
