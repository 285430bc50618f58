#include "Cli/GuidedDevice.h"
#include "Cli/CommandLine.h"
#include "Core/Errors.h"
#include <chrono>
#include <thread>

namespace armadillo::cli {

GuidedDevice::GuidedDevice(const std::string& port, int baud, bool simulate, bool unpaced, TactilePlayer& player, SensorHook onSensor)
    : player_(player), onSensor_(std::move(onSensor))
{
    std::unique_ptr<device::LinkPort> p;
    if (!simulate) {
        p = std::make_unique<device::SerialPort>(port, baud);
        p->open();   // a missing port is an error now (exit 4), not a silent retry
        p->close();
    } else {
        device::SimulatorOptions so;
        so.baud = unpaced ? 0.0 : 57600.0;
        simulator_ = std::make_unique<device::SimulatedForearm>(std::make_shared<device::WanderingMotion>(), so);
        p = simulator_->startInProcess();
    }
    link_ = std::make_unique<device::DeviceLink>(std::move(p), [this](const device::SensorCounts& counts, double t) {
        const MotorLevels out = player_.onPacket(t);
        if (onSensor_) onSensor_(counts, player_.clock());
        return out;
    });
    link_->start();
}

GuidedDevice::~GuidedDevice()
{
    link_->stop();
    if (simulator_) simulator_->stop();
}

void GuidedDevice::waitFor(int n)
{
    auto since = std::chrono::steady_clock::now();
    std::uint64_t packets = player_.packets();
    while (player_.completed() < n) {
        if (interrupted()) throw IoError("interrupted");
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        if (player_.packets() != packets) {
            packets = player_.packets();
            since = std::chrono::steady_clock::now();
        } else if (std::chrono::steady_clock::now() - since > std::chrono::seconds(5)) {
            const std::string why = link_->lastError();
            throw IoError("no data from the device for 5 s" + (why.empty() ? std::string() : ": " + why));
        }
    }
}

} // namespace armadillo::cli
