#pragma once
// The scripted presenter of the procedures' tests: it plays the control side of a TactilePlayer
// (one onPacket per 5 ms control step, as the app's block control does), records what reached the
// motors, and hands each prompt to a script that answers it. Deterministic: no wall clock, no
// threads; a procedure that never asks again fails the test (a bounded number of steps).
#include "Access/TactilePlayer.h"
#include <array>
#include <functional>
#include <string>
#include <vector>

namespace armadillo::test {

class ScriptedPlayerSide {
public:
    explicit ScriptedPlayerSide(access::TactilePlayer& player) : player_(player) {}

    /// Steps the control side until `done()` (asked before each step) or `maxSeconds` of clock
    /// pass; true when done. Every step's levels are recorded (the set of motors on, highest level).
    bool runUntil(const std::function<bool()>& done, double maxSeconds = 120.0)
    {
        for (double waited = 0.0; waited < maxSeconds; waited += kStep) {
            if (done()) return true;
            const core::MotorLevels levels = player_.onPacket(t_);
            int set = 0;
            for (int m = 0; m < 9; ++m)
                if (levels[static_cast<std::size_t>(m)] > 0) {
                    set |= 1 << m;
                    highest_[static_cast<std::size_t>(m)] = std::max<int>(highest_[static_cast<std::size_t>(m)], levels[static_cast<std::size_t>(m)]);
                }
            if (set != 0 && (sets_.empty() || sets_.back() != set)) sets_.push_back(set);
            t_ += kStep;
        }
        return done();
    }
    /// The motor sets that came on, in order (a new entry each time the set changes), since clear().
    const std::vector<int>& sets() const noexcept { return sets_; }
    /// Highest level each motor got since clear().
    const std::array<int, 9>& highest() const noexcept { return highest_; }
    void clear()
    {
        sets_.clear();
        highest_.fill(0);
    }
    double clock() const noexcept { return t_; }

    static constexpr double kStep = 0.005;   ///< s: the plugin's 200 Hz control rate

private:
    access::TactilePlayer& player_;
    double t_ = 0.0;
    std::vector<int> sets_;
    std::array<int, 9> highest_ {};
};

} // namespace armadillo::test
