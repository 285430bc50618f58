#pragma once
// A second-order Butterworth high- or low-pass (RBJ's cookbook, Q = 1/√2; transposed direct form
// II, double state): the band filters of audio-touch (Instruments) and of the voice coil's
// hand-over of a scene's sound (Tactors). Real-time: no allocation.
#include <cmath>

namespace armadillo::core {

struct Biquad {
    double b0 = 1, b1 = 0, b2 = 0, a1 = 0, a2 = 0, z1 = 0, z2 = 0;
    /// A high-pass (`highPass`) or low-pass at `hz` for sample rate `fs`.
    static Biquad make(bool highPass, double hz, double fs)
    {
        const double w = 2.0 * 3.14159265358979323846 * hz / fs, c = std::cos(w), alpha = std::sin(w) / (2.0 * 0.7071067811865476);
        const double a0 = 1.0 + alpha;
        Biquad q;
        q.b0 = (highPass ? (1.0 + c) / 2.0 : (1.0 - c) / 2.0) / a0;
        q.b1 = (highPass ? -(1.0 + c) : (1.0 - c)) / a0;
        q.b2 = q.b0;
        q.a1 = -2.0 * c / a0;
        q.a2 = (1.0 - alpha) / a0;
        return q;
    }
    double operator()(double x) noexcept
    {
        const double y = b0 * x + z1;
        z1 = b1 * x - a1 * y + z2;
        z2 = b2 * x - a2 * y;
        return y;
    }
};

} // namespace armadillo::core
