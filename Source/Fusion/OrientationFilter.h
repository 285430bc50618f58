#pragma once
// The forearm's orientation from gyro, accelerometer and (optional) magnetometer: the
// square-root UKF of thesis §2.7 on (q, ω, α) plus the gyro bias, with the trackers of §2.6.8.
// docs/FUSION.md explains every departure from the thesis and why.
//
// Frames (INTERFACES.md): device x toward the hand, y out of the board's face, z = x × y;
// earth X east, Y up, Z south (magnetic north is −Z). orientation() maps device → earth.
//
// Real-time safe: update() allocates nothing (tested), takes dt from successive timestamps,
// initialises from the first usable accelerometer (+ magnetometer) sample, skips and counts
// unusable samples (NaN, time not increasing), and survives gaps.
#include "Core/Types.h"
#include "Fusion/OrientationModels.h"
#include "Fusion/SquareRootUkf.h"
#include "Fusion/Trackers.h"
#include <Eigen/Geometry>
#include <cstddef>

namespace armadillo {

class OrientationFilter {
public:
    struct Params {
        UkfWeights ukf {};                    ///< sigma-point α, β, κ and mean iterations

        // Process noise (continuous-time densities; the step's std is density·√dt).
        double rotationNoise = 1e-3;          ///< rad/√s: rotation not explained by ω, α
        double rateNoise = 3.0;               ///< rad/s/√s: random change of ω
        double angularAccelNoise = 30.0;      ///< rad/s²/√s: random walk of α (thesis: α' = α)
        double biasNoise = 2e-5;              ///< rad/s/√s: random walk of the gyro bias

        // Measurement noise (standard deviations per sample).
        double gyroNoise = 0.003;             ///< rad/s
        double accelFilterTau = 3.0;          ///< s: 2nd-order low-pass of the accelerometer in a gyro-only
                                              ///< (inertial) frame before it is used as gravity (departure)
        double magFilterTau = 3.0;            ///< s: the same for the magnetometer (accepted samples only)
        double startupFilterSeconds = 10.0;   ///< s: both time constants grow from 10 % to full over this
                                              ///< time after initialisation (0 = full from the start)
        double gravityNoise = 0.05;           ///< unit-vector components (≈ rad) of the filtered a/|a|
        double gravityNormGain = 4.0;         ///< noise ×(1 + gain·||a|−g|/g): linear acceleration shows in |a|
        double gravityNisLimit = 12.0;        ///< χ²(3) soft gate on the gravity innovation (inflate beyond)
        double headingNoise = 0.6;            ///< rad, heading from the horizontal field (slow: τ ≈ 10–20 s)
        double headingNisLimit = 9.0;         ///< χ²(1) soft gate on the heading innovation
        double biasObservationNoise = 0.005;  ///< rad/s, bias tracker's mean used while at rest

        // Initial standard deviations.
        double initialTiltStd = 0.05;         ///< rad
        double initialHeadingStd = 0.2;       ///< rad
        double initialRateStd = 0.1;          ///< rad/s
        double initialAngularAccelStd = 1.0;  ///< rad/s²
        double initialBiasStd = 0.01;         ///< rad/s

        double maxGap = 0.5;                  ///< s: a longer gap is not integrated (ω unknown there)
        double maxGapNoiseTime = 10.0;        ///< s: process noise of a gap is capped at this duration
        double minHorizontalField = 0.1;      ///< fraction of |m|: less horizontal field ⇒ no heading
        bool useMagnetometer = true;          ///< false: 6-axis (heading from the gyro alone)
        bool gyroCoversPrecedingInterval = true;  ///< gyro at t_k is the rate over [t_{k-1}, t_k]

        GyroBiasTracker::Params bias {};
        MagneticFieldTracker::Params field {};
    };
    static const Params& defaultParams();

    explicit OrientationFilter(const Params& p = defaultParams());
    void reset();
    void update(const ImuSample& s);

    Eigen::Quaterniond orientation() const;          ///< device → earth (X east, Y up, Z south)
    Eigen::Vector3d angularVelocity() const;         ///< rad/s, device frame, bias removed
    Eigen::Vector3d gyroBias() const;                ///< rad/s, device frame
    bool initialised() const { return initialised_; }
    std::size_t skippedSamples() const { return skipped_; }
    std::size_t magneticRejections() const { return magRejected_; }
    const UkfStats& ukfStats() const { return ukf_.stats(); }
    const Params& params() const { return params_; }
    /// Error-state covariance (12×12: rotation rad, ω rad/s, α rad/s², bias rad/s).
    Eigen::Matrix<double, kErrDim, kErrDim> covariance() const { return ukf_.covariance(); }

private:
    void initialise(const ImuSample& s);
    void predict(double dt);
    void updateGravity(const Eigen::Vector3d& accelSmooth, double rawNorm);
    void updateHeading(const Eigen::Vector3d& mag);
    void restartInertialFrame();
    void setupLowPass(double dt);

    Params params_;
    SquareRootUkf<OrientationSpace> ukf_;
    GyroBiasTracker biasTracker_;
    MagneticFieldTracker fieldTracker_;
    // Gyro-only strapdown orientation (device → a non-rotating frame) in which accelerometer and
    // magnetometer are low-passed: linear acceleration integrates away there, gravity does not.
    Eigen::Quaterniond inertial_ = Eigen::Quaterniond::Identity();
    ButterworthLowPass3 accelLowPass_, magLowPass_;
    double lowPassDt_ = 0.0;   ///< s, the step the coefficients were derived for
    double lowPassRamp_ = 1.0; ///< start-up fraction of the time constants they were derived for
    double initT_ = 0.0;       ///< s, time of the initialising sample
    double lastT_ = 0.0;
    bool initialised_ = false;
    std::size_t skipped_ = 0;
    std::size_t magRejected_ = 0;
};

/// Orientation from one accelerometer (+ magnetometer) sample: tilt from gravity, heading from
/// the horizontal field (north = −Z); without a usable field the heading keeps the device's
/// x axis in the vertical plane through north. Returns false (and identity) if accel is unusable.
bool orientationFromVectors(const Eigen::Vector3d& accel, const Eigen::Vector3d& mag, Eigen::Quaterniond& q);

} // namespace armadillo
