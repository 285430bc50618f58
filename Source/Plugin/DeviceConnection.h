#pragma once
// The device source: a serial port (or the device module's simulated forearm, in-process) run by
// the device module's DeviceLink on its own thread. Each good sensor packet is calibrated (counts
// → SI, once, at the edge) and queued for the control loop, which fuses it (SR-UKF in
// ArmTracker); the link answers with the latest motor levels the control loop published.
// A real port is claimed through PortRegistry first, so two instances never fight over it.
#include "Core/Types.h"
#include "Device/Calibration.h"
#include "Plugin/LiveInput.h"
#include "Plugin/PortRegistry.h"
#include <functional>
#include <memory>
#include <string>

namespace armadillo::device {
class DeviceLink;
class SimulatedForearm;
} // namespace armadillo::device

namespace armadillo::plugin {

class DeviceConnection {
public:
    /// The port name that selects the device module's simulated forearm (full protocol, no hardware).
    static constexpr const char* kSimulatedPort = "simulated forearm (in-process)";

    DeviceConnection(LiveInput& input, std::function<MotorLevels()> latestLevels);
    ~DeviceConnection();

    /// Message thread. Returns false with `message` saying why (port owned elsewhere, cannot open…).
    bool connect(const std::string& port, int baud, const std::string& calibrationFile, std::string& message);
    void disconnect();
    bool isOpen() const noexcept { return link_ != nullptr; }
    /// Link statistics for the UI (message thread).
    std::string status() const;

private:
    LiveInput& input_;
    std::function<MotorLevels()> latestLevels_;
    device::Calibration calibration_;
    std::string calibrationNote_;
    std::unique_ptr<PortClaim> claim_;
    std::unique_ptr<device::SimulatedForearm> simulator_;
    std::unique_ptr<device::DeviceLink> link_;
};

} // namespace armadillo::plugin
