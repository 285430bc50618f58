#pragma once
// A walking route: the start and the waypoints to walk to, in order (issue 34, thesis §5.3).
// Read from GPX 1.1 (pugixml) or from a JSON list of waypoints (Core/Json.h); errors are
// InputError naming the file and line, like every other input format (docs/NAVIGATION.md).
//
// The FIRST point of a route is its start: the walk begins there and it is never announced;
// guidance goes to point 2 first. `waypoint` in the navigation log is the 1-based index into
// Route::points of the point being guided to (2 … N).
#include "Navigation/Geodesy.h"
#include <string>
#include <string_view>
#include <vector>

namespace armadillo::navigation {

struct Waypoint {
    LatLon pos {};
    std::string name;   ///< may be empty (then only the arrival sensation is felt)
    long line = 0;      ///< where it was read (for messages), 0 = unknown
};

struct Route {
    std::string name;                 ///< the route's own name, "" when it has none
    std::string source;               ///< the file it came from (for messages)
    std::vector<Waypoint> points;     ///< points[0] = the start; at least 2
    /// Length of the legs together, m.
    double lengthM() const noexcept;
};

/// Points of a GPX track closer than this to the previous kept point are dropped (a recorded
/// track has a point every few metres; named points are always kept). m.
inline constexpr double kTrackThinningM = 15.0;
/// Two consecutive route points closer than this are refused (a leg of no length has no bearing). m.
inline constexpr double kMinLegM = 1.0;
/// The most points a route may have (a walk, not a survey): refused beyond it.
inline constexpr std::size_t kMaxRoutePoints = 10000;
/// The longest name kept for a waypoint (bytes of UTF-8); longer names are refused.
inline constexpr std::size_t kMaxWaypointName = 64;

/// GPX 1.0/1.1: the first <rte> that has <rtept>s, else the first <trk>'s <trkseg>s' <trkpt>s in
/// order (thinned: kTrackThinningM), else the <wpt>s in file order. lat/lon attributes required;
/// <name> per point optional.
Route parseGpx(std::string_view text, const std::string& source);
/// JSON: either an array of points or an object {"name": "…", "waypoints": [points]}; a point is
/// {"lat": deg, "lon": deg, "name": "…"} ("name" optional, no other members).
Route parseRouteJson(std::string_view text, const std::string& source);
/// By extension (.gpx, .json), else by the first non-blank character ('<' GPX, '[' or '{' JSON).
/// IoError when the file cannot be read, InputError for bad content.
Route readRouteFile(const std::string& path);

} // namespace armadillo::navigation
