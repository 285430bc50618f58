#pragma once
// The navigation state machine of §5.3 (issue 34): from position reports and the corrected
// heading, which waypoint is next, how far and in which direction it lies, whether the walker
// has arrived, left the route or lost the fix, and when the route is over. It decides; the
// navigation scene (NavigationScene.h) turns its decisions into sensations.
//
// Real-time: step() runs in every control step (no allocation, lock, I/O or exception); the
// route is copied in at construction.
#include "Navigation/Position.h"
#include "Navigation/Route.h"
#include <cstdint>
#include <vector>

namespace armadillo::navigation {

struct GuidanceParams {
    double arrivalRadiusM = 8.0;     ///< arrived within this distance of the waypoint, m
    double offRouteM = 20.0;         ///< further than this from the leg = off route, m
    double backOnRouteM = 15.0;      ///< back on route below this (hysteresis), m
    double offRouteRepeatS = 10.0;   ///< the off-route sensation again after this while still off, s
    double fixTimeoutS = 3.0;        ///< no position report for this long = fix lost, s
    double maxAccuracyM = 50.0;      ///< a fix whose accuracy is worse than this counts as lost, m
    double maxSpeedMps = 12.0;       ///< a jump faster than this from the last fix is garbage (refused), m/s
    int acceptAfterJumps = 3;        ///< … unless this many jumps in a row agree: the receiver re-acquired elsewhere
};
inline constexpr GuidanceParams kDefaultGuidanceParams {};

enum class FixState : std::uint8_t { Waiting, Ok, Lost };   ///< no report yet / usable / lost or unusable
const char* fixStateName(FixState s) noexcept;               ///< "waiting", "ok", "lost"

/// What a step decided. Distances and bearings are to the waypoint being guided to (NaN without
/// a fix).
struct GuidanceStep {
    FixState fix = FixState::Waiting;
    int waypoint = 1;            ///< 1-based index into Route::points of the point guided to (2…N); N+1 once finished
    double distanceM = 0.0;
    double bearingDeg = 0.0;
    double legDistanceM = 0.0;   ///< from the current leg
    bool offRoute = false;
    bool finished = false;
    /// Events of this step (at most one each):
    int arrivedAt = 0;           ///< 1-based index of the waypoint just reached (0 = none)
    bool offRouteCue = false;    ///< play the off-route sensation now
    bool fixLostNow = false;     ///< the fix was just lost
    bool newFix = false;         ///< a new usable fix arrived in this step
    bool rejectedFix = false;    ///< a report was refused as garbage (a jump, a bad value)
};

class Guidance {
public:
    Guidance(const Route& route, const GuidanceParams& params = kDefaultGuidanceParams);
    /// dt in s; the latest report of the position source (the same report may come again).
    GuidanceStep step(double dt, const PositionFix& latest) noexcept;
    void reset() noexcept;

    const Route& route() const noexcept { return route_; }
    const GuidanceParams& params() const noexcept { return p_; }
    /// The last usable fix (valid once step().fix has been Ok).
    const PositionFix& lastFix() const noexcept { return last_; }
    int waypoint() const noexcept { return next_ + 1; }
    bool finished() const noexcept { return next_ >= static_cast<int>(route_.points.size()); }

private:
    bool usable(const PositionFix& f) const noexcept;
    Route route_;
    GuidanceParams p_;
    double t_ = 0.0, lastReportT_ = -1.0, lastFixT_ = -1.0, offCueT_ = -1e9;
    std::uint64_t serial_ = 0;
    PositionFix last_ {};
    bool haveFix_ = false, offRoute_ = false;
    FixState state_ = FixState::Waiting;
    int next_ = 1;      // index (0-based) of the point guided to
    int jumps_ = 0;
};

} // namespace armadillo::navigation
