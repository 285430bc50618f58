#pragma once
// The two slow trackers of thesis §2.6.8, kept apart from the SR-UKF so each is tested alone.
//  - GyroBiasTracker: the thesis's running mean of the gyro (~500 samples, ~2.5 s), taken only
//    while the device rests (rest detection is the departure: a mean over motion is the motion).
//  - MagneticFieldTracker: the thesis's low-pass of the dip acos(a·m/|a||m|), skipping samples
//    whose |a| is far from 1 g, plus the field norm; both serve as the reference that tells a
//    clean magnetometer sample from a disturbed one (departure, docs/FUSION.md).
// Params (units in the comments) / State, no heap.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <limits>
#include <vector>

namespace armadillo::fusion {

class GyroBiasTracker {
public:
    struct Params {
        double restGyroDeviation = 0.035;   ///< rad/s: |gyro − low-pass gyro| below this counts as still (2°/s)
        double restAccelDeviation = 0.5;    ///< m/s²: |accel − low-pass accel| below this counts as still
        double restFilterTau = 0.5;         ///< s: time constant of the low-pass filters above
        double minRestTime = 1.5;           ///< s: rest must last this long before the mean is trusted
        int windowSamples = 500;            ///< samples: length of the running mean (thesis §2.6.8)
    };
    struct State {
        Eigen::Vector3d gyroLowPass = Eigen::Vector3d::Zero();    ///< rad/s
        Eigen::Vector3d accelLowPass = Eigen::Vector3d::Zero();   ///< m/s²
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();           ///< rad/s, running mean while still
        double restTime = 0.0;                                    ///< s, how long the device has been still
        int samples = 0;                                          ///< samples in the running mean (≤ window)
        bool primed = false;                                      ///< low-pass filters initialised
    };

    GyroBiasTracker();
    explicit GyroBiasTracker(const Params& p) : params_(p) {}
    void reset() { state_ = State {}; }
    /// Feeds one sample (rad/s, m/s², s). Returns true when the device has rested at least
    /// minRestTime: then bias() is a usable estimate.
    bool update(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, double dt);
    bool atRest() const noexcept { return state_.restTime >= params_.minRestTime && state_.samples > 0; }
    const Eigen::Vector3d& bias() const noexcept { return state_.mean; }
    int samples() const noexcept { return state_.samples; }
    const State& state() const noexcept { return state_; }
    const Params& params() const noexcept { return params_; }

private:
    Params params_;
    State state_ {};
};

class MagneticFieldTracker {
public:
    struct Params {
        double tau = 10.0;                   ///< s: low-pass time constant of the reference norm and dip
        double accelTolerance = 0.05;        ///< fraction of g: dip is measured only while ||a|−g| < this·g
        double normTolerance = 0.10;         ///< fraction: |m| further than this from the reference = disturbed
        double dipTolerance = 0.1745;        ///< rad: dip further than this (10°) from the reference = disturbed
        double newFieldTime = 20.0;          ///< s: a different but steady field for this long becomes the reference
        double candidateTau = 2.0;           ///< s: low-pass of the candidate (disturbed) field
    };
    struct State {
        double norm = 0.0;             ///< reference |m|, the input's unit
        double dip = 0.0;              ///< reference angle between up (accel) and m, rad (≈ 90° + inclination)
        bool haveNorm = false, haveDip = false;
        double candidateNorm = 0.0, candidateDip = 0.0;
        bool candidateDipValid = false;
        double candidateTime = 0.0;    ///< s the candidate field has been steady
        double disturbedTime = 0.0;    ///< s since the last clean sample
    };

    MagneticFieldTracker();
    explicit MagneticFieldTracker(const Params& p) : params_(p) {}
    void reset() { state_ = State {}; }
    /// Feeds one sample (accel m/s², mag any unit, dt s). Returns true when the sample agrees with
    /// the reference (use it), false when it looks disturbed (skip it).
    bool update(const Eigen::Vector3d& accel, const Eigen::Vector3d& mag, double dt);
    /// Angle between up and the field measured from one sample, rad; NaN if undefined.
    static double dipAngle(const Eigen::Vector3d& accel, const Eigen::Vector3d& mag);
    double referenceDip() const noexcept { return state_.dip; }
    double referenceNorm() const noexcept { return state_.norm; }
    bool haveDip() const noexcept { return state_.haveDip; }
    double disturbedTime() const noexcept { return state_.disturbedTime; }
    const State& state() const noexcept { return state_; }
    const Params& params() const noexcept { return params_; }

private:
    Params params_;
    State state_ {};
};

} // namespace armadillo::fusion

namespace armadillo::fusion {

/// Second-order Butterworth low-pass of 3-vectors (bilinear transform), coefficients derived once
/// for a sample period; state can be primed with a steady value. No heap.
///
/// After reset() it starts the way VQF starts its filters: for the first tau seconds the output
/// is the plain mean of the samples so far, which then primes the filter. A filter primed with its
/// first sample would carry that one sample's error for seconds (after a dropout, a sample of a
/// moving arm with 2 g of linear acceleration); the mean's error shrinks as 1/time.
class ButterworthLowPass3 {
public:
    /// tau: time constant (s) as VQF defines it, cutoff fc = √2 / (2π tau); dt: sample period (s).
    void setup(double tau, double dt);
    void prime(const Eigen::Vector3d& steady);
    Eigen::Vector3d filter(const Eigen::Vector3d& x);
    bool primed() const noexcept { return primed_; }
    /// Tapered start-up mean (weights rising from the first sample and falling to the newest) instead
    /// of the plain one: for a vector that is a derivative (acceleration), the plain mean's error is
    /// the change of its integral (Δv) over the window, the tapered one's only what oscillates.
    void setTaperedStart(bool on) { tapered_ = on; }
    void reset() { primed_ = false; sum0_.setZero(); sum1_.setZero(); sum2_.setZero(); count_ = 0; }

private:
    double b0_ = 1.0, b1_ = 0.0, b2_ = 0.0, a1_ = 0.0, a2_ = 0.0;
    double tau_ = 0.0, dt_ = 0.0;
    Eigen::Vector3d s1_ = Eigen::Vector3d::Zero(), s2_ = Eigen::Vector3d::Zero();   // direct form II transposed
    // Start-up mean, tapered at both ends: Σ (k+1)(n−k) x_k over the n samples so far, kept as the
    // moments Σ x_k, Σ k x_k, Σ k² x_k.
    Eigen::Vector3d sum0_ = Eigen::Vector3d::Zero(), sum1_ = Eigen::Vector3d::Zero(), sum2_ = Eigen::Vector3d::Zero();
    long count_ = 0;
    bool primed_ = false;
    bool tapered_ = false;
};


/// The gyro bias from the drift of gravity and of the field in a gyro-only frame (issue 49): over
/// a window the frame R(t) is integrated from the gyro less a fixed b0; if the true bias is
/// b0 + e the frame turns away from the earth by φ(t) = A(t) e, A(t) = ∫R dt (first order), so
/// a unit accelerometer sample seen in it reads u = g − [g]× A e (g constant: gravity) and a unit
/// field sample v = f − [f]× A e. Least squares for (g, f, e) and a timing offset δ (column
/// R (ω × sample): the samples taken a little before or after the frame's turn), each sensor weighed by its
/// residuals' variance inflated for their lag-1 correlation ((1+ρ)/(1−ρ): linear acceleration is
/// slow, sensor noise white), gives e and its covariance from the data alone: a clean signal (a
/// simulator's arm, a still arm) pins the bias down within a second, a translating arm says its
/// estimate is worth little. Accelerometer samples off 1 g by more than setAccelTolerance, and
/// readings repeated exactly (held by a slower stream), are left out. A buffer, sized once, holds the window (no allocation per sample).
class GyroDriftBias {
public:
    explicit GyroDriftBias(std::size_t capacity = 1024) : capacity_(capacity) { rows_.reserve(capacity); }
    /// Starts a window of `seconds` integrating gyro − b0.
    void start(const Eigen::Vector3d& b0, double seconds);
    /// Feeds one sample (dt s, gyro rad/s, accel m/s², mag any unit or NaN when untrusted).
    /// Returns true when the window has closed (its length reached or the buffer full): then
    /// bias() and covariance() hold the estimate if estimated() (else the window said nothing).
    bool update(double dt, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, const Eigen::Vector3d& mag);
    /// Fraction of g: an accelerometer sample further than this from 1 g is left out of the fit
    /// (linear acceleration: a punch, a swing's pull).
    void setAccelTolerance(double fraction) noexcept { accelTolerance_ = fraction; }
    bool estimated() const noexcept { return estimated_; }
    const Eigen::Vector3d& bias() const noexcept { return bias_; }
    const Eigen::Matrix3d& covariance() const noexcept { return cov_; }

private:
    struct Row {
        Eigen::Matrix3d A;
        Eigen::Vector3d u, v;     ///< unit accelerometer and field samples in the gyro-only frame
        Eigen::Vector3d cu, cv;   ///< their change per second of timing offset, R (ω × sample)
        bool field;
        bool gravity;   ///< |a| within accelTolerance of 1 g
    };
    void solve();
    std::size_t capacity_;
    std::vector<Row> rows_;
    Eigen::Quaterniond R_ = Eigen::Quaterniond::Identity();
    Eigen::Matrix3d A_ = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b0_ = Eigen::Vector3d::Zero(), bias_ = Eigen::Vector3d::Zero();
    Eigen::Matrix3d cov_ = Eigen::Matrix3d::Identity();
    double age_ = 0.0, length_ = 0.0;
    double accelTolerance_ = 0.05;
    Eigen::Vector3d lastAccel_ = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    Eigen::Vector3d lastMag_ = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    bool estimated_ = false;
};

} // namespace armadillo::fusion
