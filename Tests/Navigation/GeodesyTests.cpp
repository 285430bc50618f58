// Geodesy against closed forms on the sphere of radius R (expected values computed by hand from
// the definitions, not from the code under test).
#include "Navigation/Geodesy.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

using namespace armadillo::navigation;

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kOneDegreeM = kEarthRadiusM * kPi / 180.0;   // arc of 1° on the sphere: 111 195.08 m
} // namespace

TEST_CASE("distance: a degree of meridian and of equator is R·π/180; zero for the same point", "[geodesy]")
{
    CHECK(kOneDegreeM == Approx(111195.08).margin(0.01));
    CHECK(distanceM({10.0, 20.0}, {11.0, 20.0}) == Approx(kOneDegreeM).epsilon(1e-9));
    CHECK(distanceM({0.0, 20.0}, {0.0, 21.0}) == Approx(kOneDegreeM).epsilon(1e-9));
    // Along the parallel at 60° (cos = 0.5): d = 2R·asin(cos φ · sin(Δλ/2)).
    CHECK(distanceM({60.0, 0.0}, {60.0, 1.0}) == Approx(2.0 * kEarthRadiusM * std::asin(0.5 * std::sin(kPi / 360.0))).epsilon(1e-9));
    CHECK(distanceM({48.1, 11.5}, {48.1, 11.5}) == 0.0);
    // Antipodes: half the circumference.
    CHECK(distanceM({0.0, 0.0}, {0.0, 180.0}) == Approx(kPi * kEarthRadiusM).epsilon(1e-9));
}

TEST_CASE("bearing: the four directions, and across the date line", "[geodesy]")
{
    CHECK(initialBearingDeg({0, 0}, {1, 0}) == Approx(0.0).margin(1e-9));
    CHECK(initialBearingDeg({0, 0}, {0, 1}) == Approx(90.0));
    CHECK(initialBearingDeg({0, 0}, {-1, 0}) == Approx(180.0));
    CHECK(initialBearingDeg({0, 0}, {0, -1}) == Approx(270.0));
    CHECK(initialBearingDeg({0, 179.9}, {0, -179.9}) == Approx(90.0));   // east across 180°
    // North-east on the equator: tan θ = sin Δλ cos φ2 / (sin φ2) with φ1 = 0 → θ = atan2(sin 1°, tan 1° ·cos 1°…)
    const double d = kPi / 180.0;
    const double expected = std::atan2(std::sin(d) * std::cos(d), std::sin(d)) * 180.0 / kPi;   // φ1 = 0 closed form
    CHECK(initialBearingDeg({0, 0}, {1, 1}) == Approx(expected).epsilon(1e-12));
    CHECK(initialBearingDeg({5, 5}, {5, 5}) == 0.0);
}

TEST_CASE("destination inverts distance and bearing (property, 2000 random cases)", "[geodesy]")
{
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> lat(-80, 80), lon(-180, 180), brg(0, 360), dist(1, 5000);
    for (int i = 0; i < 2000; ++i) {
        const LatLon a {lat(rng), lon(rng)};
        const double b = brg(rng), d = dist(rng);
        const LatLon c = destination(a, b, d);
        REQUIRE(validLatLon(c));
        CHECK(distanceM(a, c) == Approx(d).epsilon(1e-7));
        CHECK(std::fabs(wrap180(initialBearingDeg(a, c) - b)) < 1e-6);
    }
}

TEST_CASE("cross-track and along-track on the equator; leg distance before, beside and past a leg", "[geodesy]")
{
    const LatLon a {0, 0}, b {0, 1};   // eastward along the equator, 111 km
    // 0.001° north of the leg's middle: left of the direction of travel (negative), 111.195 m.
    CHECK(crossTrackM(a, b, {0.001, 0.5}) == Approx(-0.001 * kOneDegreeM).epsilon(1e-6));
    CHECK(crossTrackM(a, b, {-0.001, 0.5}) == Approx(0.001 * kOneDegreeM).epsilon(1e-6));
    CHECK(alongTrackM(a, b, {0.001, 0.5}) == Approx(0.5 * kOneDegreeM).epsilon(1e-6));
    CHECK(alongTrackM(a, b, {0.0, -0.1}) == Approx(-0.1 * kOneDegreeM).epsilon(1e-6));
    CHECK(legDistanceM(a, b, {0.001, 0.5}) == Approx(0.001 * kOneDegreeM).epsilon(1e-6));
    CHECK(legDistanceM(a, b, {0.0, -0.002}) == Approx(0.002 * kOneDegreeM).epsilon(1e-6));   // before a: distance to a
    CHECK(legDistanceM(a, b, {0.0, 1.003}) == Approx(0.003 * kOneDegreeM).epsilon(1e-6));    // past b: distance to b
}

TEST_CASE("wraps and the local plane", "[geodesy]")
{
    CHECK(wrap360(-10) == Approx(350));
    CHECK(wrap360(720) == Approx(0));
    CHECK(wrap180(190) == Approx(-170));
    CHECK(wrap180(-180) == Approx(180));
    LocalPlane plane {{48.0, 11.0}};
    double x = 0, y = 0;
    plane.toXY(destination({48.0, 11.0}, 90.0, 100.0), x, y);
    CHECK(x == Approx(100.0).margin(0.01));
    CHECK(y == Approx(0.0).margin(0.01));
    const LatLon back = plane.fromXY(30.0, -40.0);
    CHECK(distanceM({48.0, 11.0}, back) == Approx(50.0).margin(0.01));
    CHECK_FALSE(validLatLon({91, 0}));
    CHECK_FALSE(validLatLon({0, std::nan("")}));
}
