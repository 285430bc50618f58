#include "Live/Outputs/MessagesRig.h"
#include "Live/Sources/SourceRegistry.h"
#include "Core/Text.h"

namespace armadillo::live {

namespace {


/// Each comma-separated filter of `list` subscribed (urgent or not). "" or why one is refused.
std::string addTopics(mqtt::MqttConfig& config, const std::string& list, bool urgent)
{
    std::size_t from = 0;
    while (from <= list.size()) {
        const std::size_t comma = std::min(list.find(',', from), list.size());
        const std::string t = core::trimmed(list.substr(from, comma - from));
        from = comma + 1;
        if (t.empty()) continue;
        if (const auto why = mqtt::topicFilterProblem(t); !why.empty()) return "topic '" + t + "': " + why;
        config.topics.push_back({t, 1, urgent});
    }
    return {};
}

} // namespace

std::string MessagesRig::start(const MessagesSettings& settings)
{
    stop();
    try {
        const std::string file = core::trimmed(settings.configFile);
        mqtt::MqttConfig config = !file.empty() ? mqtt::loadMqttConfig(file) : mqtt::MqttConfig {};
        const std::string broker = core::trimmed(settings.broker);
        if (!broker.empty()) mqtt::parseBrokerAddress(broker, "broker", config.host, config.port);
        if (auto why = addTopics(config, settings.topics, false); !why.empty()) return "MQTT: " + why;
        if (auto why = addTopics(config, settings.urgent, true); !why.empty()) return "MQTT: " + why;
        mqtt::PresenterOptions options;
        options.timed = settings.timed;
        open(std::move(config), std::move(options)).start();
        return {};
    } catch (const std::exception& e) {
        return std::string("MQTT: ") + e.what();
    }
}

mqtt::MessageService& MessagesRig::open(mqtt::MqttConfig config, mqtt::PresenterOptions options)
{
    stop();
    auto service = openMessageSource(std::move(config), std::move(options));   // the registry (Live/Sources/SourceRegistry.h)
    current_ = service.get();
    services_.push_back(std::move(service));
    return *current_;
}

void MessagesRig::stop()
{
    if (current_ != nullptr) current_->stop();
    current_ = nullptr;
}

std::string MessagesRig::describe() const
{
    return current_ != nullptr ? current_->describe() : std::string("stopped");
}

} // namespace armadillo::live
