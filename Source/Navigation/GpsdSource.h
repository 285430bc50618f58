#pragma once
// Positions from gpsd, the standard Linux GPS daemon (any receiver gpsd knows, or a phone that
// forwards NMEA to it), through libgps and gpsd's JSON protocol (WATCH with "json":true; each
// TPV report carries the fix mode 1 = none, 2 = 2D, 3 = 3D, latitude, longitude, the
// horizontal error estimate eph, speed and track). See gpsd's own documentation of the
// protocol (gpsd_json(5)) and libgps(3).
//
// The source runs on its own thread and stores every TPV report — a fix, or "no fix" — into a
// PositionMailbox (lock-free). A report with mode ≥ 2 whose latitude/longitude are not numbers or
// out of range is refused (counted) and stored as "no fix": the walker feels the fix lost, never
// a wrong direction. A gpsd that goes away is reported (no more reports: the scene's timeout),
// and the source reconnects every second.
#include "Navigation/Position.h"
#include <atomic>
#include <memory>
#include <string>
#include <string_view>
#include <thread>

namespace armadillo::navigation {

struct GpsdEndpoint {
    std::string host = "localhost";
    std::string port = "2947";   ///< gpsd's registered port
};
/// "HOST:PORT", "HOST", ":PORT" or "" (localhost:2947); "[::1]:PORT" for IPv6. InputError
/// (source "--gpsd") for a bad port.
GpsdEndpoint parseGpsdEndpoint(const std::string& text);

/// What one gpsd report gives the walker: nothing (not a TPV report: VERSION, DEVICES, SKY, …),
/// a fix, "no fix", or a position refused as garbage (then `out` is "no fix").
enum class GpsdReport : std::uint8_t { None, Fix, NoFix, Rejected };
/// One line of gpsd's JSON protocol (gpsd_json(5)) as the source reads it (every line it
/// receives): a TPV report's mode, time, lat, lon, eph (or epx, epy), speed and track; a fix
/// whose position is not two numbers in range is Rejected. libgps only connects and asks for
/// the reports (its own JSON reader hangs on some malformed ones).
GpsdReport readGpsdJson(std::string_view line, PositionFix& out);

class GpsdSource {
public:
    /// Connects now: IoError naming the host and port when gpsd cannot be reached.
    GpsdSource(const GpsdEndpoint& endpoint, PositionMailbox& mailbox);
    ~GpsdSource();
    GpsdSource(const GpsdSource&) = delete;
    GpsdSource& operator=(const GpsdSource&) = delete;
    void start();
    void stop();

    std::uint64_t fixes() const noexcept { return fixes_.load(); }        ///< reports with a usable fix
    std::uint64_t noFix() const noexcept { return noFix_.load(); }        ///< reports without one
    std::uint64_t rejected() const noexcept { return rejected_.load(); }  ///< garbage positions refused
    std::uint64_t disconnects() const noexcept { return disconnects_.load(); }
    bool connected() const noexcept { return connected_.load(); }
    std::string describe() const { return endpoint_.host + ":" + endpoint_.port; }

private:
    struct Impl;
    void run();
    GpsdEndpoint endpoint_;
    PositionMailbox& mailbox_;
    std::unique_ptr<Impl> impl_;
    std::thread thread_;
    std::atomic<bool> running_ {false}, connected_ {false};
    std::atomic<std::uint64_t> fixes_ {0}, noFix_ {0}, rejected_ {0}, disconnects_ {0};
};

} // namespace armadillo::navigation
