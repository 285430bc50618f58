// "Here" by the arm: the §2.6.3 "button pushing" movement along the forearm axis. Synthetic IMU
// streams from a small physical model of the forearm: its elevation θ(t) (gravity's axial
// component g·sin θ, the centripetal r·θ'² of a forearm turning about the elbow), its roll rate,
// and a push (minimum-jerk out along the axis and back), at the control rate with sensor noise.
#include "Braille/ArmPush.h"
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <limits>
#include <random>

using namespace armadillo::braille;

namespace {
constexpr double kDt = 0.005;        // 200 updates/s
constexpr double kG = 9.80665;
constexpr double kPi = 3.14159265358979323846;
constexpr double kElbowToSensor = 0.2;   // m

using Signal = std::function<double(double)>;
const Signal kZero = [](double) { return 0.0; };

/// Second derivative of the minimum-jerk profile 10u³ − 15u⁴ + 6u⁵ (0 → 1 over u in [0, 1]).
double minJerk(double u) { return 60.0 * u - 180.0 * u * u + 120.0 * u * u * u; }

/// Axial acceleration of a push: `distance` m out along the forearm in `half` s, and back.
Signal push(double start, double distance = 0.06, double half = 0.2)
{
    return [=](double t) {
        const double k = distance / (half * half);
        if (t >= start && t < start + half) return k * minJerk((t - start) / half);
        if (t >= start + half && t < start + 2.0 * half) return -k * minJerk((t - start - half) / half);
        return 0.0;
    };
}

struct Stream {
    Signal elevation = [](double) { return 0.0; };   ///< rad: forearm above the horizontal
    Signal rollRate = kZero;                          ///< rad/s about the forearm axis
    Signal linear = kZero;                            ///< m/s² along the forearm axis
    double accelNoise = 0.3, rateNoise = 0.05;        ///< rms
};

/// Feeds the stream for `seconds`; returns the times the detector fired.
std::vector<double> run(const Stream& s, double seconds, std::uint32_t seed = 1, PushDetector* used = nullptr)
{
    PushDetector local;
    PushDetector& d = used ? *used : local;
    std::mt19937 rng(seed);
    std::normal_distribution<double> na(0.0, s.accelNoise), nr(0.0, s.rateNoise);
    std::vector<double> fired;
    for (double t = 0.0; t < seconds; t += kDt) {
        const double th = s.elevation(t), dth = (s.elevation(t + 1e-4) - s.elevation(t - 1e-4)) / 2e-4;
        const double ax = kG * std::sin(th) - kElbowToSensor * dth * dth + s.linear(t) + na(rng);
        const double wx = s.rollRate(t) + nr(rng), wy = dth + nr(rng), wz = nr(rng);
        if (d.update(t, ax, std::sqrt(wx * wx + wy * wy + wz * wz))) fired.push_back(t);
    }
    return fired;
}

double deg(double d) { return d * kPi / 180.0; }
} // namespace

TEST_CASE("push: a push along the forearm and back fires once, at any elevation", "[braille][push]")
{
    for (const double elev : {-90.0, -45.0, 0.0, 30.0}) {
        Stream s;
        s.elevation = [=](double) { return deg(elev); };
        s.linear = push(1.0);
        const auto fired = run(s, 3.0);
        REQUIRE(fired.size() == 1);
        CHECK(fired[0] > 1.0);
        CHECK(fired[0] < 1.4);   // on the stop, within the push
    }
    // A gentler push (4 cm, peak ≈ 5.8 m/s²) and a pull (the other way first) count too.
    Stream gentle;
    gentle.linear = push(1.0, 0.04);
    CHECK(run(gentle, 3.0).size() == 1);
    Stream pull;
    pull.linear = push(1.0, -0.06);
    CHECK(run(pull, 3.0).size() == 1);
}

TEST_CASE("push: two pushes a second apart fire twice; the start time is the push's", "[braille][push]")
{
    Stream s;
    s.linear = [a = push(1.0), b = push(2.2)](double t) { return a(t) + b(t); };
    PushDetector d;
    const auto fired = run(s, 4.0, 1, &d);
    REQUIRE(fired.size() == 2);
    CHECK(d.startedAt() > 2.2);
    CHECK(d.startedAt() < fired[1]);
}

TEST_CASE("push: reading by roll, twists, slow posture changes and noise do not fire", "[braille][push]")
{
    SECTION("reading by roll: the forearm turns about its own axis, hanging and level")
    {
        for (const double elev : {-90.0, 0.0}) {
            Stream s;
            s.elevation = [=](double) { return deg(elev); };
            s.rollRate = [](double t) { return 1.2 * std::sin(2.0 * kPi * t / 4.0); };   // ±1.2 rad/s, back and forth
            CHECK(run(s, 20.0).empty());
        }
    }
    SECTION("a twist of the wrist with a jolt along the axis: the angular rate refuses it")
    {
        Stream s;
        s.rollRate = [](double t) { return t >= 1.0 && t < 1.4 ? 6.0 * std::sin(2.0 * kPi * (t - 1.0) / 0.4) : 0.0; };
        s.linear = push(1.0);   // the same axial signal as a push
        CHECK(run(s, 3.0).empty());
        s.rollRate = kZero;     // (the probe: without the turn it is a push)
        CHECK(run(s, 3.0).size() == 1);
    }
    SECTION("slow posture changes: the arm raised from hanging to 30° in 2 s and lowered again")
    {
        Stream s;
        s.elevation = [](double t) {
            const double phase = std::fmod(t, 6.0);   // up in 2 s, hold 1 s, down in 2 s, hold 1 s
            const double up = deg(-90.0), top = deg(30.0);
            auto ease = [](double u) { return 0.5 - 0.5 * std::cos(kPi * std::clamp(u, 0.0, 1.0)); };
            if (phase < 3.0) return up + (top - up) * ease(phase / 2.0);
            return top + (up - top) * ease((phase - 3.0) / 2.0);
        };
        CHECK(run(s, 30.0).empty());
    }
    SECTION("sensor noise alone, a minute of it, three times the usual")
    {
        Stream s;
        s.accelNoise = 0.9;
        s.rateNoise = 0.15;
        for (std::uint32_t seed : {1u, 2u, 3u}) CHECK(run(s, 60.0, seed).empty());
    }
    SECTION("taps and knocks on the device: sharp, both ways within a few ms")
    {
        Stream s;
        // Three knocks, each ±15 m/s² for 10 ms one way then 10 ms the other.
        s.linear = [](double t) {
            for (const double at : {1.0, 2.0, 3.0})
                if (t >= at && t < at + 0.02) return t < at + 0.01 ? 15.0 : -15.0;
            return 0.0;
        };
        CHECK(run(s, 4.0).empty());
        PushParams noMinimum;   // (the probe: without the minimum push time each knock would be one)
        noMinimum.minPush = 0.0;
        PushDetector probe(noMinimum);
        CHECK(run(s, 4.0, 1, &probe).size() == 3);
    }
    SECTION("too slow to be a push: 6 cm out and back in 2 s")
    {
        Stream s;
        s.linear = push(1.0, 0.06, 1.0);
        CHECK(run(s, 4.0).empty());
    }
}

TEST_CASE("push: a push out that never stops, or samples with a NaN, give nothing", "[braille][push]")
{
    // Out only (a reach): the axial acceleration goes one way and comes back to zero.
    Stream s;
    s.linear = [](double t) { return t >= 1.0 && t < 1.2 ? 8.0 * std::sin(kPi * (t - 1.0) / 0.2) : 0.0; };
    CHECK(run(s, 3.0).empty());
    PushDetector d;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (double t = 0.0; t < 1.0; t += kDt) CHECK_FALSE(d.update(t, t > 0.5 ? nan : 0.0, nan));
}
