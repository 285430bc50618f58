#pragma once
// The heading a walker can trust (thesis §5.3): the compass reads where the thumb points, but a
// strap sits a little turned on the forearm and the thumb does not point exactly where the
// person walks. The difference is learned online: while the person moves steadily, the arm's
// heading averaged over whole arm-swing cycles (found by peak detection in the forearm's
// elevation, so the swing's own yaw cancels) is compared with the walking direction — the
// receiver's course over ground when it gives one (Doppler, good at walking speed), else the
// direction of a line fitted through the last fixes. The offset is their circular mean,
// exponentially forgetting (a strap that slips is followed).
//
// Real-time: arm() runs in every control step and fix() at each new position report; neither
// allocates, locks or throws (fixed rings). Angles in degrees, times in seconds, metres.
#include "Navigation/Position.h"
#include <array>
#include <cstdint>
#include <limits>

namespace armadillo::navigation {

struct HeadingLearnerParams {
    double minSpeedMps = 0.6;        ///< slower than this the walking direction is not trusted, m/s
    double steadyArmDeg = 12.0;      ///< the arm's heading may spread this much over a sample (circular std), deg
    int fitFixes = 8;                ///< fixes in the fitted line when the source gives no course (≤ kRing)
    double minFitSpanM = 7.0;        ///< the fitted stretch must be at least this long, m
    double maxFitResidualM = 6.0;    ///< RMS distance of the fixes from the fitted line, m (a curve is not a line)
    double swingMinDeg = 3.0;        ///< an elevation swing smaller than this (peak to trough) is no swing, deg
    double swingMaxPeriodS = 2.5;    ///< peaks further apart than this: no swing (arm held still), s
    double forget = 0.08;            ///< weight of a new sample once learned (exponential forgetting)
    int learnedAfter = 4;            ///< samples until offsetDeg() is used (`learned()`)
};
inline constexpr HeadingLearnerParams kDefaultHeadingLearnerParams {};

class HeadingLearner {
public:
    static constexpr int kRing = 16;
    explicit HeadingLearner(const HeadingLearnerParams& p = kDefaultHeadingLearnerParams) : p_(p) {}

    /// Every control step: the thumb's heading (deg; NaN when unknown) and the forearm's
    /// elevation (deg) at time t (s).
    void arm(double t, double headingDeg, double elevationDeg) noexcept;
    /// Each new position report with a usable fix: its position in a local east/north plane (m),
    /// the source's course and speed (NaN when not given), at time t (s, the same clock as arm()).
    /// A report without a fix breaks the fitted line (call reset_fit()).
    void fix(double t, double x, double y, double courseDeg, double speedMps) noexcept;
    void breakFit() noexcept { fitCount_ = 0; }
    void reset() noexcept;

    /// The learned offset: thumb heading − walking direction, deg in (−180, 180]; 0 before any sample.
    double offsetDeg() const noexcept { return offset_; }
    bool learned() const noexcept { return samples_ >= p_.learnedAfter; }
    int samples() const noexcept { return samples_; }
    /// The last walking direction measured (deg, NaN when none yet) and the arm-swing period (s,
    /// NaN while no swing is seen) — for logs and the docs' figures.
    double walkingDeg() const noexcept { return walking_; }
    double swingPeriodS() const noexcept { return swingPeriod_; }

private:
    struct Sum {
        double s = 0.0, c = 0.0;
        int n = 0;
        void add(double rad) noexcept;
        void add(const Sum& o) noexcept { s += o.s; c += o.c; n += o.n; }
    };
    void learn(const Sum& arm, double walkingDeg) noexcept;
    HeadingLearnerParams p_;
    // Swing detection on the elevation (peaks with hysteresis).
    double runMax_ = 0.0, runMin_ = 0.0, lastPeakT_ = -1.0, swingPeriod_ = 0.0;
    bool rising_ = true, primed_ = false;
    Sum cycle_ {}, complete_ {};   // arm heading since the last peak / in whole cycles since the last fix
    // Per fix interval: the arm's heading sum, for the fitted line's window.
    struct FixRow { double t = 0.0, x = 0.0, y = 0.0; Sum arm {}; };
    std::array<FixRow, kRing> ring_ {};
    int fitHead_ = 0, fitCount_ = 0;
    double offset_ = 0.0, walking_ = std::numeric_limits<double>::quiet_NaN();
    double offS_ = 0.0, offC_ = 0.0;   // the circular mean's running vector
    int samples_ = 0;
};

} // namespace armadillo::navigation
