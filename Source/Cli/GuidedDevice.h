#pragma once
// The device side of the command line's guided procedures: a serial port (--port) or the
// built-in simulator (--simulate) and a DeviceLink whose handler is an access::TactilePlayer.
#include "Access/TactilePlayer.h"
#include "Link/DeviceLink.h"
#include "Link/Simulator.h"
#include <functional>
#include <memory>
#include <string>

namespace armadillo::cli {

using access::TactilePlayer;
using access::TactileSegment;

/// The device side of a guided procedure: a serial port (--port) or the built-in simulator
/// (--simulate), a DeviceLink whose handler is the player. Throws IoError for a missing port.
class GuidedDevice {
public:
    /// `onSensor` (optional) sees every sensor packet on the control thread after the player,
    /// with the player's clock; it must be real-time (no allocation, lock or I/O).
    using SensorHook = std::function<void(const device::SensorCounts&, double t)>;
    GuidedDevice(const std::string& port, int baud, bool simulate, bool unpaced, TactilePlayer& player, SensorHook onSensor = {});
    ~GuidedDevice();
    /// Waits (polling, ends on SIGINT) until the player completed sequence `n`. IoError when no
    /// packet arrives for 5 s.
    void waitFor(int n);
    device::DeviceLink& link() { return *link_; }

private:
    TactilePlayer& player_;
    SensorHook onSensor_;
    std::unique_ptr<device::SimulatedForearm> simulator_;
    std::unique_ptr<device::DeviceLink> link_;
};

} // namespace armadillo::cli
