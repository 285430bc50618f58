#pragma once
// An independent check of the safety bounds on a recorded motor stream: packet i stays on for
// hold[i] s. Written from the definitions (SafetyParams), not from the stage's own bookkeeping.
#include "Tactile/TactileEngine.h"
#include <algorithm>
#include <vector>

namespace armadillo::test {

struct BoundsReport {
    double maxAboveRun = 0.0;      ///< s
    double maxAboveInWindow = 0.0; ///< s above rating in the worst aboveRatingWindow
    double maxMeanPower = 0.0;     ///< mean (level/15)² over the worst powerWindow
    double maxOnRun = 0.0;         ///< s
};

/// Largest integral of a piecewise-constant signal (value[i] over hold[i]) over any window of
/// length w. The maximum is reached with one window edge on a packet boundary.
inline double maxWindowIntegral(const std::vector<double>& value, const std::vector<double>& hold, double w)
{
    const std::size_t n = value.size();
    std::vector<double> t(n + 1, 0.0), c(n + 1, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        t[i + 1] = t[i] + hold[i];
        c[i + 1] = c[i] + value[i] * hold[i];
    }
    const auto integralTo = [&](double x) {   // ∫ from t[0] to x
        if (x <= t[0]) return 0.0;
        if (x >= t[n]) return c[n];
        const auto k = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), x) - t.begin()) - 1;
        return c[k] + value[k] * (x - t[k]);
    };
    double best = 0.0;
    for (std::size_t i = 0; i <= n; ++i) {
        best = std::max(best, integralTo(t[i] + w) - c[i]);
        best = std::max(best, c[i] - integralTo(t[i] - w));
    }
    return best;
}

inline BoundsReport measureBounds(const std::vector<core::MotorLevels>& packets, const std::vector<double>& hold,
                                  const tactile::SafetyParams& p = tactile::kDefaultSafetyParams)
{
    BoundsReport r;
    for (int m = 0; m < core::kMaxMotors; ++m) {
        std::vector<double> above(packets.size()), power(packets.size());
        double aboveRun = 0.0, onRun = 0.0;
        for (std::size_t i = 0; i < packets.size(); ++i) {
            const int level = packets[i][static_cast<std::size_t>(m)];
            above[i] = level > p.ratedLevel ? 1.0 : 0.0;
            power[i] = (level / 15.0) * (level / 15.0);
            aboveRun = level > p.ratedLevel ? aboveRun + hold[i] : 0.0;
            onRun = level > 0 ? onRun + hold[i] : 0.0;
            r.maxAboveRun = std::max(r.maxAboveRun, aboveRun);
            r.maxOnRun = std::max(r.maxOnRun, onRun);
        }
        r.maxAboveInWindow = std::max(r.maxAboveInWindow, maxWindowIntegral(above, hold, p.aboveRatingWindow));
        r.maxMeanPower = std::max(r.maxMeanPower, maxWindowIntegral(power, hold, p.powerWindow) / p.powerWindow);
    }
    return r;
}

inline bool withinBounds(const BoundsReport& r, const tactile::SafetyParams& p = tactile::kDefaultSafetyParams)
{
    const double eps = 1e-9;
    return r.maxAboveRun <= p.maxAboveRatingRun + eps
        && r.maxAboveInWindow <= p.maxAboveRatingFraction * p.aboveRatingWindow + eps
        && r.maxMeanPower <= p.maxMeanPower * (1.0 + 1e-9)
        && r.maxOnRun <= p.maxOnRun + eps;
}

} // namespace armadillo::test
