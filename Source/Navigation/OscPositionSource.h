#pragma once
// Positions over OSC/UDP (issue 34), on their own thread, into a PositionMailbox:
//   /armadillo/position lat lon [accuracy_m]   (ARMadillo's own address, docs/INTERFACES.md;
//                                               numbers of any OSC numeric type, degrees and metres)
//   /<uuid>/gps lat lon, /ZIGSIM/<uuid>/gps lat lon   (ZIG SIM's OSC mode: its `gps` command)
//   {"sensordata": {"gps": {"latitude": …, "longitude": …}}}   (ZIG SIM's JSON mode)
// The ZIG SIM forms follow the addresses the OSC dialects already read for its motion
// (Osc/OscDialects.cpp cites ZIG SIM's own documentation); issue 34 names its `gps` command.
// Anything else on the port is ignored (counted); a position that is not two finite numbers in
// range is refused (counted) and reported as "no fix", so the walker feels the fix lost rather
// than a wrong direction.
#include "Navigation/Position.h"
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <thread>

namespace armadillo::navigation {

/// One UDP datagram → a report. Returns true when it was a position message (then `out` holds a
/// fix, or "no fix" with `rejected` set for a bad one); false for anything else. Not real-time
/// (the JSON form parses into a tree); runs on the source's thread.
bool decodePositionDatagram(const std::uint8_t* data, std::size_t size, PositionFix& out, bool& rejected);

/// What a position reader saw (any thread reads).
struct PositionCounters {
    std::atomic<std::uint64_t> fixes {0}, rejected {0}, ignored {0};
};
/// Decodes one datagram; a position (or a refused one, as "no fix") goes into the mailbox.
/// Counts; returns true when the datagram was a position message.
bool storePositionDatagram(const std::uint8_t* data, std::size_t size, PositionMailbox& mailbox, PositionCounters& counters);

class OscPositionSource {
public:
    /// Binds the UDP port on every interface (0 = a free one): IoError when it cannot.
    OscPositionSource(int port, PositionMailbox& mailbox);
    ~OscPositionSource();
    OscPositionSource(const OscPositionSource&) = delete;
    OscPositionSource& operator=(const OscPositionSource&) = delete;
    void start();
    void stop();
    int port() const noexcept { return port_; }
    std::uint64_t fixes() const noexcept { return counters_.fixes.load(); }
    std::uint64_t rejected() const noexcept { return counters_.rejected.load(); }
    std::uint64_t ignored() const noexcept { return counters_.ignored.load(); }

private:
    void run();
    PositionMailbox& mailbox_;
    int fd_ = -1, port_ = 0;
    std::thread thread_;
    std::atomic<bool> running_ {false};
    PositionCounters counters_;
};

} // namespace armadillo::navigation
