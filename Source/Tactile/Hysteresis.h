#pragma once
// Two thresholds on every boundary (thesis §3.2.4): a state turns on when the signal rises above
// `enter` and off only when it falls below `exit`, so noise near one threshold cannot chatter.
namespace armadillo::tactile {

class Hysteresis {
public:
    /// For an upward boundary use enter > exit (e.g. +0.1 / −0.1). For a downward boundary
    /// (state on when the signal is LOW) use enter < exit.
    constexpr Hysteresis(double enter, double exit, bool initiallyOn = false) noexcept
        : enter_(enter), exit_(exit), on_(initiallyOn) {}

    /// An upward boundary at `threshold` with a dead band of ±`halfWidth` (thesis Figure 3-6:
    /// threshold 0, enter +0.1, exit −0.1).
    static constexpr Hysteresis around(double threshold, double halfWidth, bool initiallyOn = false) noexcept
    {
        return Hysteresis(threshold + halfWidth, threshold - halfWidth, initiallyOn);
    }

    /// Feeds one value; returns the state after it.
    constexpr bool update(double x) noexcept
    {
        if (enter_ >= exit_) {
            if (!on_ && x > enter_) on_ = true;
            else if (on_ && x < exit_) on_ = false;
        } else {
            if (!on_ && x < enter_) on_ = true;
            else if (on_ && x > exit_) on_ = false;
        }
        return on_;
    }
    constexpr bool on() const noexcept { return on_; }
    constexpr void reset(bool on = false) noexcept { on_ = on; }
    constexpr void setThresholds(double enter, double exit) noexcept { enter_ = enter; exit_ = exit; }
    constexpr double enter() const noexcept { return enter_; }
    constexpr double exit() const noexcept { return exit_; }
    /// The threshold that decides the next change: exit while on, enter while off.
    constexpr double activeThreshold() const noexcept { return on_ ? exit_ : enter_; }

private:
    double enter_, exit_;
    bool on_;
};

} // namespace armadillo::tactile
