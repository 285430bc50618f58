#pragma once
// The motor targets a front end sets by hand (issue 46): the `patch` scene's cell. A patcher
// (Pure Data's [armadillo] `motors L1 … L9`) writes the nine levels of the grid from its own
// thread; the scene reads them in its control step and states them as intents, so they reach
// the motors only through the tactile engine and its safety stage (Core/Scene.h). One writer
// thread at a time, any number of real-time readers (a seqlock: readers never block the writer).
#include "Core/SpscQueue.h"
#include "Core/Types.h"
#include <algorithm>
#include <array>
#include <cmath>

namespace armadillo::core {

class MotorTargets {
public:
    static constexpr int kCount = kGridMotors;   ///< the 3×3 grid, motor 1 first
    static constexpr float kMaxLevel = 15.0f;
    using Levels = std::array<float, kCount>;

    /// Writer thread: the nine targets, each clamped to 0…15 (NaN → 0).
    void set(const Levels& levels) noexcept
    {
        Levels clamped {};
        for (int i = 0; i < kCount; ++i) {
            const float v = levels[static_cast<std::size_t>(i)];
            clamped[static_cast<std::size_t>(i)] = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, kMaxLevel);
        }
        cell_.store(clamped);
    }
    /// Any thread, real-time: the latest targets (`lastGood` when a write overlapped every read).
    Levels load(const Levels& lastGood) const noexcept { return cell_.load(lastGood); }

private:
    SeqLock<Levels> cell_;
};

} // namespace armadillo::core
