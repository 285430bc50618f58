#include "Navigation/Guidance.h"
#include <algorithm>
#include <cmath>
#include <limits>

namespace armadillo::navigation {

const char* fixStateName(FixState s) noexcept
{
    switch (s) {
    case FixState::Waiting: return "waiting";
    case FixState::Ok: return "ok";
    case FixState::Lost: return "lost";
    }
    return "?";
}

const char* fixQualityName(FixQuality q) noexcept
{
    switch (q) {
    case FixQuality::None: return "none";
    case FixQuality::Fix2D: return "2d";
    case FixQuality::Fix3D: return "3d";
    }
    return "?";
}

Guidance::Guidance(const Route& route, const GuidanceParams& params) : route_(route), p_(params) {}

void Guidance::reset() noexcept
{
    t_ = 0.0;
    lastReportT_ = lastFixT_ = -1.0;
    offCueT_ = -1e9;
    serial_ = 0;
    last_ = {};
    haveFix_ = offRoute_ = false;
    state_ = FixState::Waiting;
    next_ = 1;
    jumps_ = 0;
}

bool Guidance::usable(const PositionFix& f) const noexcept
{
    if (f.quality == FixQuality::None || !validLatLon(f.pos)) return false;
    if (std::isfinite(f.accuracyM) && f.accuracyM > p_.maxAccuracyM) return false;
    return true;
}

GuidanceStep Guidance::step(double dt, const PositionFix& latest) noexcept
{
    GuidanceStep s;
    if (std::isfinite(dt) && dt > 0.0) t_ += dt;
    const int n = static_cast<int>(route_.points.size());

    if (latest.serial != 0 && latest.serial != serial_) {   // a new report
        serial_ = latest.serial;
        lastReportT_ = t_;
        if (usable(latest)) {
            bool accept = true;
            if (haveFix_) {
                const double elapsed = std::max(t_ - lastFixT_, 0.2);
                const double allowed = p_.maxSpeedMps * elapsed + (std::isfinite(latest.accuracyM) ? 2.0 * latest.accuracyM : 20.0);
                if (distanceM(last_.pos, latest.pos) > allowed && ++jumps_ < p_.acceptAfterJumps) accept = false;
            }
            if (accept) {
                jumps_ = 0;
                last_ = latest;
                lastFixT_ = t_;
                haveFix_ = true;
                s.newFix = true;
            } else {
                s.rejectedFix = true;
            }
        } else if (validLatLon(latest.pos) || latest.quality == FixQuality::None) {
            // "No fix" from a living source: lost at once (said, not guessed from an old fix).
            if (haveFix_) lastFixT_ = -1e9;
        } else {
            s.rejectedFix = true;
        }
    }
    const bool fresh = haveFix_ && t_ - lastFixT_ <= p_.fixTimeoutS;
    const FixState previous = state_;
    state_ = fresh ? FixState::Ok : (haveFix_ || lastReportT_ >= 0.0 ? FixState::Lost : FixState::Waiting);
    if (state_ == FixState::Waiting && t_ > p_.fixTimeoutS) state_ = FixState::Lost;   // nothing at all yet: say so
    s.fix = state_;
    s.fixLostNow = state_ == FixState::Lost && previous != FixState::Lost;

    s.finished = finished();
    if (s.finished) {
        s.waypoint = n + 1;
        return s;
    }
    if (haveFix_) {
        const LatLon& here = last_.pos;
        if (state_ == FixState::Ok) {
            const double d = distanceM(here, route_.points[static_cast<std::size_t>(next_)].pos);
            if (d <= p_.arrivalRadiusM) {
                s.arrivedAt = next_ + 1;
                ++next_;
                offRoute_ = false;
                offCueT_ = -1e9;
                if (finished()) {
                    s.finished = true;
                    s.waypoint = n + 1;
                    s.distanceM = 0.0;
                    return s;
                }
            }
        }
        const Waypoint& from = route_.points[static_cast<std::size_t>(next_ - 1)];
        const Waypoint& to = route_.points[static_cast<std::size_t>(next_)];
        s.distanceM = distanceM(here, to.pos);
        s.bearingDeg = initialBearingDeg(here, to.pos);
        s.legDistanceM = legDistanceM(from.pos, to.pos, here);
        if (state_ == FixState::Ok) {
            if (!offRoute_ && s.legDistanceM > p_.offRouteM) offRoute_ = true, offCueT_ = -1e9;
            else if (offRoute_ && s.legDistanceM < p_.backOnRouteM) offRoute_ = false;
            if (offRoute_ && t_ - offCueT_ >= p_.offRouteRepeatS) {
                s.offRouteCue = true;
                offCueT_ = t_;
            }
        }
    } else {
        s.distanceM = s.bearingDeg = s.legDistanceM = std::numeric_limits<double>::quiet_NaN();
    }
    s.offRoute = offRoute_;
    s.waypoint = next_ + 1;
    return s;
}

} // namespace armadillo::navigation
