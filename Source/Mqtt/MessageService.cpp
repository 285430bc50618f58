#include "Mqtt/MessageService.h"

namespace armadillo::mqtt {

MessageService::MessageService(MqttConfig config, PresenterOptions options)
    : config_((validateMqttConfig(config), std::move(config))), inbox_(config_), presenter_(inbox_, std::move(options))
{
    client_ = std::make_unique<MqttClient>(config_);
    client_->setMessageHandler([this](const ReceivedMessage& m) { inbox_.offer(m); });
}

MessageService::~MessageService()
{
    stop();
}

void MessageService::start()
{
    client_->start();
}

void MessageService::stop()
{
    if (client_) client_->stop();
}

std::string MessageService::describe() const
{
    const MqttStatus s = client_->status();
    const InboxStats in = inbox_.stats();
    std::string line = std::string(connectionStateName(s.state)) + " " + (s.state == ConnectionState::Connected ? "to " : "") + s.broker;
    if (s.state == ConnectionState::Connected)
        line += ", " + std::to_string(s.subscriptions) + " topic" + (s.subscriptions == 1 ? "" : "s");
    else if (!s.lastError.empty())
        line += " (" + s.lastError + ")";
    if (s.connects > 1) line += ", reconnected " + std::to_string(s.connects - 1) + "x";
    line += "; " + std::to_string(in.accepted) + " received, " + std::to_string(presenter_.shown()) + " shown, " + std::to_string(in.waiting) + " waiting";
    if (in.droppedOldest > 0) line += ", " + std::to_string(in.droppedOldest) + " dropped (queue full)";
    if (in.refused > 0) line += ", " + std::to_string(in.refused) + " refused: " + in.lastRefusal;
    return line;
}

} // namespace armadillo::mqtt
