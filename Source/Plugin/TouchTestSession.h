#pragma once
// The app's per-motor sensitivity test (issue 26): the same measurement as `armadillo
// touch-profile` (Source/Cli/CmdTouchProfile.cpp) driven by the app — a 1-up/2-down staircase
// (Tactile/Staircase.h) per motor, interleaved in a seeded random order so no motor runs twice in
// a row, each stimulus a soft 0.25 s level on one motor through an access::TactilePlayer (its own
// TactileEngine and SafetyStage, the touch profile NOT applied: the raw threshold is measured),
// played by the control step in place of the scene's levels (BlockControl::setStimulus). The
// reader answers felt / not felt after each stimulus (buttons, Y / N keys). Then, as the CLI, a
// comfortable level on the profile's comfort motor (m5): ascending from its threshold + 1, one
// level a step, until the reader answers "comfortable" (or level 15). The result is a
// device::TouchProfile (the CLI's JSON, "comfort" included). JUCE-free, message thread only (the player's control side runs in the
// control step).
#include "Access/TactilePlayer.h"
#include "Link/TouchProfile.h"
#include "Tactile/Staircase.h"
#include <array>
#include <cstdint>
#include <random>
#include <string>

namespace armadillo::plugin {

class TouchTestSession {
public:
    static constexpr double kOnSeconds = 0.25;    ///< stimulus (the CLI's --on default)
    static constexpr double kGapSeconds = 0.5;    ///< stillness after it (--gap)
    static constexpr double kRestSeconds = 3.0;   ///< a motor rests this long between its stimuli (safety stage's power window)

    TouchTestSession();
    access::TactilePlayer& player() noexcept { return player_; }

    enum class State { Idle, Presenting, Asking, Done };
    State state() const noexcept { return state_; }
    /// Starts a new test (the seed fixes the order of the motors); `comfort` false skips the
    /// comfortable-level step (the CLI's --no-comfort).
    void begin(std::uint64_t seed = 1, bool comfort = true);
    /// The thresholds are measured: the stimuli now ask for a comfortable level.
    bool comfortStep() const noexcept { return comfortStep_; }
    /// Ends a test early; nothing is kept.
    void cancel() noexcept { state_ = State::Idle; }
    /// Timer: a stimulus that has been played moves the test on to Asking. True when it did
    /// (the caller says the question).
    bool poll();
    /// The answer to the stimulus just played (only in Asking): the next stimulus is queued, or
    /// the test is Done.
    void answer(bool felt);
    /// Shows the current stimulus again (only in Asking).
    void again();
    /// "motor m3, level 8: felt it?" ("…: comfortable?" in the comfort step); "" when not asking.
    std::string question() const;
    int motor() const noexcept { return motor_; }       ///< 0-based, the motor of the current stimulus
    int level() const noexcept { return level_; }
    int stimuli() const noexcept { return stimuli_; }
    /// The measured profile (valid in Done).
    device::TouchProfile profile() const;

private:
    void next();
    void present();

    access::TactilePlayer player_;
    std::array<Staircase, device::kProfileMotors> stairs_ {};
    std::array<double, device::kProfileMotors> lastStart_ {};
    std::vector<int> order_;
    std::mt19937_64 rng_ {1};
    State state_ = State::Idle;
    int motor_ = -1, previous_ = -1, level_ = 0, stimuli_ = 0, waitingFor_ = 0, comfort_ = 0;
    bool askComfort_ = true, comfortStep_ = false;
};

} // namespace armadillo::plugin
