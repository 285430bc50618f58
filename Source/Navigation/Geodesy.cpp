#include "Navigation/Geodesy.h"
#include <algorithm>
#include <cmath>
#include <numbers>

namespace armadillo::navigation {
namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
double clampUnit(double v) noexcept { return std::clamp(v, -1.0, 1.0); }
} // namespace

bool validLatLon(const LatLon& p) noexcept
{
    return std::isfinite(p.lat) && std::isfinite(p.lon) && p.lat >= -90.0 && p.lat <= 90.0 && p.lon >= -180.0 && p.lon <= 180.0;
}

double wrap360(double deg) noexcept
{
    double r = std::fmod(deg, 360.0);
    if (r < 0.0) r += 360.0;
    return r >= 360.0 ? 0.0 : r;
}

double wrap180(double deg) noexcept
{
    double r = wrap360(deg);
    return r > 180.0 ? r - 360.0 : r;
}

double distanceM(const LatLon& a, const LatLon& b) noexcept
{
    const double p1 = a.lat * kDeg, p2 = b.lat * kDeg;
    const double dp = (b.lat - a.lat) * kDeg, dl = (b.lon - a.lon) * kDeg;
    const double h = std::sin(dp / 2) * std::sin(dp / 2) + std::cos(p1) * std::cos(p2) * std::sin(dl / 2) * std::sin(dl / 2);
    return 2.0 * kEarthRadiusM * std::asin(std::sqrt(std::clamp(h, 0.0, 1.0)));
}

double initialBearingDeg(const LatLon& a, const LatLon& b) noexcept
{
    const double p1 = a.lat * kDeg, p2 = b.lat * kDeg, dl = (b.lon - a.lon) * kDeg;
    const double y = std::sin(dl) * std::cos(p2);
    const double x = std::cos(p1) * std::sin(p2) - std::sin(p1) * std::cos(p2) * std::cos(dl);
    if (y == 0.0 && x == 0.0) return 0.0;
    return wrap360(std::atan2(y, x) / kDeg);
}

LatLon destination(const LatLon& from, double bearingDeg, double dist) noexcept
{
    const double d = dist / kEarthRadiusM, th = bearingDeg * kDeg;
    const double p1 = from.lat * kDeg, l1 = from.lon * kDeg;
    const double p2 = std::asin(clampUnit(std::sin(p1) * std::cos(d) + std::cos(p1) * std::sin(d) * std::cos(th)));
    const double l2 = l1 + std::atan2(std::sin(th) * std::sin(d) * std::cos(p1), std::cos(d) - std::sin(p1) * std::sin(p2));
    return {p2 / kDeg, wrap180(l2 / kDeg)};
}

double crossTrackM(const LatLon& a, const LatLon& b, const LatLon& p) noexcept
{
    const double d13 = distanceM(a, p) / kEarthRadiusM;
    const double t13 = initialBearingDeg(a, p) * kDeg, t12 = initialBearingDeg(a, b) * kDeg;
    return std::asin(clampUnit(std::sin(d13) * std::sin(t13 - t12))) * kEarthRadiusM;
}

double alongTrackM(const LatLon& a, const LatLon& b, const LatLon& p) noexcept
{
    const double d13 = distanceM(a, p) / kEarthRadiusM;
    const double dxt = crossTrackM(a, b, p) / kEarthRadiusM;
    const double c = std::cos(dxt);
    const double at = c == 0.0 ? 0.0 : std::acos(clampUnit(std::cos(d13) / c)) * kEarthRadiusM;
    const double t13 = initialBearingDeg(a, p) * kDeg, t12 = initialBearingDeg(a, b) * kDeg;
    return std::cos(t13 - t12) < 0.0 ? -at : at;
}

double legDistanceM(const LatLon& a, const LatLon& b, const LatLon& p) noexcept
{
    const double along = alongTrackM(a, b, p);
    if (along <= 0.0) return distanceM(a, p);
    if (along >= distanceM(a, b)) return distanceM(b, p);
    return std::fabs(crossTrackM(a, b, p));
}

void LocalPlane::toXY(const LatLon& p, double& x, double& y) const noexcept
{
    x = wrap180(p.lon - origin.lon) * kDeg * kEarthRadiusM * std::cos(origin.lat * kDeg);
    y = (p.lat - origin.lat) * kDeg * kEarthRadiusM;
}

LatLon LocalPlane::fromXY(double x, double y) const noexcept
{
    return {origin.lat + y / kEarthRadiusM / kDeg, wrap180(origin.lon + x / (kEarthRadiusM * std::cos(origin.lat * kDeg)) / kDeg)};
}

} // namespace armadillo::navigation
