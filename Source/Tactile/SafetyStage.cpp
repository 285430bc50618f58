// The safety stage (thesis §3.2.3): the last word on every motor level.
//
// Each motor keeps a run-length history of what the stage put out: records (start time, level)
// with the running integrals of level² and of "above rating" up to each record's start, so the
// integral over any interval is two look-ups. A decision plans the new level for the horizon
// H = max(maxHoldTime, dt) and checks every window that ends within [now, now + H]:
//   • run above rating:    aboveRun + H ≤ maxAboveRatingRun
//   • duty above rating:   A[now+H−W₂, now] + H ≤ f·W₂   (A + d is nondecreasing in d, so d = H
//                          is the worst window end)
//   • mean power:          E[now+d−W₁₀, now] + L²·d ≤ P·W₁₀ for every d in (0, H]; the left side
//                          is piecewise linear in d, so only d = H and the history's level changes
//                          inside [now−W₁₀, now−W₁₀+H] need checking
//   • soft time limit:     onRun + H ≤ maxOnRun, else the motor rests restAfterOnRun
// Windows ending later are checked by later decisions, so by induction every window is.
#include "Tactile/TactileEngine.h"
#include <algorithm>
#include <cmath>
#include <limits>

namespace armadillo {

namespace {
constexpr std::size_t kRecordsPerMotor = 2048;   // run-length records per motor (power of two)
// Relative slack against rounding in the window sums: limits are met with a hair to spare.
constexpr double kSlack = 1e-9;
} // namespace

SafetyStage::SafetyStage() { prepare(kDefaultSafetyParams, kMaxMotors); }

void SafetyStage::prepare(const SafetyParams& params, int motorCount)
{
    params_ = params;
    params_.ratedLevel = std::clamp(params_.ratedLevel, 0, kMaxLevel);
    params_.maxHoldTime = std::max(params_.maxHoldTime, 1e-4);
    motorCount_ = std::clamp(motorCount, 0, kMaxMotors);
    capacity_ = kRecordsPerMotor;
    const std::size_t n = capacity_ * static_cast<std::size_t>(kMaxMotors);
    start_.assign(n, 0.0);
    cumE_.assign(n, 0.0);
    cumA_.assign(n, 0.0);
    level_.assign(n, 0);
    oldest_.fill(0);
    newest_.fill(0);   // one record per motor: level 0 since time 0
    aboveRun_.fill(0.0);
    onRun_.fill(0.0);
    rest_.fill(0.0);
    last_.fill(0);
    now_ = 0.0;
    forceOff_ = false;
    limited_ = 0;
}

// Sequence number of the last record starting at or before t (the oldest kept if none does).
std::uint64_t SafetyStage::findRecord(int m, double t) const noexcept
{
    const auto mi = static_cast<std::size_t>(m);
    const std::size_t base = mi * capacity_;
    const std::size_t mask = capacity_ - 1;
    std::uint64_t lo = oldest_[mi];
    std::uint64_t hi = newest_[mi];
    if (start_[base + (hi & mask)] <= t) return hi;   // the usual case: t inside the open record
    while (lo < hi) {
        const std::uint64_t mid = lo + (hi - lo + 1) / 2;
        if (start_[base + (mid & mask)] <= t) lo = mid;
        else hi = mid - 1;
    }
    return lo;
}

// Integral from 0 to t (t ≤ now) of level² (above = false) or of [level > rated] (above = true).
double SafetyStage::cumulativeAt(int m, double t, bool above) const noexcept
{
    const std::size_t r = static_cast<std::size_t>(m) * capacity_ + (findRecord(m, t) & (capacity_ - 1));
    // Records are only dropped once they lie entirely before the longest window, so t never
    // falls before the oldest record except before time 0, when nothing was on.
    const double span = std::max(0.0, t - start_[r]);
    const double level = level_[r];
    const double value = above ? (level > params_.ratedLevel ? 1.0 : 0.0) : level * level;
    return (above ? cumA_[r] : cumE_[r]) + value * span;
}

void SafetyStage::dropOld(int m) noexcept
{
    const auto mi = static_cast<std::size_t>(m);
    const std::size_t base = mi * capacity_;
    const std::size_t mask = capacity_ - 1;
    const double keepFrom = now_ - std::max(params_.powerWindow, params_.aboveRatingWindow) - 1e-6;
    while (oldest_[mi] < newest_[mi] && start_[base + ((oldest_[mi] + 1) & mask)] <= keepFrom) ++oldest_[mi];
}

void SafetyStage::push(int m, std::uint8_t level) noexcept
{
    const auto mi = static_cast<std::size_t>(m);
    const std::size_t base = mi * capacity_;
    const std::size_t mask = capacity_ - 1;
    const std::size_t open = base + (newest_[mi] & mask);
    if (level_[open] == level) return;
    if (start_[open] >= now_) {   // the open record has not lasted yet: just relabel it
        level_[open] = level;
        return;
    }
    if (newest_[mi] - oldest_[mi] + 1 >= capacity_) {
        // History full (levels changing every packet at a high rate): keep accounting on the safe
        // side by letting the open record stand for the larger of both levels from now on.
        level_[open] = std::max(level_[open], level);
        return;
    }
    const double elapsed = now_ - start_[open];
    const double l = level_[open];
    const double e = cumE_[open] + l * l * elapsed;
    const double a = cumA_[open] + (level_[open] > params_.ratedLevel ? elapsed : 0.0);
    ++newest_[mi];
    const std::size_t r = base + (newest_[mi] & mask);
    start_[r] = now_;
    cumE_[r] = e;
    cumA_[r] = a;
    level_[r] = level;
}

MotorLevels SafetyStage::process(const MotorLevels& requested, double dt) noexcept
{
    limited_ = 0;
    const bool error = !(dt >= 0.0) || !std::isfinite(dt);
    if (!error) now_ += dt;
    const double horizon = std::max(params_.maxHoldTime, error ? 0.0 : dt);
    const int rated = params_.ratedLevel;
    const double runLimit = params_.maxAboveRatingRun;
    const double dutyWindow = params_.aboveRatingWindow;
    const double dutyLimit = params_.maxAboveRatingFraction * dutyWindow;
    const double powerWindow = params_.powerWindow;
    const double energyLimit = params_.maxMeanPower * double(kMaxLevel * kMaxLevel) * powerWindow;
    const std::size_t mask = capacity_ - 1;

    MotorLevels out {};
    for (int m = 0; m < kMaxMotors; ++m) {
        const auto mi = static_cast<std::size_t>(m);
        // What the previous packet did during the dt that just passed.
        if (!error) {
            const int previous = last_[mi];
            aboveRun_[mi] = previous > rated ? aboveRun_[mi] + dt : 0.0;
            onRun_[mi] = previous > 0 ? onRun_[mi] + dt : 0.0;
            rest_[mi] = std::max(0.0, rest_[mi] - dt);
        }
        dropOld(m);
        int level = std::min<int>(requested[mi], kMaxLevel);
        const int wanted = level;
        if (error || forceOff_ || m >= motorCount_ || rest_[mi] > 0.0) level = 0;

        // Soft vibrations get a time limit too.
        if (level > 0 && onRun_[mi] + horizon > params_.maxOnRun) {
            level = 0;
            rest_[mi] = params_.restAfterOnRun;
        }
        // Above the rating: a run limit and a duty limit.
        if (level > rated) {
            const double above = cumulativeAt(m, now_, true) - cumulativeAt(m, now_ + horizon - dutyWindow, true);
            if (aboveRun_[mi] + horizon > runLimit * (1.0 - kSlack) || above + horizon > dutyLimit * (1.0 - kSlack))
                level = rated;
        }
        // Mean power over every window ending within the horizon.
        if (level > 0) {
            const double total = cumulativeAt(m, now_, false);
            double maxSquare = std::numeric_limits<double>::infinity();
            const auto consider = [&](double d) {
                if (d <= 0.0) return;
                const double history = total - cumulativeAt(m, now_ + d - powerWindow, false);
                maxSquare = std::min(maxSquare, (energyLimit - history) / d);
            };
            consider(horizon);
            // Level changes of the history inside [now − W, now − W + H).
            const std::size_t base = mi * capacity_;
            const double from = now_ - powerWindow, to = now_ - powerWindow + horizon;
            for (std::uint64_t s = findRecord(m, from) + 1; s <= newest_[mi]; ++s) {
                const double st = start_[base + (s & mask)];
                if (st >= to) break;
                if (st > from) consider(st - from);
            }
            // kSquareSlack: the rated level held steadily sits exactly on the limit; rounding in
            // the sums must not make it flicker. Its effect is ≤ 1e-6·H level²·s per window.
            constexpr double kSquareSlack = 1e-6;
            if (!(maxSquare + kSquareSlack >= 1.0)) level = 0;
            else if (maxSquare + kSquareSlack < double(level * level))
                level = std::min(level, int(std::floor(std::sqrt(maxSquare + kSquareSlack))));
        }
        if (level < wanted) ++limited_;
        out[mi] = static_cast<std::uint8_t>(level);
        push(m, out[mi]);
    }
    forceOff_ = false;
    last_ = out;
    return out;
}

} // namespace armadillo
