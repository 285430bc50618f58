#include "Tactile/Staircase.h"
#include <algorithm>
#include <cmath>

namespace armadillo::tactile {

Staircase::Staircase(const StaircaseParams& params) : p_(params)
{
    p_.minLevel = std::max(0, p_.minLevel);
    p_.maxLevel = std::max(p_.minLevel, p_.maxLevel);
    p_.firstStep = std::max(1, p_.firstStep);
    p_.finalReversals = std::max(1, p_.finalReversals);
    p_.maxTrials = std::max(1, p_.maxTrials);
    level_ = std::clamp(p_.startLevel, p_.minLevel, p_.maxLevel);
    step_ = p_.firstStep;
    lowestFelt_ = p_.maxLevel;
    finalLevels_.reserve(static_cast<std::size_t>(p_.maxTrials) + 1);
}

void Staircase::move(int direction) noexcept
{
    if (direction_ != 0 && direction != direction_) {   // a reversal, at the level just shown
        if (step_ == 1) finalLevels_.push_back(level_);
        step_ = std::max(1, step_ / 2);
    }
    direction_ = direction;
    level_ = std::clamp(level_ + direction * step_, p_.minLevel, p_.maxLevel);
}

void Staircase::answer(bool felt) noexcept
{
    if (done_) return;
    ++trials_;
    if (felt) {
        everFelt_ = true;
        lowestFelt_ = std::min(lowestFelt_, level_);
        noAtTop_ = 0;
        if (++yesRun_ >= 2) {
            yesRun_ = 0;
            if (level_ == p_.minLevel) {
                if (++yesAtBottom_ >= 2) done_ = true;
            } else {
                move(-1);
            }
        }
    } else {
        yesRun_ = 0;
        yesAtBottom_ = 0;
        if (level_ == p_.maxLevel) {
            if (++noAtTop_ >= 3) done_ = true;
        } else {
            move(+1);
        }
    }
    if (static_cast<int>(finalLevels_.size()) >= p_.finalReversals || trials_ >= p_.maxTrials) done_ = true;
}

int Staircase::threshold() const noexcept
{
    if (!everFelt_) return p_.maxLevel;
    if (yesAtBottom_ >= 2) return p_.minLevel;
    if (finalLevels_.size() >= 2) {
        const std::size_t n = std::min<std::size_t>(finalLevels_.size(), static_cast<std::size_t>(p_.finalReversals));
        double sum = 0.0;
        for (std::size_t i = finalLevels_.size() - n; i < finalLevels_.size(); ++i) sum += finalLevels_[i];
        return std::clamp(static_cast<int>(std::lround(sum / static_cast<double>(n))), p_.minLevel, p_.maxLevel);
    }
    return lowestFelt_;
}

} // namespace armadillo::tactile
