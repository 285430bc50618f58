#pragma once
// Answers from the arm itself (issue 26): a quick twist of the forearm and back asks for the
// trial again; two twists in a row skip it. Measured on the roll rate about the forearm axis
// (the gyro's x in the device frame, rad/s, calibrated), so it needs no orientation: a twist is
// the rate beyond `rate` one way, then beyond `rate` the other way within `maxTurn` s (a turn
// that does not come back — reading by roll, a slow change of posture — is no gesture). A single
// twist is reported once `pairWindow` s passed without a second (then it would be a skip).
// Real-time: plain arithmetic, for the device link's control thread.
namespace armadillo::access {

enum class ArmGesture { None, Repeat, Skip };

struct TwistParams {
    double rate = 3.0;          ///< rad/s (≈ 170 °/s): a deliberate flick, not a reading roll
    double maxTurn = 0.6;       ///< s from the first half of the twist to the way back
    double pairWindow = 1.0;    ///< s after a twist in which a second makes it a skip
};

class TwistDetector {
public:
    explicit TwistDetector(const TwistParams& params = {}) noexcept : p_(params) {}
    /// One sample: time t (s, non-decreasing) and the roll rate (rad/s). Returns a gesture when one
    /// is complete, else None. NaN rates are ignored.
    ArmGesture update(double t, double rollRate) noexcept;

private:
    TwistParams p_;
    int sign_ = 0;              // direction of the first half of a twist in progress (0 = none)
    double firstAt_ = 0.0;
    bool armed_ = true;         // the rate fell back below half the threshold since the last twist
    bool pending_ = false;      // one twist seen, waiting for a second
    double pendingAt_ = 0.0;
};

} // namespace armadillo::access
