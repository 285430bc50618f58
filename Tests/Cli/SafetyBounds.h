#pragma once
// An independent check of the motor safety rules (ARMADILLO.md §6, issue 5) on a tactile stream
// as written to CSV: each row's levels hold until the next row. Written apart from the tactile
// module on purpose, so a bug there cannot hide itself in its own checker.
#include "Core/Csv.h"
#include <algorithm>
#include <string>
#include <vector>

namespace armadillo::testing {

struct SafetyReport {
    double longestAboveRating = 0.0;     ///< s, longest run of level > 5 on any motor
    double maxAboveIn2s = 0.0;           ///< s above rating in the worst 2 s window
    double maxPowerIn10s = 0.0;          ///< mean (level/15)² over the worst 10 s window
    std::string worst;                   ///< which motor and when, for messages
    bool ok() const
    {
        return longestAboveRating <= 0.300 + 1e-9 && maxAboveIn2s <= 0.6 + 1e-9 && maxPowerIn10s <= (5.0 / 15.0) * (5.0 / 15.0) + 1e-9;
    }
};

inline SafetyReport checkSafety(const std::vector<core::TactileRow>& rows, int motorCount)
{
    SafetyReport report;
    const std::size_t n = rows.size();
    if (n == 0) return report;
    // Each row holds until the next; the last for the median interval.
    std::vector<double> dts;
    for (std::size_t i = 1; i < n; ++i) dts.push_back(rows[i].t - rows[i - 1].t);
    std::sort(dts.begin(), dts.end());
    const double lastDt = dts.empty() ? 0.005 : dts[dts.size() / 2];
    std::vector<double> edge(n + 1);
    for (std::size_t i = 0; i < n; ++i) edge[i] = rows[i].t;
    edge[n] = rows[n - 1].t + lastDt;

    for (int m = 0; m < motorCount; ++m) {
        // Prefix integrals of "above rating" time and of power.
        std::vector<double> above(n + 1, 0.0), power(n + 1, 0.0);
        double run = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            const double d = edge[i + 1] - edge[i];
            const int level = rows[i].levels[static_cast<std::size_t>(m)];
            above[i + 1] = above[i] + (level > 5 ? d : 0.0);
            power[i + 1] = power[i] + d * (level / 15.0) * (level / 15.0);
            run = level > 5 ? run + d : 0.0;
            if (run > report.longestAboveRating) {
                report.longestAboveRating = run;
                report.worst = "motor " + std::to_string(m + 1) + " above rating until t=" + std::to_string(edge[i + 1]);
            }
        }
        // Integral of a piecewise-constant function over [a, a+W] is maximal with an edge at a
        // breakpoint: check windows starting and ending at every row edge.
        const auto integral = [&](const std::vector<double>& prefix, double a, double b) {
            const auto at = [&](double x) {
                if (x <= edge[0]) return 0.0;
                if (x >= edge[n]) return prefix[n];
                const std::size_t k = static_cast<std::size_t>(std::upper_bound(edge.begin(), edge.end(), x) - edge.begin()) - 1;
                const double frac = (x - edge[k]) / (edge[k + 1] - edge[k]);
                return prefix[k] + frac * (prefix[k + 1] - prefix[k]);
            };
            return at(b) - at(a);
        };
        for (std::size_t i = 0; i <= n; ++i) {
            for (double w : {2.0}) {
                const double v = std::max(integral(above, edge[i], edge[i] + w), integral(above, edge[i] - w, edge[i]));
                if (v > report.maxAboveIn2s) report.maxAboveIn2s = v;
            }
            const double p = std::max(integral(power, edge[i], edge[i] + 10.0), integral(power, edge[i] - 10.0, edge[i])) / 10.0;
            if (p > report.maxPowerIn10s) report.maxPowerIn10s = p;
        }
    }
    return report;
}

} // namespace armadillo::testing
