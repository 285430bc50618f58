#pragma once
// Two thresholds on every boundary (thesis §3.2.4): a state turns on when the signal rises above
// `enter` and off only when it falls below `exit`, so noise near one threshold cannot chatter.
namespace armadillo {

class Hysteresis {
public:
    /// For an upward boundary use enter > exit (e.g. +0.1 / −0.1). For a downward boundary
    /// (state on when the signal is LOW) use enter < exit.
    constexpr Hysteresis(double enter, double exit, bool initiallyOn = false) noexcept
        : enter_(enter), exit_(exit), on_(initiallyOn) {}

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

private:
    double enter_, exit_;
    bool on_;
};

} // namespace armadillo
