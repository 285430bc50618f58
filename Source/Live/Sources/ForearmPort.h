#pragma once
// Where a forearm's packets come from, opened once for every rig that reads one: a serial port
// (the real device, or a Bluetooth serial link) or the device module's simulated forearm,
// in-process. `armadillo play` (both arms), the app's and plugin's device source
// (DeviceConnection) and the command line's guided procedures (GuidedDevice) all open their port
// here and differ only in what they ask: probe the port now or let the link wait for it, how the
// simulated arm moves and how fast its link is paced.
#include "Link/Motion.h"
#include <cstdint>
#include <memory>
#include <string>

namespace armadillo::link {
class LinkPort;
class SimulatedForearm;
} // namespace armadillo::link

namespace armadillo::live {

struct ForearmPortRequest {
    bool simulate = false;       ///< the simulated forearm instead of `port`
    std::string port;            ///< serial port path (not simulated)
    int baud = 57600;
    /// Not simulated: open the port now, so a missing or busy port is an IoError naming it
    /// (exit 4 on the command line). Off: the link opens it, and retries while it is missing
    /// (the app's device source, which reports "Waiting for" instead).
    bool openNow = true;
    /// Simulated: how the arm moves (null: the wandering arm with `seed`), the link's pace in
    /// baud (0: unpaced, as fast as the reader takes it) and the board thread's SCHED_FIFO
    /// priority (0: none).
    std::shared_ptr<const link::MotionSource> motion;
    std::uint64_t seed = 1;
    double simulatorBaud = 57600.0;
    int simulatorPriority = 0;
};

/// An opened forearm port. A simulated one owns its simulator: stop the link reading `port`
/// first, then the simulator (stop() or the destructor).
struct ForearmPort {
    std::unique_ptr<link::LinkPort> port;
    std::unique_ptr<link::SimulatedForearm> simulator;

    ForearmPort();
    ForearmPort(ForearmPort&&) noexcept;
    ForearmPort& operator=(ForearmPort&&) noexcept;
    ~ForearmPort();
};

/// Opens the port `request` names. Throws IoError for a port that cannot be opened (openNow).
ForearmPort openForearmPort(const ForearmPortRequest& request);

} // namespace armadillo::live
