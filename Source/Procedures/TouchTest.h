#pragma once
// The per-motor sensitivity test (issue 26), written once for `armadillo touch-profile`
// (Cli/CmdTouchProfile.cpp presents it on stdin/stderr) and the app's Reader window
// (Plugin/ReaderPanel.cpp): a 1-up/2-down staircase (Tactile/Staircase.h) per motor, interleaved
// in a seeded random order so no motor runs twice in a row, each stimulus a soft level (no
// jump-start spike: the level asked is the level felt) on one motor through an
// access::TactilePlayer (its own TactileEngine and SafetyStage, the touch profile NOT applied: the
// raw threshold is measured). Each motor rests kRestSeconds of stimulus clock between two of its
// stimuli (the safety stage's mean-power window would otherwise lower a strong level repeated on
// one motor). The reader answers felt / not felt after each stimulus. Then a comfortable level on
// the profile's comfort motor (m5): ascending from its threshold + 1, one level a step, until the
// reader answers "comfortable" (at level 15 it is taken without asking). The result is a
// link::TouchProfile ("comfort" included), written by save().
//
// Threads: everything here runs on one front-end thread (the app's message thread, the CLI's main
// thread); the player's control side (TactilePlayer::onPacket) runs on the control step (the app's
// block control, the CLI's device link thread), as every TactilePlayer does.
#include "Access/TactilePlayer.h"
#include "Link/TouchProfile.h"
#include "Tactile/Staircase.h"
#include <array>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace armadillo::procedures {

class TouchTest {
public:
    struct Params {
        double onSeconds = 0.25;     ///< s a stimulus lasts (the CLI's --on; ≤ 0.3, the safety stage's run limit)
        double gapSeconds = 0.5;     ///< s of stillness after it (--gap)
        double restSeconds = 3.0;    ///< s of stimulus clock a motor rests between two of its stimuli
        double packetPeriod = 0.0;   ///< > 0: the player counts each packet as this many s (the CLI's --unpaced)
    };
    static constexpr double kOnSeconds = 0.25;
    static constexpr double kGapSeconds = 0.5;
    static constexpr double kRestSeconds = 3.0;

    TouchTest();
    explicit TouchTest(const Params& params);
    access::TactilePlayer& player() noexcept { return player_; }
    const Params& params() const noexcept { return params_; }

    enum class State { Idle, Presenting, Asking, Done };
    State state() const noexcept { return state_; }
    /// Starts a new test (the seed fixes the order of the motors); `comfort` false skips the
    /// comfortable-level step (the CLI's --no-comfort). The first stimulus is queued.
    void begin(std::uint64_t seed = 1, bool comfort = true);
    /// The thresholds are measured: the stimuli now ask for a comfortable level.
    bool comfortStep() const noexcept { return comfortStep_; }
    /// Ends a test early; nothing is kept.
    void cancel() noexcept { state_ = State::Idle; }
    /// A stimulus that has been played (and its stillness) moves the test on to Asking. True when
    /// it did: the presenter asks question() now.
    bool poll();
    /// The sequence number of the stimulus being presented (the player's; 0 when none): a
    /// presenter that blocks waits until player().completed() reaches it.
    int waitingFor() const noexcept { return waitingFor_; }
    /// The answer to the stimulus just played (only in Asking): the next stimulus is queued, or
    /// the test is Done. In the comfort step `felt` means "comfortable".
    void answer(bool felt);
    /// Shows the current stimulus again (only in Asking).
    void again();
    /// "motor m3, level 8: felt it?" ("…: comfortable?" in the comfort step); "" when not asking.
    std::string question() const;
    /// The level the safety stage let through for the stimulus just played, when lower than the
    /// level asked (a presenter says so); 0 otherwise.
    int loweredTo() const noexcept;
    int motor() const noexcept { return motor_; }   ///< 0-based, the motor of the current stimulus
    int level() const noexcept { return level_; }
    int stimuli() const noexcept { return stimuli_; }
    /// The measured profile (valid in Done); `date` stamped now (UTC).
    link::TouchProfile profile() const;
    /// Writes profile() to `path` (atomic; IoError when it cannot).
    void save(const std::string& path) const;
    /// "thresholds 2,5,9,…, comfortable level 7": the result in words.
    std::string summary() const;
    /// The CLI's summary line: {"stimuli":…,"stimulus_seconds":…,"threshold":[…],"comfort":…}.
    std::string summaryJson() const;

private:
    void next();
    void present();

    Params params_;
    access::TactilePlayer player_;
    std::array<tactile::Staircase, link::kProfileMotors> stairs_ {};
    std::array<double, link::kProfileMotors> lastStart_ {};
    std::vector<int> order_;
    std::mt19937_64 rng_ {1};
    State state_ = State::Idle;
    int motor_ = -1, previous_ = -1, level_ = 0, stimuli_ = 0, waitingFor_ = 0, comfort_ = 0;
    bool askComfort_ = true, comfortStep_ = false;
};

} // namespace armadillo::procedures
