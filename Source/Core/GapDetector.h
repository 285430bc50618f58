#pragma once
// What counts as a dropout in a sample stream, decided in one place for the filter (which bridges
// or re-acquires, docs/FUSION.md) and the links (which report gaps, docs/DEVICE.md): a step longer
// than `factor` × the running typical step and longer than `minGap`. Until a typical step is known
// only a step longer than `firstLimit` is a gap. Plain value type, no heap, any thread that owns it.
#include <algorithm>
#include <cstdint>

namespace armadillo::core {

class GapDetector {
public:
    struct Params {
        double factor = 4.0;        ///< × the typical step
        double minGap = 0.03;       ///< s: shorter steps are never gaps (jittery senders)
        double firstLimit = 0.25;   ///< s: the limit before a typical step is known
        double averaging = 0.01;    ///< weight of each non-gap step in the typical step (≈ 100 steps)
    };
    GapDetector() = default;
    explicit GapDetector(const Params& p) : params_(p) {}

    /// Feeds one step (s, > 0). True when it is a gap (counted; the typical step ignores it).
    bool step(double dt) noexcept
    {
        const double limit = typical_ > 0.0 ? std::max(params_.minGap, params_.factor * typical_) : params_.firstLimit;
        if (dt > limit) {
            ++count_;
            longest_ = std::max(longest_, dt);
            return true;
        }
        typical_ = typical_ > 0.0 ? typical_ + params_.averaging * (dt - typical_) : dt;
        return false;
    }
    void reset() noexcept { typical_ = longest_ = 0.0; count_ = 0; }

    std::uint64_t count() const noexcept { return count_; }
    double longest() const noexcept { return longest_; }      ///< s
    double typicalStep() const noexcept { return typical_; }  ///< s, 0 before the first step
    const Params& params() const noexcept { return params_; }

private:
    Params params_ {};
    double typical_ = 0.0;
    double longest_ = 0.0;
    std::uint64_t count_ = 0;
};

} // namespace armadillo::core
