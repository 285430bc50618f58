#pragma once
// Measures a tactor channel's signal the way the actuator gets it, independently of the renderer:
// frames of `frame` samples; a frame's level is 15 × its peak |sample| / gain (the Syntacts
// convention of docs/FORMATS.md), its power (level/15)² as the safety stage counts it (a frame
// holding a level for part of it counts whole: never less than what the actuator got), and its
// energy 2 × mean(sample²) / gain² (a sine of peak A has mean square A²/2).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace armadillo::test {

struct FrameMeasure {
    std::vector<double> level;   ///< per frame
    std::vector<double> power;   ///< per frame: (level/15)², the measure of the safety stage's power rule
    std::vector<double> energy;  ///< per frame: 2 × mean square (= (level/15)² for whole carrier periods)
};

inline FrameMeasure measureFrames(const std::vector<float>& x, std::size_t frame, double gain = 1.0)
{
    FrameMeasure m;
    for (std::size_t at = 0; at + frame <= x.size(); at += frame) {
        double peak = 0.0, sq = 0.0;
        for (std::size_t i = at; i < at + frame; ++i) {
            peak = std::max(peak, std::fabs(static_cast<double>(x[i])));
            sq += static_cast<double>(x[i]) * static_cast<double>(x[i]);
        }
        m.level.push_back(15.0 * peak / gain);
        m.power.push_back((peak / gain) * (peak / gain));
        m.energy.push_back(2.0 * sq / static_cast<double>(frame) / (gain * gain));
    }
    return m;
}

/// The safety rules of docs/TACTILE.md measured on frames of `frameSeconds`.
struct SignalBounds {
    double longestAboveRun = 0.0;     ///< s above the rating (level > rated + 0.5) without a break
    double worstAboveFraction = 0.0;  ///< of any 2 s window
    double worstMeanPower = 0.0;      ///< of any 10 s window (or the whole signal when shorter), frame peaks
    double worstMeanEnergy = 0.0;     ///< the same from the signal's energy
    double longestOnRun = 0.0;        ///< s at any level > 0.5 without a break
};

inline SignalBounds measureBounds(const FrameMeasure& m, double frameSeconds, int rated = 5)
{
    SignalBounds b;
    const std::size_t n = m.level.size();
    double above = 0.0, on = 0.0;
    for (std::size_t f = 0; f < n; ++f) {
        above = m.level[f] > rated + 0.5 ? above + frameSeconds : 0.0;
        on = m.level[f] > 0.5 ? on + frameSeconds : 0.0;
        b.longestAboveRun = std::max(b.longestAboveRun, above);
        b.longestOnRun = std::max(b.longestOnRun, on);
    }
    const auto window = [&](double seconds) { return std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(seconds / frameSeconds))); };
    const std::size_t dutyW = window(2.0), powerW = std::min(window(10.0), std::max<std::size_t>(n, 1));
    std::size_t count = 0;
    double power = 0.0, energy = 0.0;
    for (std::size_t f = 0; f < n; ++f) {
        count += m.level[f] > rated + 0.5 ? 1 : 0;
        if (f >= dutyW) count -= m.level[f - dutyW] > rated + 0.5 ? 1 : 0;
        b.worstAboveFraction = std::max(b.worstAboveFraction, static_cast<double>(count) / static_cast<double>(dutyW));
        power += m.power[f];
        energy += m.energy[f];
        if (f >= powerW) {
            power -= m.power[f - powerW];
            energy -= m.energy[f - powerW];
        }
        if (f + 1 >= powerW) {
            b.worstMeanPower = std::max(b.worstMeanPower, power / static_cast<double>(powerW));
            b.worstMeanEnergy = std::max(b.worstMeanEnergy, energy / static_cast<double>(powerW));
        }
    }
    return b;
}

} // namespace armadillo::test
