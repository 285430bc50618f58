#include "Live/Sources/GuidedDevice.h"
#include "Core/Clock.h"
#include "Core/Errors.h"
#include "Live/Sources/SourceRegistry.h"
#include <chrono>
#include <thread>

namespace armadillo::live {

GuidedDevice::GuidedDevice(const std::string& port, int baud, bool simulate, bool unpaced, TactilePlayer& player, SensorHook onSensor,
                           std::shared_ptr<const link::MotionSource> motion)
    : player_(player), onSensor_(std::move(onSensor))
{
    ArmSourceDescription description;
    description.kind = ArmSourceDescription::Kind::Forearm;
    description.forearm.simulate = simulate;
    description.forearm.port = port;
    description.forearm.baud = baud;
    description.forearm.openNow = true;   // a missing port is an error now (exit 4), not a silent retry
    description.forearm.motion = std::move(motion);
    description.forearm.simulatorBaud = unpaced ? 0.0 : 57600.0;
    ArmSourceHandlers handlers;
    handlers.onPacket = [this](const link::SensorCounts& counts, double t) {
        const core::MotorLevels out = player_.onPacket(t);
        if (onSensor_) onSensor_(counts, player_.clock());
        return out;
    };
    source_ = openArmSource(description, std::move(handlers));
    source_->start();
}

GuidedDevice::~GuidedDevice() { source_->stop(); }

void GuidedDevice::checkAlive()
{
    const double now = core::monotonicSeconds();
    if (interrupted_ && interrupted_()) throw core::IoError("interrupted");
    if (lastPacketAt_ < 0.0 || player_.packets() != lastPackets_) {
        lastPackets_ = player_.packets();
        lastPacketAt_ = now;
    } else if (now - lastPacketAt_ > 5.0) {
        const std::string why = source_->link()->lastError();
        throw core::IoError("no data from the device for 5 s" + (why.empty() ? std::string() : ": " + why));
    }
}

void GuidedDevice::waitUntil(const std::function<bool()>& done)
{
    lastPacketAt_ = -1.0;   // the 5 s count from the start of this wait
    while (!done()) {
        checkAlive();
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
}

void GuidedDevice::waitFor(int n)
{
    waitUntil([&] { return player_.completed() >= n; });
}

} // namespace armadillo::live
