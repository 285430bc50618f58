#pragma once
// Position fixes and their hand-over from a position source's own thread (gpsd, OSC, the
// simulated walk) to the control side (issue 34). A source stores every report — a fix, or "no
// fix" — into the mailbox; the navigation scene reads the latest one in its real-time control
// step (a SeqLock: the writer never waits, the reader never blocks; Core/SpscQueue.h). A source
// that stops reporting is noticed by the reader (no new serial within the fix timeout), so a
// lost fix is always said, never guessed.
#include "Core/SpscQueue.h"
#include "Navigation/Geodesy.h"
#include <atomic>
#include <cstdint>
#include <limits>

namespace armadillo::navigation {

enum class FixQuality : std::uint8_t {
    None = 0,   ///< the source is alive but has no position (no satellites, "mode 1" in gpsd)
    Fix2D = 2,  ///< latitude and longitude
    Fix3D = 3,  ///< with altitude
};
const char* fixQualityName(FixQuality q) noexcept;   ///< "none", "2d", "3d"

struct PositionFix {
    LatLon pos {};
    FixQuality quality = FixQuality::None;
    double accuracyM = std::numeric_limits<double>::quiet_NaN();   ///< horizontal (1σ-ish, as the source gives it), m; NaN = unknown
    double speedMps = std::numeric_limits<double>::quiet_NaN();    ///< ground speed, m/s; NaN = unknown
    double courseDeg = std::numeric_limits<double>::quiet_NaN();   ///< course over ground (clockwise from true north), deg; NaN = unknown
    double sourceTime = std::numeric_limits<double>::quiet_NaN();  ///< the source's own time stamp (s, e.g. UTC seconds), for logs only
    std::uint64_t serial = 0;                                      ///< 1, 2, … per report (0 = nothing reported yet)
};

/// One position source → one reader. store() from the source's thread, latest() from the
/// control thread; both real-time (no lock, allocation or wait).
class PositionMailbox {
public:
    /// Publishes a report; its serial is set here (one more than the previous).
    void store(PositionFix fix) noexcept
    {
        fix.serial = serial_.fetch_add(1, std::memory_order_relaxed) + 1;
        box_.store(fix);
    }
    /// The latest report (serial 0 before the first). Bounded: on a torn read it returns the last
    /// good value this reader saw.
    PositionFix latest() noexcept
    {
        last_ = box_.load(last_);
        return last_;
    }
    /// Reports refused by the source as garbage (NaN, out of range) — counted for the summary.
    void countRejected() noexcept { rejected_.fetch_add(1, std::memory_order_relaxed); }
    std::uint64_t rejected() const noexcept { return rejected_.load(std::memory_order_relaxed); }
    std::uint64_t reports() const noexcept { return serial_.load(std::memory_order_relaxed); }

private:
    core::SeqLock<PositionFix> box_;
    std::atomic<std::uint64_t> serial_ {0};   // the one writer's counter
    PositionFix last_ {};         // the one reader's last good value
    std::atomic<std::uint64_t> rejected_ {0};
};

} // namespace armadillo::navigation
