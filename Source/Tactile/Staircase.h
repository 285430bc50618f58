#pragma once
// An adaptive staircase for a detection threshold (touch fitted to the reader, issue 26).
//
// Transformed up-down rule "1-up/2-down" (Levitt 1971, J. Acoust. Soc. Am. 49:467): after one
// "not felt" the level goes up one step; after two "felt" in a row at the same level it goes down
// one step. It converges on the level felt 70.7 % of the time. Steps start at `firstStep` and
// halve at every reversal (change of direction) down to 1 level; the estimate is the mean of the
// reversal levels reached with the 1-level step (the last `finalReversals` of them), rounded.
// A motor never felt at the top level (three "no" there) ends as "not felt" at maxLevel; one felt
// at the bottom level twice over ends at minLevel. Plain arithmetic: no allocation after
// construction, no clock — the caller presents level(), then reports answer().
#include <vector>

namespace armadillo::tactile {

struct StaircaseParams {
    int startLevel = 8;        ///< the first level shown (clearly felt by most skins at the motors' rating)
    int minLevel = 1;
    int maxLevel = 15;
    int firstStep = 4;         ///< levels; halves at each reversal down to 1
    int finalReversals = 6;    ///< reversals with the 1-level step that end the staircase
    int maxTrials = 40;        ///< a safety net: the staircase ends after this many answers anyway
};

class Staircase {
public:
    Staircase() : Staircase(StaircaseParams {}) {}
    explicit Staircase(const StaircaseParams& params);
    int level() const noexcept { return level_; }   ///< the level to present next
    void answer(bool felt) noexcept;
    bool done() const noexcept { return done_; }
    /// The estimate so far (final once done()): see the rule above.
    int threshold() const noexcept;
    /// False when the reader never felt the motor, even at maxLevel.
    bool felt() const noexcept { return everFelt_; }
    int trials() const noexcept { return trials_; }
    int reversals() const noexcept { return static_cast<int>(finalLevels_.size()); }

private:
    void move(int direction) noexcept;
    StaircaseParams p_;
    int level_ = 8, step_ = 4, direction_ = 0, yesRun_ = 0, trials_ = 0;
    int noAtTop_ = 0, yesAtBottom_ = 0, lowestFelt_ = 0;
    bool done_ = false, everFelt_ = false;
    std::vector<int> finalLevels_;   // reserved in the constructor
};

} // namespace armadillo::tactile
