#pragma once
// The panic gesture (docs/STAGE.md "Panic"): the forearm hanging straight down (elevation
// ≤ kElevationDeg) for kSeconds fires once; the arm must rise above kElevationDeg before hanging
// counts again, so a resume while it still hangs does not panic again. Run by the one control
// step, live::ControlLoop::tick, for `armadillo play --panic-gesture` and the app's panicGesture
// setting alike.
//
// Real-time: no allocation, lock, I/O or throw. One thread (the control step) calls update().
#include "Core/ArmState.h"
#include <cmath>
#include <limits>

namespace armadillo::engine {

class PanicGesture {
public:
    static constexpr double kElevationDeg = -75.0;
    static constexpr double kSeconds = 2.0;

    /// One control step at time `t` (s, the arm's timeline). True once per hang, when it has
    /// lasted kSeconds. An invalid arm (no source, not fused yet) neither starts nor ends a hang.
    bool update(double t, const core::ArmState& arm) noexcept
    {
        if (!arm.valid) return false;
        if (!(arm.features.pose.elevationDeg <= kElevationDeg)) {
            since_ = kNotHanging;
            return false;
        }
        if (since_ < 0.0) {
            since_ = t;
            return false;
        }
        if (std::isfinite(since_) && t - since_ >= kSeconds) {
            since_ = kFired;
            return true;
        }
        return false;
    }
    /// Forgets a hang in progress (and a fired one: the next hang counts at once).
    void reset() noexcept { since_ = kNotHanging; }
    bool hanging() const noexcept { return since_ >= 0.0; }

private:
    static constexpr double kNotHanging = -1.0;
    static constexpr double kFired = std::numeric_limits<double>::infinity();   // fired; waits for the arm to rise
    double since_ = kNotHanging;   // when the current hang began
};

} // namespace armadillo::engine
