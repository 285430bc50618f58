#pragma once
// The device side of the command line's guided procedures (touch-profile, the adaptive braille
// training, calibrate; Source/Procedures holds the procedures themselves): a serial port (--port)
// or the built-in simulator (--simulate) and a DeviceLink whose handler is an
// access::TactilePlayer. Here, in the live rig, so the front ends never include a source's own
// headers (issue 32).
// Threads: the link's thread runs the player's onPacket and the sensor hook (real-time: no
// allocation, lock or I/O); everything else runs on the caller's (main) thread.
#include "Access/TactilePlayer.h"
#include "Link/Motion.h"
#include "Link/Packets.h"
#include "Live/Sources/SourceRegistry.h"
#include <functional>
#include <memory>
#include <string>

namespace armadillo::live {

using access::TactilePlayer;
using access::TactileSegment;

/// The device side of a guided procedure: a serial port (--port) or the built-in simulator
/// (--simulate), a DeviceLink whose handler is the player. Throws IoError for a missing port.
class GuidedDevice {
public:
    /// `onSensor` (optional) sees every sensor packet on the control thread after the player,
    /// with the player's clock; it must be real-time (no allocation, lock or I/O).
    using SensorHook = std::function<void(const link::SensorCounts&, double t)>;
    /// `motion` (optional): how the simulated forearm moves (default: the wandering arm).
    GuidedDevice(const std::string& port, int baud, bool simulate, bool unpaced, TactilePlayer& player, SensorHook onSensor = {},
                 std::shared_ptr<const link::MotionSource> motion = {});
    ~GuidedDevice();
    GuidedDevice(const GuidedDevice&) = delete;
    GuidedDevice& operator=(const GuidedDevice&) = delete;
    /// Asked while waiting: true ends the wait with IoError("interrupted") (the CLI's SIGINT).
    void setInterruptCheck(std::function<bool()> interrupted) { interrupted_ = std::move(interrupted); }
    /// Waits (polling) until the player completed sequence `n`. IoError when no packet arrives
    /// for 5 s, or when interrupted.
    void waitFor(int n);
    /// Waits (polling every millisecond) until `done()` is true; IoError as waitFor.
    void waitUntil(const std::function<bool()>& done);
    /// IoError when no packet arrived for 5 s (for a caller that waits by itself; call it often).
    void checkAlive();
    link::DeviceLink& link() { return *source_->link(); }

private:
    TactilePlayer& player_;
    SensorHook onSensor_;
    std::function<bool()> interrupted_;
    std::unique_ptr<ArmSource> source_;   // the forearm, opened through the registry (Live/Sources/SourceRegistry.h)
    std::uint64_t lastPackets_ = 0;
    double lastPacketAt_ = -1.0;   ///< s on the steady clock when the packet count last moved
};

} // namespace armadillo::live
