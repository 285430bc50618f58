// Arm gestures of the adaptive training: a twist and back = repeat, two = skip.
#include "Access/ArmGestures.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <vector>

using namespace armadillo::access;

namespace {
constexpr double kDt = 0.005;
constexpr double kPi = 3.14159265358979323846;

/// Feeds rate(t) for `seconds` and collects every gesture reported.
std::vector<ArmGesture> run(const std::function<double(double)>& rate, double seconds)
{
    TwistDetector d;
    std::vector<ArmGesture> out;
    for (double t = 0.0; t < seconds; t += kDt)
        if (const ArmGesture g = d.update(t, rate(t)); g != ArmGesture::None) out.push_back(g);
    return out;
}

/// One full sine period of the roll rate: a turn of amplitude `peak` rad/s one way and back.
double twist(double t, double start, double period, double peak)
{
    if (t < start || t > start + period) return 0.0;
    return peak * std::sin(2.0 * kPi * (t - start) / period);
}
} // namespace

TEST_CASE("gestures: a twist and back is a repeat, two in a row a skip", "[gestures]")
{
    CHECK(run([](double t) { return twist(t, 0.5, 0.3, 6.0); }, 3.0) == std::vector<ArmGesture> {ArmGesture::Repeat});
    CHECK(run([](double t) { return twist(t, 0.5, 0.3, -6.0); }, 3.0) == std::vector<ArmGesture> {ArmGesture::Repeat});
    CHECK(run([](double t) { return twist(t, 0.5, 0.3, 6.0) + twist(t, 1.0, 0.3, 6.0); }, 3.0) == std::vector<ArmGesture> {ArmGesture::Skip});
    // Two twists far apart: two repeats.
    CHECK(run([](double t) { return twist(t, 0.5, 0.3, 6.0) + twist(t, 2.5, 0.3, 6.0); }, 5.0) ==
          std::vector<ArmGesture> {ArmGesture::Repeat, ArmGesture::Repeat});
}

TEST_CASE("gestures: reading rolls, one-way turns, slow twists and noise are no gesture", "[gestures]")
{
    // A reading roll of 15° in 0.25 s peaks near 1.6 rad/s: far below the threshold.
    CHECK(run([](double t) { return twist(t, 0.5, 0.5, 1.6); }, 3.0).empty());
    // A fast turn one way that stays there (half a sine).
    CHECK(run([](double t) { return t > 0.5 && t < 0.65 ? 6.0 * std::sin(kPi * (t - 0.5) / 0.15) : 0.0; }, 3.0).empty());
    // A twist whose way back comes too late (2 s period: each half 1 s > 0.6 s).
    CHECK(run([](double t) { return twist(t, 0.5, 2.0, 6.0); }, 4.0).empty());
    std::mt19937_64 rng(3);
    std::normal_distribution<double> noise(0.0, 0.5);
    CHECK(run([&](double) { return noise(rng); }, 20.0).empty());
    CHECK(run([](double) { return std::numeric_limits<double>::quiet_NaN(); }, 2.0).empty());
}
