#include "Live/Sources/SourceRegistry.h"
#include "Core/Errors.h"
#include "Link/LinkPort.h"
#include "Link/Simulator.h"
#include "Mqtt/MessageService.h"

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

ArmSource::ArmSource() = default;

ArmSource::~ArmSource() { stop(); }

void ArmSource::start()
{
    if (link_) link_->start();
    if (osc_) osc_->start();
}

void ArmSource::stop()
{
    if (link_) link_->stop();   // no motor packet leaves after this
    if (osc_) osc_->stop();
    if (simulator_) simulator_->stop();
}

ArmSource& ArmSourceSlot::open(const ArmSourceDescription& description, ArmSourceHandlers handlers)
{
    close();
    source_ = openArmSource(description, std::move(handlers));
    return *source_;
}

void ArmSourceSlot::close() noexcept
{
    if (source_ != nullptr) source_->stop();
    source_.reset();
}

std::unique_ptr<ArmSource> openArmSource(const ArmSourceDescription& description, ArmSourceHandlers handlers)
{
    std::unique_ptr<ArmSource> source(new ArmSource());
    switch (description.kind) {
    case ArmSourceDescription::Kind::Forearm: {
        if (!handlers.onPacket) throw core::InputError("", 0, "", "a forearm source needs a packet handler");
        ForearmPort port = openForearmPort(description.forearm);   // IoError naming the port
        source->simulator_ = std::move(port.simulator);
        source->link_ = std::make_unique<link::DeviceLink>(std::move(port.port), std::move(handlers.onPacket), description.link);
        break;
    }
    case ArmSourceDescription::Kind::OscUdp:
        source->osc_ = std::make_unique<osc::OscReceiver>(description.oscPort, std::move(handlers.onImu), std::move(handlers.onOrientation),
                                                          description.osc);   // IoError when the port is taken
        break;
    case ArmSourceDescription::Kind::OscSerial:
        source->osc_ = std::make_unique<osc::OscReceiver>(description.oscSerial, std::move(handlers.onImu), std::move(handlers.onOrientation),
                                                          description.osc);   // IoError when the port is not there
        break;
    }
    return source;
}

std::unique_ptr<mqtt::MessageService> openMessageSource(mqtt::MqttConfig config, mqtt::PresenterOptions options)
{
    return std::make_unique<mqtt::MessageService>(std::move(config), std::move(options));
}

} // namespace armadillo::live
