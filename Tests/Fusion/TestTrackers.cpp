// Gyro-bias and magnetic-field trackers (thesis §2.6.8) and the inertial low-pass.
#include "Core/Types.h"
#include "Fusion/Trackers.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <random>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::fusion;

TEST_CASE("bias tracker: still device gives the mean gyro; motion clears rest", "[fusion][trackers]")
{
    GyroBiasTracker t;
    std::mt19937 rng(7);
    std::normal_distribution<double> n(0.0, 0.003);
    const Eigen::Vector3d bias(0.01, -0.02, 0.005);
    const Eigen::Vector3d up(0.0, kStandardGravity, 0.0);
    bool rest = false;
    for (int i = 0; i < 1000; ++i) rest = t.update(bias + Eigen::Vector3d(n(rng), n(rng), n(rng)), up, 0.005);
    CHECK(rest);
    CHECK((t.bias() - bias).norm() < 0.001);
    CHECK(t.samples() == t.params().windowSamples);
    CHECK_FALSE(t.update(Eigen::Vector3d(1.0, 0.0, 0.0), up, 0.005));
    CHECK_FALSE(t.atRest());
}

TEST_CASE("field tracker: dip and norm reference, disturbance, adoption of a new steady field", "[fusion][trackers]")
{
    MagneticFieldTracker t;
    const Eigen::Vector3d up(0.0, kStandardGravity, 0.0);
    const double incl = degToRad(66.0);
    const Eigen::Vector3d field(0.0, -std::sin(incl) * 50.0, -std::cos(incl) * 50.0);
    for (int i = 0; i < 100; ++i) CHECK(t.update(up, field, 0.01));
    CHECK(t.referenceDip() == Approx(kPi / 2 + incl).epsilon(1e-9));
    CHECK(t.referenceNorm() == Approx(50.0));
    CHECK_FALSE(t.update(up, field * 1.5, 0.01));            // norm jump
    const Eigen::Vector3d tilted(0.0, -std::sin(incl - 0.5) * 50.0, -std::cos(incl - 0.5) * 50.0);
    CHECK_FALSE(t.update(up, tilted, 0.01));                 // dip jump, same norm
    // Under strong linear acceleration the dip is not judged, only the norm.
    CHECK(t.update(up * 2.0, tilted, 0.01));
    // A steady, different field for longer than newFieldTime becomes the reference.
    bool accepted = false;
    for (int i = 0; i < 2200 && !accepted; ++i) accepted = t.update(up, field * 1.5, 0.01);
    CHECK(accepted);
    CHECK(t.referenceNorm() == Approx(75.0).epsilon(0.01));
}

TEST_CASE("butterworth: unity DC gain, strong attenuation of a 1 Hz swing", "[fusion][trackers]")
{
    ButterworthLowPass3 lp;
    const double dt = 1.0 / 285.714;
    lp.setup(3.0, dt);
    Eigen::Vector3d y;
    for (int i = 0; i < 3000; ++i) y = lp.filter(Eigen::Vector3d(1.0, 2.0, 3.0));
    CHECK((y - Eigen::Vector3d(1.0, 2.0, 3.0)).norm() < 1e-9);
    double peak = 0.0;
    for (int i = 0; i < 20000; ++i) {
        y = lp.filter(Eigen::Vector3d(1.0 + std::sin(2 * kPi * 1.0 * i * dt), 2.0, 3.0));
        if (i > 10000) peak = std::max(peak, std::abs(y.x() - 1.0));
    }
    // Second order: about (fc/f)² = (0.075/1)² ≈ 0.006 of the swing gets through.
    CHECK(peak < 0.01);
    CHECK(peak > 0.001);
}

TEST_CASE("butterworth: the tapered start-up mean of a swinging arm's acceleration finds gravity sooner", "[fusion][trackers][gaps]")
{
    // After a gap the low-pass restarts on a moving arm: a = g + dv/dt with v swinging ±1 m/s at
    // 1 Hz, the stream starting mid-swing. The plain mean's error is (v(T) − v(0))/T; the tapered
    // one (weights rising from the first sample and falling to the newest) loses the boundary terms
    // (issue 36, docs/FUSION.md "Dropouts"). Both give a constant input back exactly.
    const double dt = 1.0 / 285.714, g = 9.81;
    auto meanTilt = [&](bool tapered, double from, double to) {
        ButterworthLowPass3 lp;
        lp.setup(3.0, dt);
        lp.setTaperedStart(tapered);
        double sum = 0.0;
        int n = 0;
        for (int i = 0; i * dt < to; ++i) {
            const double t = i * dt;
            const double dv = 1.0 * 2 * kPi * std::cos(2 * kPi * t + 1.0);   // v = sin(2π t + 1) m/s
            const Eigen::Vector3d y = lp.filter(Eigen::Vector3d(dv, g, 0.3 * dv));
            if (t >= from) {
                sum += std::acos(std::clamp(y.normalized().y(), -1.0, 1.0));
                ++n;
            }
        }
        return radToDeg(sum / n);
    };
    const double plain = meanTilt(false, 1.0, 3.0), tapered = meanTilt(true, 1.0, 3.0);
    INFO("mean tilt error 1–3 s after the restart: plain mean " << plain << "°, tapered " << tapered << "°");
    CHECK(plain > 2.0);              // the probe: the plain mean carries Δv/T (measured 2.74°)
    CHECK(tapered < 0.6 * plain);    // measured 1.28°
    for (const bool tapered2 : {false, true}) {
        ButterworthLowPass3 lp;
        lp.setup(3.0, dt);
        lp.setTaperedStart(tapered2);
        Eigen::Vector3d y;
        for (int i = 0; i < 200; ++i) y = lp.filter(Eigen::Vector3d(1.0, 2.0, 3.0));
        CHECK((y - Eigen::Vector3d(1.0, 2.0, 3.0)).norm() < 1e-12);
    }
}

TEST_CASE("drift bias: a turning arm's power-up gyro bias from the drift of gravity and field, with an honest covariance", "[fusion][trackers]")
{
    using Eigen::Quaterniond;
    using Eigen::Vector3d;
    // An arm turning about two axes, gyro with bias b, clean gravity and field (a simulator's arm):
    // one second pins b down to a few hundredths of a degree per second. The same arm carrying a
    // slow linear acceleration of 2 m/s² (0.5 Hz): the estimate is worse, and its covariance says so.
    const Vector3d b(0.03, -0.02, 0.015);
    const Vector3d up(0.0, 9.81, 0.0), north(0.0, -0.8, -0.6);
    for (const double lin : {0.0, 2.0}) {
        INFO("linear acceleration " << lin << " m/s²");
        std::mt19937 rng(7);
        std::normal_distribution<double> n(0.0, 1.0);
        auto noise = [&](double s) -> Vector3d { return Vector3d(n(rng), n(rng), n(rng)) * s; };
        GyroDriftBias est;
        est.start(Vector3d::Zero(), 1.0);
        Quaterniond q = Quaterniond::Identity();   // device → earth
        const double dt = 1.0 / 250.0;
        bool done = false;
        for (int k = 0; k < 1000 && !done; ++k) {
            const double t = k * dt;
            const Vector3d w(0.5 * std::cos(1.3 * t), 0.4 * std::sin(0.9 * t), 0.2);
            if (k > 0) q = (q * Quaterniond(Eigen::AngleAxisd(w.norm() * dt, w.normalized()))).normalized();
            const Vector3d a = q.conjugate() * (up + Vector3d(lin * std::sin(3.1 * t), 0.0, lin * std::cos(3.1 * t))) + noise(0.04);
            const Vector3d m = q.conjugate() * north + noise(0.004);
            done = est.update(k == 0 ? 1e-9 : dt, w + b + noise(0.006), a, m);
        }
        REQUIRE(done);
        REQUIRE(est.estimated());
        const Vector3d e = est.bias() - b;
        const double nis = e.dot(est.covariance().ldlt().solve(e));
        INFO("estimate " << est.bias().transpose() << ", sd " << est.covariance().diagonal().cwiseSqrt().transpose() << ", NIS " << nis);
        CHECK(nis < 16.0);   // χ²(3) 99.9 %: the covariance is honest
        if (lin == 0.0) CHECK(e.norm() < 0.002);
        else CHECK(est.covariance().trace() > 1e-6);
    }
}
