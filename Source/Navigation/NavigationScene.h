#pragma once
// The navigation scene (issue 34, thesis §4.1 and §5.3): guides a walker along a route by touch
// alone. Between waypoints the §4.1 compass (the `compass` scene itself, run inside this one)
// points the thumb toward the next waypoint — one motor on the side to turn toward, clicking
// faster as the heading nears it, a steady touch on both sides when on course. Arriving within
// the radius plays the arrival sensation, then the waypoint's name in Arm Braille (its §5.3 sign
// shorthand when it has one, the rows method) framed as the adaptive training frames a cell (the
// "next" sweep before, the "your turn" double tap after), then guidance turns to the next one.
// Off route, fix lost and the route's end have their own sensations (docs/NAVIGATION.md).
//
// Everything is a motor intent on the MotorCanvas, so the TactileEngine shapes it and its
// SafetyStage has the last word. The scene is made by a front end with its route and a
// NavigationLink (not by name from the scene registry: it cannot run without a route and a
// position source, so it is not one of the plugin's scene choices); Engine(config, scene) runs it.
//
// Threads: control() is real-time (no allocation, lock, I/O or exception). Positions come in
// through the link's PositionMailbox (a source's own thread stores, control() reads); the status
// for a display (the app's Navigation view, the CLI) leaves through a SeqLock snapshot and the
// per-update log through an SPSC queue.
#include "Core/Scene.h"
#include "Core/SpscQueue.h"
#include "Navigation/Guidance.h"
#include "Navigation/HeadingLearner.h"
#include "Navigation/Position.h"
#include "Navigation/Route.h"
#include <atomic>
#include <limits>
#include <memory>

namespace armadillo::navigation {

/// What is being felt (log column `sensation`).
enum class Sensation : std::uint8_t { None, Compass, Arrival, OffRoute, FixLost, End };
const char* sensationName(Sensation s) noexcept;   ///< "none", "compass", "arrival", "off-route", "fix-lost", "end"

/// The snapshot a display polls (any thread, SeqLock): plain data only.
struct NavigationStatus {
    double t = 0.0;                 ///< s since the scene started
    int waypoint = 0;               ///< 1-based index into the route of the point guided to; count + 1 once finished
    int waypointCount = 0;          ///< points in the route (the start included)
    char name[kMaxWaypointName + 1] {};   ///< the waypoint's name ("" when it has none)
    char shown[kMaxWaypointName + 1] {};  ///< what the arm spells for it (its shorthand), "" = nothing
    double distanceM = std::numeric_limits<double>::quiet_NaN();   ///< to the waypoint, m
    double bearingDeg = std::numeric_limits<double>::quiet_NaN();  ///< to the waypoint, clockwise from true north
    double headingDeg = std::numeric_limits<double>::quiet_NaN();  ///< the corrected heading the compass uses
    double offsetDeg = 0.0;         ///< the learned thumb − walking-direction offset
    bool headingLearned = false;
    FixState fix = FixState::Waiting;
    double lat = std::numeric_limits<double>::quiet_NaN(), lon = std::numeric_limits<double>::quiet_NaN();   ///< last usable fix
    double accuracyM = std::numeric_limits<double>::quiet_NaN();
    bool offRoute = false;
    bool finished = false;
    int arrivals = 0;               ///< waypoints reached so far
    Sensation sensation = Sensation::None;
    bool magDisturbed = false;      ///< the fusion refuses the magnetometer: heading on the gyro, learning paused
};

/// One row of the navigation log, per control update.
struct NavigationLogRecord {
    double t = 0.0, lat = 0.0, lon = 0.0;
    FixState fix = FixState::Waiting;
    int waypoint = 0;
    double distanceM = 0.0, bearingDeg = 0.0, headingDeg = 0.0, armHeadingDeg = 0.0, offsetDeg = 0.0, legDistanceM = 0.0;
    bool offRoute = false;
    int arrivedAt = 0;
    Sensation sensation = Sensation::None;
    bool magDisturbed = false;
};

/// Shared between the front end, the position source and the scene.
struct NavigationLink {
    PositionMailbox position;
    core::SeqLock<NavigationStatus> status;
    core::SpscQueue<NavigationLogRecord, 8192> log; ///< drained by the front end (a full queue drops rows, counted)
    std::atomic<std::uint64_t> droppedLog {0};
    std::atomic<bool> logEnabled {false};
};

enum class NameDisplay : std::uint8_t { Shorthand, Full, None };

struct NavigationOptions {
    GuidanceParams guidance {};
    HeadingLearnerParams heading {};
    bool learnHeading = true;        ///< false: the fixed offset below only
    double headingOffsetDeg = 0.0;   ///< a known strap offset (used until the learning has enough samples)
    NameDisplay names = NameDisplay::Shorthand;
    float level = 5.0f;              ///< peak level of the sensations, 0..15 (the safety stage still decides)
    /// The sign words whose §5.3 shorthand is shown (empty: the shipped Braille/signwords.txt).
    std::vector<std::string> signWords;
};

/// The thumb's heading (deg clockwise from north; NaN when invalid or the thumb points up or
/// down) exactly as the compass scene reads it (Instruments/CompassScene.cpp), and the forearm's
/// elevation (deg).
double thumbHeadingDeg(const core::ArmState& arm, core::ArmSide side) noexcept;
double forearmElevationDeg(const core::ArmState& arm) noexcept;

/// What the arm spells for a waypoint name: the sign shorthand of a sign word ("entrance" → "en"),
/// else the name in lower case; "" for no name. Not real-time.
std::string shownName(const std::string& name, NameDisplay mode, const std::vector<std::pair<std::string, std::string>>& shorthand);

/// A navigation scene for `route` (at least 2 points), fed by `link`. Not real-time.
std::unique_ptr<core::Scene> makeNavigationScene(const Route& route, std::shared_ptr<NavigationLink> link, const NavigationOptions& options = {});

} // namespace armadillo::navigation
