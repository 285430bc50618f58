#include "Live/Sources/ForearmPort.h"
#include "Link/LinkPort.h"
#include "Link/Simulator.h"

namespace armadillo::live {

ForearmPort::ForearmPort() = default;
ForearmPort::ForearmPort(ForearmPort&&) noexcept = default;
ForearmPort& ForearmPort::operator=(ForearmPort&&) noexcept = default;
ForearmPort::~ForearmPort() = default;

ForearmPort openForearmPort(const ForearmPortRequest& request)
{
    ForearmPort out;
    if (!request.simulate) {
        auto port = std::make_unique<link::SerialPort>(request.port, request.baud);
        if (request.openNow) port->open();   // the port's own message; later losses reconnect in the link
        out.port = std::move(port);
        return out;
    }
    link::SimulatorOptions options;
    options.baud = request.simulatorBaud;
    options.realtimePriority = request.simulatorPriority;
    auto motion = request.motion ? request.motion : std::make_shared<link::WanderingMotion>(request.seed);
    out.simulator = std::make_unique<link::SimulatedForearm>(std::move(motion), options);
    out.port = out.simulator->startInProcess();
    return out;
}

} // namespace armadillo::live
