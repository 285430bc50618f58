// OrientationFilter on synthetic motion with exact truth (issue 4): still with a drifting bias,
// constant rates, the thesis's square-wave swings with 4 g transients, a 180° flip, no
// magnetometer; robustness to NaN, gaps and time going backwards; no heap per update.
#include "Core/Pose.h"
#include "Fusion/OrientationFilter.h"
#include "Fusion/Quaternion.h"
#include <algorithm>
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
using namespace armadillo::core;
using namespace armadillo::fusion;
using Eigen::Quaterniond;
using Eigen::Vector3d;

namespace {
constexpr double kRate = 285.714;   // Hz, as the BROAD recordings
const double kIncl = degToRad(67.0);
const Vector3d kField(0.0, -std::sin(kIncl) * 49.0, -std::cos(kIncl) * 49.0);   // µT, north = −Z, dipping down

Vector3d zero(double) { return Vector3d::Zero(); }

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
    std::vector<std::pair<double, double>> errors;   ///< (t, total error rad) of every sample fed after `settle`
    OrientationFilter::Recovery recovery {};
    Vector3d leverArm = Vector3d::Zero();   ///< m, what the filter learned by the end
    /// Median error over [from, to).
    double median(double from, double to) const
    {
        std::vector<double> v;
        for (const auto& [t, e] : errors)
            if (t >= from && t < to) v.push_back(e);
        if (v.empty()) return kNaN;
        std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
        return v[v.size() / 2];
    }
    /// Largest error over [from, to).
    double worst(double from, double to) const
    {
        double w = 0.0;
        for (const auto& [t, e] : errors)
            if (t >= from && t < to) w = std::max(w, e);
        return w;
    }
};

/// What the link does to the stream: samples inside a gap are never delivered (the time column
/// keeps the gap), the stream may start late (mid-movement), the field may be disturbed.
struct Link {
    std::vector<std::pair<double, double>> gaps;            ///< [from, to) in s
    double startAt = 0.0;                                   ///< s: first sample delivered
    std::function<Vector3d(double)> magDisturbance = zero;  ///< µT added in the device frame
    Vector3d leverArm = Vector3d::Zero();                   ///< m, device frame: where the sensor sits from the
                                                            ///< centre the arm turns about (not the link's, but
                                                            ///< the one place for the stream's options)
    bool dropped(double t) const
    {
        if (t < startAt) return true;
        for (const auto& [a, b] : gaps)
            if (t >= a && t < b) return true;
        return false;
    }
};

SimResult simulate(double seconds, const Quaterniond& q0, const std::function<Vector3d(double)>& rate,
                   const std::function<Vector3d(double)>& linearAccel, const std::function<Vector3d(double)>& bias,
                   bool withMag, double settle = 5.0, unsigned seed = 11,
                   const OrientationFilter::Params& params = OrientationFilter::defaultParams(), const Link& link = {})
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
        if (!link.leverArm.isZero()) {
            // The turn's own acceleration at the lever arm: ω×(ω×r) + α×r (device frame).
            const Vector3d wt = rate(t), at = (rate(t + 1e-4) - rate(t - 1e-4)) / 2e-4;
            s.accel += wt.cross(wt.cross(link.leverArm)) + at.cross(link.leverArm);
        }
        if (withMag) s.mag = quat::rotateInverse(q, kField) + Vector3d(magNoise(rng), magNoise(rng), magNoise(rng)) + link.magDisturbance(t);
        if (link.dropped(t)) continue;
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
        r.errors.emplace_back(t, err);
    }
    r.recovery = f.recovery();
    r.leverArm = f.leverArm();
    r.rmsError = std::sqrt(sum2 / std::max(1L, n));
    r.skipped = f.skippedSamples();
    return r;
}

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
        // Since the low-pass starts with a plain mean (Trackers.h) the flat filter is much better
        // than it was (2.99° → 1.64°); the ramp still must not lose to it.
        CHECK(ramp.maxTiltError < flat.maxTiltError);
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
    SUCCEED("skipped under the sanitizer");
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

namespace {
/// A forearm that never rests: every axis turning at up to ~1.5 rad/s, and ±2 m/s² of linear
/// acceleration at 0.9–1.4 Hz (gestures; slower sustained swings are a known weakness, FUSION.md).
Vector3d movingRate(double t) { return Vector3d(1.5 * std::sin(1.3 * t), 1.0 * std::cos(0.9 * t + 0.4), 0.8 * std::sin(0.5 * t + 1.0)); }
Vector3d movingAccel(double t) { return Vector3d(2.0 * std::sin(7.1 * t), 1.5 * std::cos(5.7 * t), 2.0 * std::sin(8.9 * t + 0.3)); }
Vector3d smallBias(double) { return Vector3d(0.004, 0.002, -0.004); }
} // namespace

TEST_CASE("filter: after a gap it cannot bridge, a moving arm is re-acquired", "[fusion][filter][gaps]")
{
    // Dropouts of 0.3, 1 and 3 s in the middle of a movement (the time column keeps the gap).
    Link link;
    link.gaps = {{20.0, 20.3}, {40.0, 41.0}, {60.0, 63.0}};
    const SimResult r = simulate(80.0, poseToQuaternion({10.0, 20.0, 0.0}), movingRate, movingAccel, smallBias, true, 5.0,
                                 11, OrientationFilter::defaultParams(), link);
    CHECK(r.recovery.gaps == 3);
    CHECK(r.recovery.reacquired == 3);
    CHECK(r.recovery.longestGap == Approx(3.0).margin(0.01));
    for (const auto& [from, to] : link.gaps) {
        INFO("gap " << from << "–" << to << " s: worst error 2–10 s after " << radToDeg(r.worst(to + 2.0, to + 10.0)) << "°");
        CHECK(radToDeg(r.worst(to + 2.0, to + 10.0)) < 5.0);
    }
    // The probe: the same stream through a filter that extrapolates across every gap (what the
    // filter did before re-acquisition) is far off after the long gaps — the check above can fail.
    OrientationFilter::Params bridgeAll = OrientationFilter::defaultParams();
    bridgeAll.maxBridge = 1e9;
    bridgeAll.disagreementTime = bridgeAll.acquireDisagreementTime = 1e9;
    const SimResult old = simulate(80.0, poseToQuaternion({10.0, 20.0, 0.0}), movingRate, movingAccel, smallBias, true, 5.0,
                                   11, bridgeAll, link);
    CHECK(radToDeg(old.worst(63.0 + 2.0, 63.0 + 10.0)) > 20.0);
}

TEST_CASE("filter: a short gap is bridged with what ω and α know", "[fusion][filter][gaps]")
{
    Link link;
    link.gaps = {{20.0, 20.03}};
    const SimResult r = simulate(40.0, poseToQuaternion({10.0, 20.0, 0.0}), movingRate, movingAccel, smallBias, true, 5.0,
                                 11, OrientationFilter::defaultParams(), link);
    CHECK(r.recovery.gaps == 1);
    CHECK(r.recovery.bridged == 1);
    CHECK(r.recovery.reacquired == 0);
    CHECK(radToDeg(r.worst(20.0, 40.0)) < 3.0);
}

TEST_CASE("filter: a stream that starts in the middle of a movement", "[fusion][filter][gaps]")
{
    // No rest phase, a gyro bias nobody has measured yet, 2 m/s² of linear acceleration.
    Link link;
    link.startAt = 30.0;
    auto bias = [](double) { return Vector3d(0.01, -0.008, 0.006); };
    const SimResult r = simulate(45.0, poseToQuaternion({0.0, 0.0, 0.0}), movingRate, movingAccel, bias, true, 30.0, 11,
                                 OrientationFilter::defaultParams(), link);
    INFO("median error 1–3 s after the start " << radToDeg(r.median(31.0, 33.0)) << "°, worst 3–15 s " << radToDeg(r.worst(33.0, 45.0)) << "°");
    CHECK(radToDeg(r.median(31.0, 33.0)) < 5.0);
    CHECK(radToDeg(r.worst(33.0, 45.0)) < 5.0);
}

TEST_CASE("filter: no gate locks the truth out: a heading 150° off is re-acquired from a trusted field", "[fusion][filter][gaps]")
{
    // For the first 5 s (arm still) the field is the earth's turned 150° about the vertical — same
    // norm and dip, so the field tracker takes it as the reference and the filter starts 150° off.
    // Then the true field returns while the arm moves: every heading innovation is beyond the ±90°
    // the update can take. Only the persistent-disagreement rule can bring the heading back.
    const Quaterniond q0 = poseToQuaternion({10.0, 20.0, 0.0});
    const Vector3d turned = Eigen::AngleAxisd(degToRad(150.0), Vector3d::UnitY()) * kField;
    const Vector3d wrong = quat::rotateInverse(q0, turned - kField);
    Link link;
    link.magDisturbance = [&](double t) -> Vector3d { return t < 5.0 ? wrong : Vector3d::Zero(); };
    auto rate = [](double t) -> Vector3d { return t < 5.0 ? Vector3d::Zero() : movingRate(t); };
    const SimResult r = simulate(40.0, q0, rate, zero, smallBias, true, 0.0, 11, OrientationFilter::defaultParams(), link);
    CHECK(radToDeg(r.worst(0.0, 4.0)) > 140.0);   // the setup really starts 150° off
    CHECK(r.recovery.headingResets >= 1);
    INFO("median error 11–13 s " << radToDeg(r.median(11.0, 13.0)) << "°, worst 15–40 s " << radToDeg(r.worst(15.0, 40.0)) << "°");
    CHECK(radToDeg(r.median(11.0, 13.0)) < 5.0);
    CHECK(radToDeg(r.worst(15.0, 40.0)) < 3.0);
    // The probe: without the rule the same stream stays off for tens of seconds. (Until issue 36 it
    // stayed locked out, > 60°; since the estimate averages the field over 6 s, that average
    // sweeps through the headings between the old field and the new one, and the plain update
    // follows it slowly: 11° at 30–40 s, against 0.2° with the rule.)
    OrientationFilter::Params noRule = OrientationFilter::defaultParams();
    noRule.disagreementTime = noRule.acquireDisagreementTime = 1e9;
    const SimResult locked = simulate(40.0, q0, rate, zero, smallBias, true, 0.0, 11, noRule, link);
    INFO("without the rule: worst 30–40 s " << radToDeg(locked.worst(30.0, 40.0)) << "°");
    CHECK(radToDeg(locked.worst(30.0, 40.0)) > 5.0);
}

TEST_CASE("filter: heading comes back after a long magnetic disturbance ends", "[fusion][filter][gaps]")
{
    // 40 s of a disturbed field (rejected) while the arm keeps moving and the gyro bias steps by
    // 1.5°/s, unseen: the heading drifts by tens of degrees meanwhile.
    Link link;
    link.magDisturbance = [](double t) -> Vector3d { return t >= 10.0 && t < 50.0 ? Vector3d(20.0, -15.0, 10.0) : Vector3d::Zero(); };
    auto rate = [](double t) -> Vector3d { return t < 5.0 ? Vector3d::Zero() : movingRate(t); };
    auto bias = [](double t) -> Vector3d { return t < 10.0 ? Vector3d(0.004, 0.002, -0.004) : Vector3d(0.019, 0.017, -0.019); };
    const SimResult r = simulate(100.0, poseToQuaternion({0.0, 0.0, 0.0}), rate, zero, bias, true, 5.0, 11,
                                 OrientationFilter::defaultParams(), link);
    INFO("worst error during the disturbance " << radToDeg(r.worst(10.0, 50.0)) << "°, median 5–10 s after it "
         << radToDeg(r.median(55.0, 60.0)) << "°, median 20–50 s after it " << radToDeg(r.median(70.0, 100.0)) << "°");
    CHECK(radToDeg(r.worst(40.0, 50.0)) > 10.0);   // the disturbance really cost heading
    CHECK(radToDeg(r.median(55.0, 60.0)) < 5.0);
    // Afterwards the heading holds: the bias step about the vertical is observable only through
    // the (slow) heading updates, so a few degrees of wander remain while it is learned.
    CHECK(radToDeg(r.median(70.0, 100.0)) < 5.0);
}


TEST_CASE("filter: a state that agrees with the young averages after a gap keeps its own precision", "[fusion][filter][gaps]")
{
    // The arm holds still through a 1 s gap: the state before the gap is right, and the young
    // averages (0.1 s of samples) are not better than it, so the step leaves it alone.
    Link link;
    link.gaps = {{20.0, 21.0}};
    const SimResult r = simulate(30.0, poseToQuaternion({10.0, 20.0, 0.0}), zero, zero, smallBias, true, 5.0, 11,
                                 OrientationFilter::defaultParams(), link);
    CHECK(r.recovery.reacquired == 1);
    CHECK(r.recovery.reacquireSteps == 0);
    INFO("worst error 0–3 s after the gap " << radToDeg(r.worst(21.0, 24.0)) << "°");
    CHECK(radToDeg(r.worst(21.0, 24.0)) < 1.5);
}

TEST_CASE("filter: the lever arm of an arm turning about the elbow is learned and not taken for gravity", "[fusion][filter][gaps]")
{
    // The sensor 25 cm from the elbow along the forearm (device x), the arm turning briskly (up to
    // 3 rad/s, so 2–3 m/s² of centripetal and tangential acceleration that turns with the arm). The
    // filter learns r from its steady state and takes the turn's acceleration off before averaging
    // gravity (docs/FUSION.md, issue 49); after a 1 s dropout the young gravity average is then
    // not misled by it. The probe (leverArmTau 0) is the filter without the lever arm.
    Link link;
    link.leverArm = Vector3d(0.25, 0.0, 0.0);
    link.gaps = {{40.0, 41.0}};
    auto rate = [](double t) -> Vector3d {
        return t < 3.0 ? Vector3d::Zero() : Vector3d(3.0 * std::sin(2.1 * t), 2.5 * std::cos(1.7 * t + 0.4), 2.0 * std::sin(1.1 * t + 1.0));
    };
    const SimResult r = simulate(60.0, poseToQuaternion({10.0, 20.0, 0.0}), rate, zero, smallBias, true, 5.0, 11,
                                 OrientationFilter::defaultParams(), link);
    OrientationFilter::Params none = OrientationFilter::defaultParams();
    none.leverArmTau = 0.0;
    const SimResult off = simulate(60.0, poseToQuaternion({10.0, 20.0, 0.0}), rate, zero, smallBias, true, 5.0, 11, none, link);
    INFO("median error 20–40 s " << radToDeg(r.median(20.0, 40.0)) << "° (without the lever arm " << radToDeg(off.median(20.0, 40.0))
         << "°), 0–1 s after the gap " << radToDeg(r.median(41.0, 42.0)) << "° (" << radToDeg(off.median(41.0, 42.0)) << "°), 1–3 s "
         << radToDeg(r.median(42.0, 44.0)) << "° (" << radToDeg(off.median(42.0, 44.0)) << "°)");
    INFO("lever arm learned " << r.leverArm.transpose() << " m");
    CHECK((r.leverArm - link.leverArm).norm() < 0.04);   // 0.22 m: the ridge (leverArmPrior) shrinks it a little
    CHECK(radToDeg(r.median(20.0, 40.0)) < 1.0);
    CHECK(radToDeg(r.median(41.0, 42.0)) < 5.0);
    CHECK(radToDeg(off.median(41.0, 42.0)) > 2.0 * radToDeg(r.median(41.0, 42.0)));
}

TEST_CASE("filter: every parameter can be set by its name (armadillo fuse --param)", "[fusion][filter]")
{
    OrientationFilter::Params p = OrientationFilter::defaultParams();
    CHECK(OrientationFilter::setParameter(p, "headingNoise", 0.4));
    CHECK(p.headingNoise == 0.4);
    CHECK(OrientationFilter::setParameter(p, "field.normTolerance", 0.2));
    CHECK(p.field.normTolerance == 0.2);
    CHECK(OrientationFilter::setParameter(p, "bias.minRestTime", 2.0));
    CHECK(p.bias.minRestTime == 2.0);
    CHECK(OrientationFilter::setParameter(p, "useMagnetometer", 0.0));
    CHECK_FALSE(p.useMagnetometer);
    CHECK_FALSE(OrientationFilter::setParameter(p, "nosuchThing", 1.0));
    const std::vector<std::string> names = OrientationFilter::parameterNames();
    CHECK(std::find(names.begin(), names.end(), "reacquireWindow") != names.end());
    CHECK(std::find(names.begin(), names.end(), "magFilterTau") != names.end());
    for (const std::string& n : names) {
        OrientationFilter::Params q = OrientationFilter::defaultParams();
        CHECK(OrientationFilter::setParameter(q, n, 1.0));
    }
}
