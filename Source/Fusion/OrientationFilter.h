#pragma once
// The forearm's orientation from gyro, accelerometer and (optional) magnetometer: the
// square-root UKF of thesis §2.7 on (q, gyro bias), the gyro as the process model's input (the
// thesis's state is (q, ω, α); departure 12), with the trackers of §2.6.8.
// docs/FUSION.md explains every departure from the thesis and why.
//
// Frames (INTERFACES.md): device x toward the hand, y out of the board's face, z = x × y;
// earth X east, Y up, Z south (magnetic north is −Z). orientation() maps device → earth.
//
// Real-time safe: update() allocates nothing (tested), takes dt from successive timestamps,
// initialises from the first usable accelerometer (+ magnetometer) sample, skips and counts
// unusable samples (NaN, time not increasing), and re-acquires after gaps and disagreements:
// a gap longer than `maxBridge` (or a state that measurements contradict for
// `disagreementTime`) starts again from gravity and the field as at start-up, keeping the gyro
// bias (docs/FUSION.md, "Dropouts and re-acquisition").
#include "Core/GapDetector.h"
#include "Core/Types.h"
#include "Fusion/OrientationModels.h"
#include "Fusion/SquareRootUkf.h"
#include "Fusion/Trackers.h"
#include <Eigen/Geometry>
#include <cstddef>
#include <string>
#include <vector>

namespace armadillo::fusion {

class OrientationFilter {
public:
    struct Params {
        UkfWeights ukf {};                    ///< sigma-point α, β, κ and mean iterations

        // Process noise (continuous-time densities; the step's std is density·√dt). The gyroscope
        // is the process model's input (departure 12): ω and α are not states, and their random
        // changes only matter where the rotation is extrapolated with them, over a bridged gap.
        double rotationNoise = 3e-3;          ///< rad/√s: rotation the gyro does not explain (1e-3 with
                                              ///< ω and α as states, whose uncertainty added about as much)
        double rateNoise = 3.0;               ///< rad/s/√s: random change of ω (bridged gaps)
        double angularAccelNoise = 30.0;      ///< rad/s²/√s: random walk of α (bridged gaps)
        double biasNoise = 2e-5;              ///< rad/s/√s: random walk of the gyro bias

        // Mechanical shocks (a tap on the arm, a knock against something): the accelerometer jumps
        // by many g from one sample to the next, and the gyro misreads the impact for a few
        // milliseconds (shock response, saturation). Modelled as extra rotation process noise for
        // that step, proportional to the jump beyond the threshold (docs/FUSION.md, issue 36).
        double shockThreshold = 3.0;          ///< g: accelerometer change between successive samples (BROAD:
                                              ///< ≤ 2.0 g without taps, in the fast-rotation trial; up to 28 g in taps)
        double shockRotationNoise = 1e-3;     ///< rad (std, this step) per g of change beyond the threshold
        bool shockRestartsFieldLowPass = true;///< a shock also empties the magnetometer's low-pass (below)

        // Measurement noise (standard deviations per sample).
        double gyroNoise = 0.003;             ///< rad/s, white noise of the rate (turns the state by gyroNoise·dt)
        double accelFilterTau = 3.0;          ///< s: 2nd-order low-pass of the accelerometer in a gyro-only
                                              ///< (inertial) frame before it is used as gravity (departure)
        double magFilterTau = 6.0;            ///< s: the same for the magnetometer (accepted samples only;
                                              ///< 3 s until issue 36: longer averages an orientation-
                                              ///< dependent field error away, docs/FUSION.md)
        bool accelTaperedStart = true;        ///< the accelerometer's low-pass starts with a tapered mean
                                              ///< (Trackers.h; after a gap in a moving arm, docs/FUSION.md)
        double magDisagreementTau = 3.0;      ///< s: the field's average that the heading-disagreement rule watches
        double startupFilterSeconds = 10.0;   ///< s: both time constants grow from 10 % to full over this
                                              ///< time after initialisation (0 = full from the start)
        double gravityNoise = 0.025;          ///< unit-vector components (≈ rad) of the filtered a/|a|
                                              ///< (0.05 until issue 36; with the rotation noise above)
        double youngAverageVelocity = 0.5;    ///< m/s: velocity change the accelerometer's young average may
                                              ///< carry: its direction is off by up to this/(g·T) after T s of
                                              ///< averaging, added to the gravity noise (docs/FUSION.md, issue 36)
        double youngMaxVelocity = 2.0;        ///< m/s: the most a fast arm's velocity can change (a fast gesture's
                                              ///< speed). The young average's Δv is taken as the linear acceleration
                                              ///< seen since it restarted (∫ ||a| − g| dt), at least youngAverageVelocity
                                              ///< and at most this (issue 49: a translating arm's young average is
                                              ///< 30–150° off for half a second; 0.5 m/s says 29° at 0.1 s, 6° at 0.5 s)
        /// s: the time scale of an arm's movement, 1/(2π · 1 Hz). After a gap the young average's Δv is its
        /// samples' spread about their mean in the inertial frame (σ_a, the linear acceleration left after
        /// the lever arm) times this: the velocity amplitude of a movement with that acceleration, at least
        /// youngSpreadFloor, at most youngMaxVelocity (issue 49, third session: on the dev trials' 54 gaps
        /// the young average's error is σ_a·(0.09–0.16 s)/(g·T) in the median at every age from 0.1 to 3 s,
        /// log-correlation 0.8–0.9 in the first half second, against 0.2–0.65 for ∫ ||a| − g| dt, which
        /// misses acceleration across gravity). 0: the ∫ ||a| − g| dt rule after gaps too. At start-up
        /// the ∫ ||a| − g| dt rule stays (the start-up's acquisition was tuned with it; no prior to weigh).
        double youngMotionTime = 0.159;
        double youngSpreadFloor = 0.1;        ///< m/s: the least Δv the spread rule gives (a few samples' spread
                                              ///< is no proof of a still arm)
        /// After a gap the young average's error is one error, not a new one each sample: it stays for its
        /// age T while younger than youngMotionTime, and for about youngMotionTime after. A per-sample
        /// update counts it min(T, youngMotionTime)/dt times, so its noise is raised by √ of that (only
        /// after gaps: at start-up there is no prior orientation for the young average to be weighed against).
        bool youngCorrelated = true;
        // The accelerometer sits at a lever arm r from the centre the arm turns about (elbow, shoulder,
        // wrist): it reads ω×(ω×r) + α×r besides gravity and the centre's own acceleration. r (device
        // frame) is learned by least squares from the steady filter (specific force less the state's
        // gravity against [ω]×² + [α]×, forgetting over leverArmTau), and the turn's acceleration the
        // gyro predicts is taken off every sample before it is averaged as gravity (issue 49: in the
        // stationary-magnet trial a 0.13–0.15 m lever arm explains half the linear acceleration).
        double leverArmTau = 20.0;            ///< s (0: no lever arm)
        double leverArmPrior = 1.0;           ///< (rad/s²)²: ridge toward r = 0 (the motion must exceed this to
                                              ///< make r observable: ω² or α of about 1 rad/s² and up)
        // A magnet carried with the sensor (hard iron) adds a field h fixed in the device frame: the
        // magnetometer reads Rᵀ m_earth + h. Learned by least squares from the steady filter over the
        // arm's turns (forgetting over hardIronTau; ridge hardIronPrior toward h = 0, so that an arm
        // that does not turn leaves it at 0) and taken off the field while its averages are young:
        // a long average in the inertial frame cancels h as the arm turns, a young one does not
        // (issue 49: trial 34, attached magnet, 1–3 s after a gap at 80 s, 20–26° → 8–12°).
        double hardIronTau = 20.0;            ///< s (0: no hard-iron estimate)
        double hardIronPrior = 0.1;           ///< ridge on h (the information of a unit turn is ≈ 1)
        double gravityNormGain = 4.0;         ///< noise ×(1 + gain·||a|−g|/g): linear acceleration shows in |a|
        double gravityNisLimit = 12.0;        ///< χ²(3) soft gate on the gravity innovation (inflate beyond)
        double headingNoise = 0.6;            ///< rad, heading from the horizontal field (slow: τ ≈ 10–20 s)
        double headingNisLimit = 9.0;         ///< χ²(1) soft gate on the heading innovation
        double biasObservationNoise = 0.005;  ///< rad/s, bias tracker's mean used while at rest
        /// s: the first window of the power-up drift estimate of the gyro bias (GyroDriftBias, Trackers.h;
        /// issue 49): from start-up, driftBiasWindows windows (the first two this long, then each twice
        /// the one before, at most driftBiasMaxWindow) each give the bias with the covariance their
        /// residuals say (0: none). A window is observed only if it proves the filter's bias wrong
        /// (the filter's value outside its driftBiasProof region) and the window before proved the same
        /// and agrees with it: a real power-up bias persists, a window fooled by the motion (the OSC
        /// senders' wandering arm, whose phones send bias-free rates) is not repeated by the next one.
        double driftBiasWindow = 0.5;
        double driftBiasWindows = 4.0;        ///< windows (0.5, 0.5, 1, 2 s: the first 4 s)
        double driftBiasMaxWindow = 4.0;      ///< s: windows grow to this length
        double driftBiasProof = 11.34;        ///< χ²(3) at 99 %: proof that the filter's bias is wrong; agreement of two windows
        double driftBiasNisLimit = 12.0;      ///< χ²(3) soft gate of a window's estimate against the filter's bias

        // Initial standard deviations (start-up and every re-acquisition). Wide enough that the
        // first measurements win; no wider, because sigma points sit at ±√12·σ and heading wraps at π.
        double initialTiltStd = 0.3;          ///< rad
        double initialHeadingStd = 0.35;      ///< rad
        double initialBiasStd = 0.01;         ///< rad/s

        core::GapDetector::Params gap {};     ///< what a dropout is (Core/GapDetector.h: 4 × the typical step, ≥ 30 ms)
        double reacquireAccelTolerance = 0.2; ///< fraction of g: a sample whose |a| is further off gives no tilt
        double maxBridge = 0.04;              ///< s: longer gaps re-acquire; shorter ones are extrapolated
                                              ///< with ω and α (what they can honestly carry, docs/FUSION.md)
        // Re-acquisition's joint gravity + heading step: reacquireWindow after the data returns, the
        // young averages of accelerometer and field give an orientation; the state moves towards it
        // by as much as their disagreement exceeds what the averages can be trusted for (the gyro is
        // gone over the gap, so how far the arm turned shows only in that disagreement).
        double reacquireWindow = 0.1;         ///< s of samples averaged before the step (0: no step)
        /// The joint step is repeated at reacquireRepeat × the previous step's age (0.1, 0.2, 0.4, 0.8,
        /// 1.6 s) while acquiring: the prior before the gap and the maturing averages weighed afresh,
        /// once each (0 or ≤ 1: once).
        double reacquireRepeat = 2.0;
        /// s: the range of orientations the arm has been moving in (the steady filter's mean rotation
        /// matrix over this time). After a gap the arm is somewhere in it: the orientation before the gap
        /// is trusted to the lesser of (rate × gap) and the range's spread (0: rate × gap only).
        double rangeTau = 10.0;
        double reacquireHeadingNoise = 0.1;   ///< rad: heading error of the young field average itself
                                              ///< (with reacquireFieldVector: its direction error)
        // The step as one least-squares rotation (Wahba's problem) from three sources at once: the
        // orientation before the gap turned by the gyro since (trusted as far as the arm can have
        // turned during the gap: its rate before and after the gap times the gap's length), the
        // young gravity average, and the young field average as a whole direction (the field's
        // reference dip from the field tracker): a clean field fixes two of the three axes at
        // once, whatever the accelerometer's linear acceleration. false: the tilt-then-heading
        // step of the first issue-49 session (the young field projected on the young tilt).
        bool reacquireFieldVector = true;
        /// While acquiring after a gap, a trusted field is observed as a whole direction (tilt and
        /// heading, noise reacquireHeadingNoise) instead of its heading only: the young gravity
        /// average of a moving arm is tens of degrees off for the first second, the field is not.
        bool acquireFieldVector = true;
        // Gates reject outliers, never the truth: a state that the (trusted) measurements contradict
        // by more than these angles without a break for disagreementTime is re-acquired.
        double disagreementTime = 1.5;        ///< s
        double acquireDisagreementTime = 0.25;///< s, the same during acquisition (below): nothing is known yet
        // Acquisition: right after start-up or a re-acquisition, extra rotation noise keeps the
        // covariance open, so that heading and tilt follow the measurements while the low-pass
        // fills (the first samples of a moving arm are biased by linear acceleration, and a
        // collapsed covariance would hold on to that bias). Fades linearly to 0 over acquireTime.
        double acquireRotationNoise = 0.5;    ///< rad/√s at the start of acquisition
        double acquireTime = 3.0;             ///< s
        /// After a gap the acquisition noise holds its full value for acquireTime instead of fading
        /// (issue 49, fourth session: the young averages mature over those seconds, and a state that
        /// stops following them at 1–2 s keeps their early error; bench_gaps 1–3 s 3.21° → 3.05°,
        /// better in 5 of the 6 trials, the first second 9.32° → 9.39°). Start-up still fades.
        bool acquireHoldAfterGap = true;
        /// After a gap the young field average is a direction against the field as the steady filter
        /// last saw it in the earth frame (its 6 s average turned by the state before the gap),
        /// instead of magnetic north at the reference dip (joint step and acquisition). The arm is
        /// where it was a moment ago, and so is any local bend of the field (a magnet, steel near
        /// the performer), which the steady filter had already averaged past (issue 49, fifth
        /// session: bench_gaps 1–3 s 3.04° → 2.71°, 0–1 s 9.49° → 9.27°; trial 29's bent field,
        /// 1 s gap at 80 s, 5.39° → 2.28°). Taken only from a steady filter (a gap while still
        /// acquiring keeps the one from before).
        bool reacquireKeepField = true;
        double headingDisagreement = 0.35;    ///< rad (20°) between the field's heading and the state's
        double headingConsistency = 0.15;     ///< rad: the run's innovations stay this close to their mean
        double tiltDisagreement = 0.26;       ///< rad (15°) between low-passed gravity and the state's
        double minHorizontalField = 0.1;      ///< fraction of |m|: less horizontal field ⇒ no heading
        bool useMagnetometer = true;          ///< false: 6-axis (heading from the gyro alone)
        /// true: gyro at t_k is the mean rate over [t_{k-1}, t_k] (the step turns by ω_k t); false
        /// (issue 49, fifth session): it is the rate at the instant t_k, as phones, the thesis board's
        /// ADC and MEMS gyros sample it, and the step is the trapezoid of ω_{k-1} and ω_k. With true, a
        /// 10 Hz phone's state ran half a sample (50 ms) ahead and the bias state learnt the
        /// difference (ZIG SIM at 10 Hz 2.84°, now 1.72°; docs/FUSION.md, departure 12).
        bool gyroCoversPrecedingInterval = false;
        /// s: orientation() is the state turned on by the rate over this time: the sensor's own delay
        /// (a MEMS gyro's digital low-pass lags the motion by a few ms). With the trapezoid step BROAD
        /// gives 1.607° without a lead, 1.211° with 3 ms, 1.177° with 3.5 ms, 1.158° with 4 ms, 1.155°
        /// with 4.5 ms; an ideal sensor has none, and the thesis's 12 rad/s swings (Tests/Fusion) allow
        /// 3.5 ms within their 3° (2.38°; 4 ms: 3.05°).
        double outputLead = 0.0035;

        GyroBiasTracker::Params bias {};
        MagneticFieldTracker::Params field {};
    };
    static const Params& defaultParams();
    /// Sets one numeric parameter by its member name (`rotationNoise`, `field.normTolerance`, …;
    /// booleans as 0/1): for tuning and cross-validation runs (`armadillo fuse --param`). Returns
    /// false for an unknown name. parameterNames() lists them.
    static bool setParameter(Params& p, const std::string& name, double value);
    static std::vector<std::string> parameterNames();

    explicit OrientationFilter(const Params& p = defaultParams());
    void reset();
    void update(const core::ImuSample& s);

    Eigen::Quaterniond orientation() const;          ///< device → earth (X east, Y up, Z south)
    Eigen::Vector3d angularVelocity() const;         ///< rad/s, device frame, bias removed
    Eigen::Vector3d gyroBias() const;                ///< rad/s, device frame
    /// m, device frame: the lever arm learned so far (leverArmTau; solved when asked: the filter
    /// needs it only while the accelerometer's average is young).
    Eigen::Vector3d leverArm() const;
    /// The magnetometer's hard-iron offset learned so far (its unit; hardIronTau), solved when asked.
    Eigen::Vector3d hardIron() const;
    bool initialised() const { return initialised_; }
    std::size_t skippedSamples() const { return skipped_; }
    std::size_t magneticRejections() const { return magRejected_; }
    /// s since the last magnetometer sample that agreed with the learned field (0 = trusted now).
    double magneticDisturbedTime() const { return fieldTracker_.disturbedTime(); }
    /// What the filter did about dropouts and disagreements (counts since reset()).
    struct Recovery {
        std::size_t gaps = 0;            ///< steps longer than the gap threshold
        std::size_t bridged = 0;         ///< … extrapolated (≤ maxBridge)
        std::size_t reacquired = 0;      ///< … too long: started again from gravity and field
        std::size_t headingResets = 0;   ///< heading re-acquired after persistent disagreement
        std::size_t tiltResets = 0;      ///< tilt re-acquired after persistent disagreement
        std::size_t reacquireSteps = 0;  ///< joint gravity + heading steps that moved the state (re-acquisition)
        double longestGap = 0.0;         ///< s
    };
    const Recovery& recovery() const { return recovery_; }
    const UkfStats& ukfStats() const { return ukf_.stats(); }
    const Params& params() const { return params_; }
    /// Error-state covariance (6×6: rotation rad, gyro bias rad/s; AttitudeErrorIndex).
    Eigen::Matrix<double, kAttDim, kAttDim> covariance() const { return ukf_.covariance(); }

private:
    void initialise(const core::ImuSample& s);
    /// Starts again from this sample (tilt at once, heading once the field is trusted), wide
    /// covariance, gyro bias kept, low-pass restarted.
    void reacquire(const core::ImuSample& s, double gap);
    void resetCovariance(double rotationStd);
    /// 1 right after start-up or a re-acquisition, falling to 0 over acquireTime.
    double acquiring() const;
    double disagreementLimit() const;
    /// Turns the state by the gyro `gyro` (rad/s, bias included) over dt, extrapolating with α
    /// `accel` (rad/s², non-zero only over a bridged gap, where `bridge` adds the noise of that).
    void predict(double dt, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, double shock, bool bridge);
    void updateGravity(const Eigen::Vector3d& accelSmooth, double rawNorm, double dt, bool tiltRule = true, double extraStd = 0.0);
    void updateHeading(const Eigen::Vector3d& mag, const Eigen::Vector3d& magFast, double dt);
    void restartInertialFrame();
    /// The joint gravity + heading step of a re-acquisition (docs/FUSION.md): `up` and `field`
    /// (device frame; field NaN when none was trusted) are the young averages.
    void reacquireStep(const Eigen::Vector3d& up, const Eigen::Vector3d& field);
    void reacquireStepJoint(const Eigen::Vector3d& up, const Eigen::Vector3d& field);
    void setupLowPass(double dt);
    /// The accelerometer sample less the turn's acceleration at the learned lever arm while the
    /// average is young (learning r from the steady filter unless `unsteady`: shock, gap).
    Eigen::Vector3d withoutTurnAcceleration(const core::ImuSample& s, double dt, bool unsteady);
    /// The magnetometer sample less the learned hard-iron offset while the averages are young.
    Eigen::Vector3d withoutHardIron(const Eigen::Vector3d& mag, double dt, bool gap);

    Params params_;
    SquareRootUkf<AttitudeSpace> ukf_;
    GyroBiasTracker biasTracker_;
    GyroDriftBias driftBias_;
    bool driftBiasActive_ = false;    ///< a power-up drift window is open
    double driftBiasNext_ = 0.0;      ///< s, the next window's length
    int driftBiasWindows_ = 0;        ///< windows closed since start-up
    bool driftPrevProved_ = false;    ///< the window before proved the filter's bias wrong
    Eigen::Vector3d driftPrevBias_ = Eigen::Vector3d::Zero();
    Eigen::Matrix3d driftPrevCov_ = Eigen::Matrix3d::Identity();
    void startDriftWindow();
    void updateDriftBias(const core::ImuSample& s, double dt, bool gap, bool shock, bool fieldTrusted);
    MagneticFieldTracker fieldTracker_;
    // Gyro-only strapdown orientation (device → a non-rotating frame) in which accelerometer and
    // magnetometer are low-passed: linear acceleration integrates away there, gravity does not.
    Eigen::Quaterniond inertial_ = Eigen::Quaterniond::Identity();
    Eigen::Vector3d fieldEarthAtGap_ = Eigen::Vector3d::Constant(core::kNaN);   ///< unit, earth frame (reacquireKeepField)
    ButterworthLowPass3 accelLowPass_, magLowPass_;
    // The field averaged at the shorter magDisagreementTau: what the heading-disagreement rule
    // watches (a changed field must show within seconds; the long average is for the estimate).
    ButterworthLowPass3 magFastLowPass_;
    double lowPassDt_ = 0.0;   ///< s, the step the coefficients were derived for
    double lowPassRamp_ = 1.0; ///< start-up fraction of the time constants they were derived for
    double initT_ = 0.0;       ///< s, time of the initialising sample (start of the low-pass ramp)
    double acquireStartT_ = 0.0;   ///< s, start of the latest acquisition: start-up, gap, re-acquisition
    double accelAverageStartT_ = 0.0;   ///< s, when the accelerometer's low-pass last restarted
    // Σ AᵀA and Σ Aᵀm for A = [Rᵀ | I] (forgetting): AᵀA = [[I, R], [Rᵀ, I]], so the weight, the
    // mean R, the mean R m and the mean m are all it takes.
    double hardIronW_ = 0.0;
    Eigen::Matrix3d hardIronR_ = Eigen::Matrix3d::Zero();
    Eigen::Vector3d hardIronRm_ = Eigen::Vector3d::Zero(), hardIronM_ = Eigen::Vector3d::Zero();
    Eigen::Matrix3d leverH_ = Eigen::Matrix3d::Zero();   ///< Σ MᵀM (forgetting), M = [ω]×² + [α]×
    Eigen::Vector3d leverY_ = Eigen::Vector3d::Zero();   ///< Σ Mᵀ (a − gravity)
    Eigen::Vector3d youngSum_ = Eigen::Vector3d::Zero();   ///< Σ a (inertial frame) since the average restarted
    double youngSumSq_ = 0.0, youngN_ = 0.0;                ///< Σ |a|², number of samples
    double rangeW_ = 0.0;               ///< weight of rangeR_ (forgetting over rangeTau)
    Eigen::Matrix3d rangeR_ = Eigen::Matrix3d::Zero();   ///< mean rotation matrix (device → earth), steady filter
    double rangeAtGap_ = 1e9;           ///< rad: how far apart two orientations of that range are (at the gap)
    double reacquireNextAge_ = 0.0;     ///< s after the gap's end: the next joint step
    double youngDv_ = 0.0;              ///< m/s, ∫ ||a| − g| dt since then (capped at youngMaxVelocity)
    /// m/s: the velocity change the accelerometer's young average may carry (youngAverageVelocity …
    /// youngMaxVelocity, from the linear acceleration seen since it restarted).
    double youngVelocity() const;
    /// Unit, earth frame: what the young field average is taken against after a gap: the field as the
    /// steady filter last saw it (reacquireKeepField), else magnetic north at the reference dip.
    Eigen::Vector3d acquisitionFieldReference() const;
    double lastT_ = 0.0;
    Eigen::Vector3d lastAccel_ = Eigen::Vector3d::Constant(core::kNaN); ///< m/s², previous sample (shock detection)
    Eigen::Vector3d lastGyro_ = Eigen::Vector3d::Constant(core::kNaN); ///< rad/s, previous sample (α, timing)
    core::GapDetector gaps_;
    double headingDisagreeT_ = 0.0, tiltDisagreeT_ = 0.0;   ///< s of unbroken disagreement
    double headingDisagreeMean_ = 0.0;                       ///< rad, mean heading innovation of that run
    Recovery recovery_ {};
    // Re-acquisition's joint step, pending from the gap's end for reacquireWindow.
    bool reacquirePending_ = false;
    bool afterGap_ = false;            ///< the latest acquisition began at a gap (not at start-up)
    double reacquireStartT_ = 0.0;
    std::size_t reacquireSamples_ = 0, reacquireFieldSamples_ = 0;
    double gapLength_ = 0.0;          ///< s, the gap that started the pending step
    double rateBeforeGap_ = 0.0;      ///< rad/s, |ω| of the last sample before it
    double reacquireTurn_ = 0.0;      ///< rad, ∫|ω| dt over the step's window (the arm's rate after the gap)
    Eigen::Vector3d magAverageInertial_ = Eigen::Vector3d::Constant(core::kNaN);   ///< the long field average's latest output
    bool initialised_ = false;
    std::size_t skipped_ = 0;
    std::size_t magRejected_ = 0;
};

/// Orientation from one accelerometer (+ magnetometer) sample: tilt from gravity, heading from
/// the horizontal field (north = −Z); without a usable field the heading keeps the device's
/// x axis in the vertical plane through north. Returns false (and identity) if accel is unusable.
bool orientationFromVectors(const Eigen::Vector3d& accel, const Eigen::Vector3d& mag, Eigen::Quaterniond& q);

} // namespace armadillo::fusion
