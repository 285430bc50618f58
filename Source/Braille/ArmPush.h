#pragma once
// "Here" answered by the arm (issue 26): the "button pushing" movement of thesis §2.6.3 — a
// quick push of the forearm along its own axis and back, like pressing a button. The thesis
// detects it as the accelerometer's forearm-axis component far from gravity's while the angular
// rate is low (a large angular rate means a swing, whose centripetal acceleration would look the
// same). Here gravity's forearm-axis component is the accelerometer's own, low-passed while no
// push is in progress (so no orientation or sign convention is needed, and a slow change of
// posture moves the baseline with it); a push is that component's departure beyond `accel` one
// way, then beyond `accel` the other way (the stop) between `minPush` and `maxPush` s later, with
// the angular rate below `maxRate` throughout (a tap on the device swings both ways within a few
// ms: too soon). It fires once, on the way back; another push is taken only after
// `refractory` s and a calm arm.
// Not a push: reading by roll (rotation about the forearm axis leaves the axial component of
// gravity alone), a twist (angular rate far above maxRate), a slow posture change (followed by
// the baseline, one way only), sensor noise (well below `accel`).
// Real-time: plain arithmetic on scalars (the braille scene's control, the device link's thread).
namespace armadillo::braille {

struct PushParams {
    double accel = 4.0;        ///< m/s² from gravity's forearm-axis component, each way (≈ 0.4 g)
    double maxRate = 1.5;      ///< rad/s (≈ 86 °/s): above it the arm turns; no push (twist: 3 rad/s)
    double maxPush = 0.5;      ///< s from the push out to the stop
    double minPush = 0.06;     ///< s: a stop sooner than this is a tap or a knock on the device, not a push
    double baselineTau = 0.3;  ///< s: time constant of the gravity baseline
    double refractory = 0.6;   ///< s after a push before the next can start
};

class PushDetector {
public:
    explicit PushDetector(const PushParams& params = {}) noexcept : p_(params) {}
    /// One sample: time t (s, non-decreasing), the accelerometer's forearm-axis component (the
    /// device's x, m/s², specific force) and the angular rate's magnitude (rad/s). True once per
    /// completed push. Samples with a NaN are skipped.
    bool update(double t, double axialAccel, double angularRate) noexcept;
    /// When the push that last fired (or the one in progress) began, s.
    double startedAt() const noexcept { return firstAt_; }
    void reset() noexcept { *this = PushDetector(p_); }
    const PushParams& params() const noexcept { return p_; }

private:
    PushParams p_;
    bool primed_ = false;     // the baseline has its first sample
    double baseline_ = 0.0, lastT_ = 0.0;
    int sign_ = 0;            // direction of the push out in progress (0 = none)
    double firstAt_ = 0.0;
    bool armed_ = true;       // calm since the last push or refusal
    double firedAt_ = -1e9;
};

} // namespace armadillo::braille
