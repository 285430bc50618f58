#pragma once
// Small real-time DSP pieces the instrument scenes share. Everything here is allocation-free
// after construction and safe to call on the audio thread.
#include <array>
#include <cmath>
#include <cstdint>

namespace armadillo::instruments::dsp {

inline constexpr double kTwoPi = 6.283185307179586476925;

/// A 4096-point sine table read with linear interpolation. A table read costs a few ns where
/// std::sin costs ~20; with 4096 points the interpolation error is below 3e-7 of full scale
/// (−130 dB), far under what a 16-bit render can show, and pitch is exact because the phase
/// accumulator is exact. Built during static initialisation, so the audio thread never meets a
/// function-local static's guard (which may lock on first use).
class SineTable {
public:
    static constexpr int kSize = 4096;
    /// phase in cycles, any value (|phase| < 2^19); returns sin(2π·phase).
    static double at(double phaseCycles) noexcept
    {
        const double x = phaseCycles * kSize;
        int i = static_cast<int>(x);
        if (x < i) --i;   // floor without a libm call (baseline x86-64 has no roundsd)
        const float frac = static_cast<float>(x - i);
        const float a = table_[static_cast<std::size_t>(i & (kSize - 1))];
        const float b = table_[static_cast<std::size_t>((i + 1) & (kSize - 1))];
        return static_cast<double>(a + frac * (b - a));
    }

private:
    static std::array<float, kSize> build()
    {
        std::array<float, kSize> v {};
        for (int i = 0; i < kSize; ++i) v[static_cast<std::size_t>(i)] = static_cast<float>(std::sin(kTwoPi * i / kSize));
        return v;
    }
    static inline const std::array<float, kSize> table_ = build();
};

/// Wraps a phase in cycles into [0, 1). Inlined floor: std::floor is a libm call on baseline
/// x86-64, and this runs several times per sample.
inline double wrapPhase(double phaseCycles) noexcept
{
    auto i = static_cast<long long>(phaseCycles);
    if (phaseCycles < static_cast<double>(i)) --i;
    return phaseCycles - static_cast<double>(i);
}

/// One-pole smoothing toward a target, per sample: y += a·(target − y).
/// a = 1 − exp(−1/(τ·fs)): after τ seconds 63% of a step is done, with no steps ("zipper").
struct OnePole {
    double coefficient = 1.0;   ///< a, dimensionless 0..1 (1 = no smoothing)
    double value = 0.0;         ///< current output, in the smoothed quantity's unit

    void setTime(double tauSeconds, double sampleRateHz) noexcept
    {
        coefficient = tauSeconds > 0.0 ? 1.0 - std::exp(-1.0 / (tauSeconds * sampleRateHz)) : 1.0;
    }
    double next(double target) noexcept
    {
        value += coefficient * (target - value);
        return value;
    }
};

/// Deterministic 64-bit generator (SplitMix64 mixing): cheap, seedable, identical everywhere,
/// so a render with the same seed repeats bit for bit.
class Random {
public:
    explicit Random(std::uint64_t seed = 1) noexcept : state_(seed) {}
    void seed(std::uint64_t s) noexcept { state_ = s; }
    std::uint64_t nextU64() noexcept
    {
        std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    /// Uniform in [0, 1).
    double uniform() noexcept { return static_cast<double>(nextU64() >> 11) * 0x1.0p-53; }
    /// Uniform in [lo, hi).
    double uniform(double lo, double hi) noexcept { return lo + (hi - lo) * uniform(); }
    /// Uniform integer in [0, n), n > 0.
    int below(int n) noexcept { return static_cast<int>(uniform() * n); }
    /// Uniform in [−1, 1): white noise.
    float bipolar() noexcept { return static_cast<float>(2.0 * uniform() - 1.0); }

private:
    std::uint64_t state_;
};

/// Topology-preserving state-variable filter (Zavalishin / Simper "SVF"): stable under
/// modulation, band-pass and low/high-pass outputs from one state. Not real-time-critical here:
/// it shapes the built-in noise bank in prepare().
struct StateVariableFilter {
    struct Coefficients {
        double g = 0.0, k = 1.0, a1 = 0.0, a2 = 0.0, a3 = 0.0;
    };
    struct Output {
        double low, band, high;
    };
    Coefficients c {};
    double ic1 = 0.0, ic2 = 0.0;   ///< state (integrator memories)

    void setup(double cutoffHz, double q, double sampleRateHz) noexcept
    {
        c.g = std::tan(kTwoPi * 0.5 * cutoffHz / sampleRateHz);
        c.k = 1.0 / q;
        c.a1 = 1.0 / (1.0 + c.g * (c.g + c.k));
        c.a2 = c.g * c.a1;
        c.a3 = c.g * c.a2;
    }
    Output process(double x) noexcept
    {
        const double v3 = x - ic2;
        const double v1 = c.a1 * ic1 + c.a2 * v3;
        const double v2 = ic2 + c.a2 * ic1 + c.a3 * v3;
        ic1 = 2.0 * v1 - ic1;
        ic2 = 2.0 * v2 - ic2;
        return {v2, v1, x - c.k * v1 - v2};
    }
};

/// Flushes tiny magnitudes to zero so decaying recursions never enter denormal arithmetic.
inline double flushTiny(double x) noexcept { return std::fabs(x) < 1e-15 ? 0.0 : x; }

} // namespace armadillo::instruments::dsp
