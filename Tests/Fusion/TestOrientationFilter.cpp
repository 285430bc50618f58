// OrientationFilter on synthetic motion with exact truth (issue 4): still with a drifting bias,
// constant rates, the thesis's square-wave swings with 4 g transients, a 180° flip, no
// magnetometer; robustness to NaN, gaps and time going backwards; no heap per update.
#include "Core/Pose.h"
#include "Fusion/OrientationFilter.h"
#include "Fusion/Quaternion.h"
#include <atomic>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <new>
#include <random>

// Counting global allocation: the filter's update() must not allocate.
namespace {
std::atomic<long> gAllocations {0};
}
// Sanitizer builds (scripts/sanitize.sh) own operator new: replacing only some of its forms there
// gives ASan alloc-dealloc mismatches, so the counter is left out and its check says so.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define ARMADILLO_NO_NEW_COUNTER 1
#else
void* operator new(std::size_t n)
{
    ++gAllocations;
    if (void* p = std::malloc(n ? n : 1)) return p;
    throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#endif

using namespace armadillo;
using Eigen::Quaterniond;
using Eigen::Vector3d;

namespace {
constexpr double kRate = 285.714;   // Hz, as the BROAD recordings
const double kIncl = degToRad(67.0);
const Vector3d kField(0.0, -std::sin(kIncl) * 49.0, -std::cos(kIncl) * 49.0);   // µT, north = −Z, dipping down

struct Truth {
    double t;
    Quaterniond q;
};

/// Simulates an IMU: body rate(t) (rad/s, the mean over each interval), extra linear acceleration
/// in the earth frame (m/s²), bias(t) (rad/s), white noise; runs the filter; returns the errors.
struct SimResult {
    double maxError = 0.0;        ///< rad, total, after `settle` s
    double rmsError = 0.0;        ///< rad
    double maxTiltError = 0.0;    ///< rad
    double finalError = 0.0;      ///< rad
    double maxDrift = 0.0;        ///< rad: error relative to the error at `settle` (what 6-axis can promise)
    std::size_t skipped = 0;
};

SimResult simulate(double seconds, const Quaterniond& q0, const std::function<Vector3d(double)>& rate,
                   const std::function<Vector3d(double)>& linearAccel, const std::function<Vector3d(double)>& bias,
                   bool withMag, double settle = 5.0, unsigned seed = 11,
                   const OrientationFilter::Params& params = OrientationFilter::defaultParams())
{
    std::mt19937 rng(seed);
    std::normal_distribution<double> gyroNoise(0.0, 0.002), accelNoise(0.0, 0.05), magNoise(0.0, 0.3);
    OrientationFilter f(params);
    Quaterniond q = q0;
    const double dt = 1.0 / kRate;
    SimResult r;
    double sum2 = 0.0;
    long n = 0;
    Quaterniond offset0 = Quaterniond::Identity();
    bool haveOffset = false;
    for (long k = 0; k * dt <= seconds; ++k) {
        const double t = k * dt;
        const Vector3d w = k == 0 ? Vector3d::Zero() : rate(t - 0.5 * dt);   // mean rate over [t−dt, t]
        if (k > 0) q = (q * quat::exp(w * dt)).normalized();
        ImuSample s;
        s.t = t;
        s.gyro = w + bias(t) + Vector3d(gyroNoise(rng), gyroNoise(rng), gyroNoise(rng));
        const Vector3d specificEarth = Vector3d(0.0, kStandardGravity, 0.0) + linearAccel(t);
        s.accel = quat::rotateInverse(q, specificEarth) + Vector3d(accelNoise(rng), accelNoise(rng), accelNoise(rng));
        if (withMag) s.mag = quat::rotateInverse(q, kField) + Vector3d(magNoise(rng), magNoise(rng), magNoise(rng));
        f.update(s);
        if (t < settle) continue;
        const Quaterniond e = f.orientation();
        const double err = quat::angleBetween(e, q);
        const Vector3d upEst = quat::rotateInverse(e, Vector3d::UnitY()), upTrue = quat::rotateInverse(q, Vector3d::UnitY());
        const double tilt = std::acos(std::clamp(upEst.dot(upTrue), -1.0, 1.0));
        r.maxError = std::max(r.maxError, err);
        r.maxTiltError = std::max(r.maxTiltError, tilt);
        sum2 += err * err;
        ++n;
        r.finalError = err;
        const Quaterniond offset = e * q.conjugate();   // earth-frame error
        if (!haveOffset) {
            offset0 = offset;
            haveOffset = true;
        }
        r.maxDrift = std::max(r.maxDrift, quat::angleBetween(offset, offset0));
    }
    r.rmsError = std::sqrt(sum2 / std::max(1L, n));
    r.skipped = f.skippedSamples();
    return r;
}

Vector3d zero(double) { return Vector3d::Zero(); }
} // namespace

TEST_CASE("filter: still for five minutes with a drifting gyro bias does not drift", "[fusion][filter]")
{
    // Bias starts at 0.6°/s and drifts by another 0.3°/s over five minutes (most in the first minute).
    auto bias = [](double t) -> Vector3d { return Vector3d(0.01, -0.008, 0.006) + Vector3d(0.005, 0.004, -0.003) * (1.0 - std::exp(-t / 60.0)); };
    const Quaterniond q0 = poseToQuaternion({10.0, 30.0, -20.0});
    for (bool mag : {true, false}) {
        INFO("magnetometer " << mag);
        // 30 s to settle: heading corrections are deliberately slow (docs/FUSION.md, departure 3).
        const SimResult r = simulate(300.0, q0, zero, zero, bias, mag, 30.0);
        CHECK(radToDeg(r.maxTiltError) < 0.5);
        // With a magnetometer the absolute orientation is right; without one the heading is the
        // initial guess (forearm north, here 30° off) and must not drift: it is the integral of the
        // bias error, which the rest-detecting tracker keeps small (integrated raw gyro: > 200°).
        if (mag)
            CHECK(radToDeg(r.maxError) < 1.5);
        else
            CHECK(radToDeg(r.maxDrift) < 1.0);
    }
}

TEST_CASE("filter: a large power-up gyro bias costs little tilt in the first seconds", "[fusion][filter]")
{
    // A thesis-era gyro: 0.03 rad/s (1.7°/s) of bias from the first sample, unknown to the filter.
    // The start-up ramp of the inertial-frame low-pass (startupFilterSeconds) keeps the tilt
    // closer while the bias is learned than full time constants from the start (same run).
    auto bias = [](double) -> Vector3d { return Vector3d(0.03, -0.02, 0.015); };
    const Quaterniond q0 = poseToQuaternion({20.0, 0.0, 0.0});
    OrientationFilter::Params noRamp = OrientationFilter::defaultParams();
    noRamp.startupFilterSeconds = 0.0;
    for (bool mag : {true, false}) {
        INFO("magnetometer " << mag);
        const SimResult ramp = simulate(12.0, q0, zero, zero, bias, mag, 0.0);
        const SimResult flat = simulate(12.0, q0, zero, zero, bias, mag, 0.0, 11, noRamp);
        INFO("worst tilt with the ramp " << radToDeg(ramp.maxTiltError) << "°, without " << radToDeg(flat.maxTiltError) << "°");
        CHECK(radToDeg(ramp.maxTiltError) < 1.5);
        CHECK(ramp.maxTiltError < 0.6 * flat.maxTiltError);
    }
}

TEST_CASE("filter: constant rates about every axis are tracked", "[fusion][filter]")
{
    auto bias = [](double) { return Vector3d(0.004, 0.002, -0.004); };
    for (const Vector3d& w : {Vector3d(1.0, 0.0, 0.0), Vector3d(0.0, 2.0, 0.0), Vector3d(0.0, 0.0, -3.0), Vector3d(1.0, -1.0, 0.5)}) {
        INFO("rate " << w.transpose());
        auto rate = [&](double t) -> Vector3d { return t < 3.0 ? Vector3d::Zero() : w; };
        // Rotating at a constant rate means centripetal forces are zero at the sensor (pure spin).
        const SimResult r = simulate(40.0, restOrientation(), rate, zero, bias, true);
        CHECK(radToDeg(r.rmsError) < 1.0);
        CHECK(radToDeg(r.maxError) < 2.5);
    }
}

TEST_CASE("filter: square-wave pitching swings with 4 g transients are recovered (thesis evaluation)", "[fusion][filter]")
{
    // Elevation alternates ±40° every second; each swing takes 0.12 s (≈ 12 rad/s peak) and shakes
    // the accelerometer with up to 4 g along the swing.
    const double swing = 0.12, amplitude = degToRad(80.0);
    auto rate = [&](double t) -> Vector3d {
        if (t < 3.0) return Vector3d::Zero();
        const double phase = std::fmod(t - 3.0, 1.0);
        if (phase >= swing) return Vector3d::Zero();
        const double sign = (static_cast<long>((t - 3.0) / 1.0) % 2 == 0) ? 1.0 : -1.0;
        const double shape = 2.0 * std::pow(std::sin(kPi * phase / swing), 2) / swing;   // integrates to 1
        return Vector3d(0.0, 0.0, sign * amplitude * shape);
    };
    auto accel = [&](double t) -> Vector3d {
        if (t < 3.0) return Vector3d::Zero();
        const double phase = std::fmod(t - 3.0, 1.0);
        if (phase >= swing) return Vector3d::Zero();
        return Vector3d(4.0 * kStandardGravity * std::sin(2.0 * kPi * phase / swing), 0.0, 0.0);
    };
    auto bias = [](double) { return Vector3d(0.004, 0.002, -0.004); };
    const Quaterniond q0 = poseToQuaternion({-40.0, 0.0, 0.0});
    const SimResult r = simulate(60.0, q0, rate, accel, bias, true);
    // The thesis's figure: the square wave is recovered without overshoot from the transients.
    CHECK(radToDeg(r.maxTiltError) < 3.0);
    CHECK(radToDeg(r.rmsError) < 1.5);
}

TEST_CASE("filter: a 180 degree flip in half a second", "[fusion][filter]")
{
    auto rate = [](double t) -> Vector3d { return (t >= 5.0 && t < 5.5) ? Vector3d(2.0 * kPi, 0.0, 0.0) : Vector3d::Zero(); };
    auto bias = [](double) { return Vector3d(0.003, -0.002, 0.001); };
    const SimResult r = simulate(20.0, restOrientation(), rate, zero, bias, true);
    CHECK(radToDeg(r.maxError) < 2.0);
    CHECK(radToDeg(r.finalError) < 0.5);
}

TEST_CASE("filter: without magnetometer tilt is exact and heading holds while turning", "[fusion][filter]")
{
    auto rate = [](double t) -> Vector3d { return t < 5.0 ? Vector3d::Zero() : Vector3d(0.8 * std::sin(t), 0.5 * std::cos(0.7 * t), 0.3); };
    auto bias = [](double) { return Vector3d(0.004, 0.002, -0.004); };
    const SimResult r = simulate(60.0, poseToQuaternion({0.0, 90.0, 0.0}), rate, zero, bias, false);
    CHECK(radToDeg(r.maxTiltError) < 1.0);
    // Heading: the initial guess (forearm north) is 90° off; what matters is that it does not drift.
    CHECK(radToDeg(r.maxDrift) < 1.5);
    CHECK(radToDeg(r.maxError) > 80.0);   // (and the test really starts 90° off)
}

TEST_CASE("filter: NaN samples, gaps and time going backwards are skipped and counted", "[fusion][filter]")
{
    OrientationFilter f;
    CHECK_FALSE(f.initialised());
    ImuSample s;
    s.t = 0.0;
    s.gyro.setZero();
    f.update(s);   // accel NaN: cannot initialise
    CHECK_FALSE(f.initialised());
    CHECK(f.skippedSamples() == 1);
    const Quaterniond q0 = poseToQuaternion({20.0, 45.0, 10.0});
    s.accel = quat::rotateInverse(q0, Vector3d(0.0, kStandardGravity, 0.0));
    s.mag = quat::rotateInverse(q0, kField);   // then: no magnetometer at all from here on
    f.update(s);
    REQUIRE(f.initialised());
    CHECK(radToDeg(quat::angleBetween(f.orientation(), q0)) < 0.1);
    s.mag = Vector3d(kNaN, kNaN, kNaN);
    for (int k = 1; k < 600; ++k) {
        s.t = k * 0.005;
        if (k == 100) s.t = 0.1;                           // backwards: skipped
        if (k == 200) s.gyro.x() = kNaN;                   // NaN gyro: skipped
        if (k == 201) s.gyro.x() = 0.0;
        if (k >= 300) s.t += 3.0;                          // a 3 s gap
        f.update(s);
        CHECK(f.orientation().coeffs().allFinite());
        CHECK(f.orientation().norm() == Approx(1.0).epsilon(1e-12));
    }
    CHECK(f.skippedSamples() == 3);
    CHECK(radToDeg(quat::angleBetween(f.orientation(), q0)) < 0.5);
    CHECK(f.covariance().allFinite());
    f.reset();
    CHECK_FALSE(f.initialised());
    CHECK(f.skippedSamples() == 0);
}

TEST_CASE("filter: update() does not allocate", "[fusion][filter]")
{
    OrientationFilter f;
    ImuSample s;
    s.gyro = Vector3d(0.1, -0.2, 0.3);
    s.accel = Vector3d(0.5, 9.7, 0.2);
    s.mag = Vector3d(10.0, -40.0, -20.0);
    s.t = 0.0;
    f.update(s);   // initialisation may do what it likes
#ifdef ARMADILLO_NO_NEW_COUNTER
    WARN("sanitizer build: no operator new counter; the normal build runs this check");
    return;
#endif
    const long before = gAllocations.load();
    for (int k = 1; k < 2000; ++k) {
        s.t = k / kRate;
        s.mag.x() = (k % 500 < 250) ? 10.0 : 80.0;   // disturbed half the time: the rejection path too
        f.update(s);
    }
    CHECK(gAllocations.load() == before);
    // The counter itself works (so the check above can fail).
    auto* p = new int(3);
    CHECK(gAllocations.load() == before + 1);
    delete p;
}
