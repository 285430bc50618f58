#pragma once
// A walk rehearsed offline (issue 34's "Done when", `armadillo navigate --simulate-walk`, the
// figures of docs/NAVIGATION.md): the navigation scene in an Engine (tactile shaping and safety
// stage) guiding a simulated blind walker (Navigation/WalkerSim.h) who feels only the levels that
// left the safety stage, the walker's GPS feeding the scene's link, on a simulated clock.
// Deterministic for a seed. A front end describes the walker (WalkerParams) and the route, and
// reads the result; the walker itself is built here.
#include "Core/Types.h"
#include "Navigation/NavigationScene.h"
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace armadillo::navigation {

struct WalkerParams {
    double speedMps = 1.3;           ///< walking speed, m/s
    double reactionS = 0.25;         ///< from feeling a cue to acting on it, s
    double baseTurnDegS = 10.0;      ///< turn rate at the slowest clicks, deg/s
    double turnPerHzDegS = 1.6;      ///< extra turn rate per Hz of click rate, deg/s/Hz
    double maxTurnDegS = 45.0;
    double strapOffsetDeg = 20.0;    ///< the thumb points this much clockwise of the walking direction
    double tremorDeg = 1.5;          ///< hand tremor on the thumb's heading (std), deg
    double swingElevationDeg = 12.0; ///< arm swing amplitude in elevation, deg
    double swingYawDeg = 4.0;        ///< arm swing amplitude in heading, deg
    double swingHz = 0.9;            ///< one swing per two steps, Hz
    double gpsRateHz = 1.0;
    double gpsBiasM = 4.0;           ///< std of the slowly wandering error per axis, m
    double gpsBiasTauS = 60.0;       ///< its correlation time, s
    double gpsWhiteM = 1.0;          ///< white noise per fix per axis (std), m
    bool gpsCourse = true;           ///< the receiver reports course and speed (Doppler), else NaN
    double gpsCourseNoiseDeg = 6.0;  ///< std of that course at walking speed, deg
    /// A magnetic disturbance (steel, a parked car) from fromS to toS s of the walk: the thumb
    /// heading is bent by biasDeg; `flagged` says whether the fusion reports it (ArmState::magDisturbedS).
    struct Disturbance {
        double fromS = -1.0, toS = -1.0, biasDeg = 0.0;
        bool flagged = true;
    } disturbance {};
    std::uint64_t seed = 1;
};
/// What an observer of the rehearsal sees of the walker after each step.
struct WalkerView {
    LatLon position {};
    double bodyHeadingDeg = 0.0;
    bool reading = false;        ///< reading a waypoint's name on the arm
};

/// The whole loop (tests, `navigate --simulate-walk`, the docs' figures): the scene in an Engine
/// (tactile shaping and safety stage), the walker feeling its levels, the walker's GPS feeding
/// the link, at `controlHz` until the route is finished or `maxSeconds` pass.
struct WalkResult {
    bool finished = false;
    double seconds = 0.0;
    std::vector<int> arrivals;          ///< waypoint indices (1-based) in the order reached
    double maxOffRouteM = 0.0;          ///< the true position's largest distance from the route's legs (after the start), m
    double medianHeadingErrorDeg = 0.0; ///< |walking direction − the bearing the compass shows| while guided, after settling
    double p90HeadingErrorDeg = 0.0;
    double learnedOffsetDeg = 0.0;      ///< the scene's offset at the end
    std::uint64_t steps = 0;
};
struct WalkOptions {
    double controlHz = 100.0;
    double maxSeconds = 3600.0;
    double settleS = 12.0;              ///< after each arrival (and the start) errors are not counted for this long, s
    double startHeadingDeg = 0.0;       ///< the walker's first body heading
    /// Called after every control step (t, where the walker is, the levels sent, the scene's status): logs.
    std::function<void(double, const WalkerView&, const core::MotorLevels&, const NavigationStatus&)> observe;
};
WalkResult simulateWalk(const Route& route, const NavigationOptions& nav, const WalkerParams& walker, const WalkOptions& options,
                        std::shared_ptr<NavigationLink> link = nullptr);

/// The result as `navigate --simulate-walk` prints it: {"finished":…,"seconds":…,"arrivals":…,
/// "waypoints":…,"max_off_route_m":…,"median_heading_error_deg":…,"learned_offset_deg":…,
/// "strap_offset_deg":…} (docs/INTERFACES.md).
std::string walkResultJson(const WalkResult& result, const Route& route, const WalkerParams& walker);

} // namespace armadillo::navigation
