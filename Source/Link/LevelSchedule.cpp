#include "Link/LevelSchedule.h"
#include <algorithm>

namespace armadillo::link {

bool LevelSchedule::push(double t, const core::MotorLevels& levels) noexcept
{
    Stamped s;
    s.t = t;
    s.levels = levels;
    if (queue_.push(s)) return true;
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return false;
}

core::MotorLevels LevelSchedule::due(double now) noexcept
{
    if (offRequested_.exchange(false, std::memory_order_acq_rel)) {
        // Everything queued so far was computed before the request: forget it.
        Stamped drop;
        while (queue_.pop(drop)) {
        }
        havePending_ = false;
        current_ = Stamped {now, {}, true};
    }
    for (;;) {
        if (!havePending_) {
            if (!queue_.pop(pending_)) break;
            havePending_ = true;
        }
        if (pending_.t > now) break;   // its time has not come yet
        current_ = pending_;
        havePending_ = false;
    }
    const bool stale = current_.off || now - current_.t > params_.staleAfter;
    if (stale && !stale_ && !current_.off) staleOffs_.fetch_add(1, std::memory_order_relaxed);
    stale_ = stale;
    const core::MotorLevels dueNow = stale ? core::MotorLevels {} : current_.levels;
    // A packet stays on until the next one. Sent as soon as it is due, a level that starts late in
    // a packet interval and ends early in another gains up to one interval on the motor; the lower
    // of now and before gives every rise one packet of delay and every fall none, so the run on
    // the motor is never longer than the run the safety stage planned.
    core::MotorLevels out {};
    for (std::size_t m = 0; m < out.size(); ++m) out[m] = std::min(dueNow[m], dueBefore_[m]);
    dueBefore_ = dueNow;
    return out;
}

} // namespace armadillo::link
