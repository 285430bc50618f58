#pragma once
// Positions on the Earth for walking navigation (issue 34, thesis §5.3). Everything here treats
// the Earth as a sphere of the WGS84 mean radius R1 = (2a + b)/3 = 6 371 008.8 m. Over a walking
// route (legs of metres to a few kilometres) the sphere differs from the WGS84 ellipsoid by at
// most about 0.5 % in distance and a few tenths of a degree in bearing — far below the 3–10 m of
// a consumer GPS fix and the ±5° the compass can show (docs/NAVIGATION.md "Limits"). Angles in
// degrees at the interface (latitude north +, longitude east +, bearings clockwise from true
// north, 0…360), radians inside; distances in metres. Pure functions, real-time safe.
namespace armadillo::navigation {

inline constexpr double kEarthRadiusM = 6371008.8;   ///< WGS84 mean radius R1, m

struct LatLon {
    double lat = 0.0;   ///< deg, −90…90
    double lon = 0.0;   ///< deg, −180…180
};

/// True when both are finite and in range (latitude −90…90, longitude −180…180).
bool validLatLon(const LatLon& p) noexcept;
/// Great-circle distance (haversine, stable for short distances), m.
double distanceM(const LatLon& a, const LatLon& b) noexcept;
/// Initial great-circle bearing from a toward b, deg clockwise from true north in [0, 360);
/// 0 when a and b coincide.
double initialBearingDeg(const LatLon& a, const LatLon& b) noexcept;
/// The point `distance` m from `from` along the great circle that starts at `bearingDeg`.
LatLon destination(const LatLon& from, double bearingDeg, double distanceM) noexcept;
/// Signed distance of p from the great circle through a and b, m: + = right of the direction of
/// travel a → b, − = left.
double crossTrackM(const LatLon& a, const LatLon& b, const LatLon& p) noexcept;
/// Distance travelled along a → b to the point of that circle nearest p, m (negative: behind a).
double alongTrackM(const LatLon& a, const LatLon& b, const LatLon& p) noexcept;
/// Distance from p to the leg (the segment a–b): the cross-track distance where p lies beside the
/// leg, the distance to the nearer end where it lies before a or past b. m, ≥ 0.
double legDistanceM(const LatLon& a, const LatLon& b, const LatLon& p) noexcept;

/// Angle helpers (deg): into [0, 360) and into (−180, 180].
double wrap360(double deg) noexcept;
double wrap180(double deg) noexcept;

/// A local east/north plane around an origin (equirectangular), for simulations and tests over a
/// few kilometres: x east, y north, m.
struct LocalPlane {
    LatLon origin {};
    void toXY(const LatLon& p, double& x, double& y) const noexcept;
    LatLon fromXY(double x, double y) const noexcept;
};

} // namespace armadillo::navigation
