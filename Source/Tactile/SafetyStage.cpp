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

namespace armadillo::tactile {

namespace {
constexpr std::size_t kRecordsPerMotor = 2048;   // run-length records per motor (power of two)
// Relative slack against rounding in the window sums: limits are met with a hair to spare.
constexpr double kSlack = 1e-9;
} // namespace

SafetyStage::SafetyStage() { prepare(kDefaultSafetyParams, core::kMaxMotors); }

void SafetyStage::prepare(const SafetyParams& params, int motorCount)
{
    params_ = params;
    params_.ratedLevel = std::clamp(params_.ratedLevel, 0, core::kMaxLevel);
    params_.maxHoldTime = std::max(params_.maxHoldTime, 1e-4);
    motorCount_ = std::clamp(motorCount, 0, core::kMaxMotors);
    capacity_ = kRecordsPerMotor;
    const std::size_t n = capacity_ * static_cast<std::size_t>(core::kMaxMotors);
    start_.assign(n, 0.0);
    cumE_.assign(n, 0.0);
    cumA_.assign(n, 0.0);
    level_.assign(n, 0);
    oldest_.fill(0);
    newest_.fill(0);   // one record per motor: level 0 since time 0
    powerCursor_.fill(0);
    dutyCursor_.fill(0);
    aboveRun_.fill(0.0);
    onRun_.fill(0.0);
    rest_.fill(0.0);
    last_.fill(0);
    now_ = 0.0;
    forceOff_ = false;
    limited_ = 0;
}

// Sequence number of the last record starting at or before t (the oldest kept if none does).
// The window edges move forward with time, so a per-motor cursor makes this O(1) amortised.
std::uint64_t SafetyStage::seek(int m, double t, std::uint64_t& cursor) const noexcept
{
    const auto mi = static_cast<std::size_t>(m);
    const std::size_t base = mi * capacity_;
    const std::size_t mask = capacity_ - 1;
    cursor = std::clamp(cursor, oldest_[mi], newest_[mi]);
    while (cursor > oldest_[mi] && start_[base + (cursor & mask)] > t) --cursor;
    while (cursor < newest_[mi] && start_[base + ((cursor + 1) & mask)] <= t) ++cursor;
    return cursor;
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

core::MotorLevels SafetyStage::process(const core::MotorLevels& requested, double dt) noexcept
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
    const double energyLimit = params_.maxMeanPower * double(core::kMaxLevel * core::kMaxLevel) * powerWindow;
    const std::size_t mask = capacity_ - 1;

    core::MotorLevels out {};
    for (int m = 0; m < core::kMaxMotors; ++m) {
        const auto mi = static_cast<std::size_t>(m);
        // What the previous packet did during the dt that just passed.
        if (!error) {
            const int previous = last_[mi];
            aboveRun_[mi] = previous > rated ? aboveRun_[mi] + dt : 0.0;
            onRun_[mi] = previous > 0 ? onRun_[mi] + dt : 0.0;
            rest_[mi] = std::max(0.0, rest_[mi] - dt);
        }
        dropOld(m);
        int level = std::min<int>(requested[mi], core::kMaxLevel);
        const int wanted = level;
        if (error || forceOff_ || m >= motorCount_ || rest_[mi] > 0.0) level = 0;

        // Soft vibrations get a time limit too.
        if (level > 0 && onRun_[mi] + horizon > params_.maxOnRun) {
            level = 0;
            rest_[mi] = params_.restAfterOnRun;
        }
        const std::size_t base = mi * capacity_;
        const std::size_t open = base + (newest_[mi] & mask);
        const auto valueOf = [rated](std::uint8_t l, bool above) {
            return above ? (l > rated ? 1.0 : 0.0) : double(l) * double(l);
        };
        // Integral from 0 to t, starting the search at a cursor.
        const auto cumulative = [&](double t, bool above, std::uint64_t& cursor) {
            const std::size_t r = base + (seek(m, t, cursor) & mask);
            return (above ? cumA_[r] : cumE_[r]) + valueOf(level_[r], above) * std::max(0.0, t - start_[r]);
        };
        // Above the rating: a run limit and a duty limit.
        if (level > rated) {
            const double total = cumA_[open] + valueOf(level_[open], true) * (now_ - start_[open]);
            const double above = total - cumulative(now_ + horizon - dutyWindow, true, dutyCursor_[mi]);
            if (aboveRun_[mi] + horizon > runLimit * (1.0 - kSlack) || above + horizon > dutyLimit * (1.0 - kSlack))
                level = rated;
        }
        // Mean power over every window ending within the horizon: window ends now + d for d in
        // (0, H]; the worst d is H or a level change of the history in (now − W, now − W + H).
        if (level > 0) {
            const double total = cumE_[open] + valueOf(level_[open], false) * (now_ - start_[open]);
            const double from = now_ - powerWindow, to = from + horizon;
            double maxSquare = std::numeric_limits<double>::infinity();
            std::uint64_t s = seek(m, from, powerCursor_[mi]);
            const std::size_t r0 = base + (s & mask);
            const double atFrom = cumE_[r0] + valueOf(level_[r0], false) * std::max(0.0, from - start_[r0]);
            // Fast path: the whole last window plus the new level for all of H fits.
            const bool fits = total - atFrom + double(level * level) * horizon <= energyLimit;
            if (!fits) {
                // The record the window's tail starts in may itself begin inside (from, to]: the
                // very first one, while the window still reaches back before the history (a stage
                // whose first call had dt = 0 starts its first level at time 0). Its start is a
                // level change too.
                if (start_[r0] > from && start_[r0] <= to)
                    maxSquare = std::min(maxSquare, (energyLimit - (total - cumE_[r0])) / (start_[r0] - from));
                while (s < newest_[mi] && start_[base + ((s + 1) & mask)] <= to) {
                    ++s;
                    const std::size_t r = base + (s & mask);
                    const double d = start_[r] - from;
                    if (d > 0.0) maxSquare = std::min(maxSquare, (energyLimit - (total - cumE_[r])) / d);
                }
                const std::size_t r = base + (s & mask);
                const double atTo = cumE_[r] + valueOf(level_[r], false) * std::max(0.0, to - start_[r]);
                maxSquare = std::min(maxSquare, (energyLimit - (total - atTo)) / horizon);
                // kSquareSlack: the rated level held steadily sits exactly on the limit; rounding in
                // the sums must not make it flicker. Its effect is ≤ 1e-6·H level²·s per window.
                constexpr double kSquareSlack = 1e-6;
                if (!(maxSquare + kSquareSlack >= 1.0)) level = 0;
                else if (maxSquare + kSquareSlack < double(level * level))
                    level = std::min(level, int(std::floor(std::sqrt(maxSquare + kSquareSlack))));
            }
        }
        if (level < wanted) ++limited_;
        out[mi] = static_cast<std::uint8_t>(level);
        push(m, out[mi]);
    }
    forceOff_ = false;
    last_ = out;
    return out;
}

} // namespace armadillo::tactile
