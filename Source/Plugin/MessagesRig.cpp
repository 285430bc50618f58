#include "Plugin/MessagesRig.h"
#include "Plugin/PluginState.h"

namespace armadillo::plugin {

juce::String MessagesRig::start(const juce::ValueTree& settings)
{
    stop();
    try {
        const auto file = settings[SettingIds::mqttConfig].toString().trim();
        mqtt::MqttConfig config = file.isNotEmpty() ? mqtt::loadMqttConfig(file.toStdString()) : mqtt::MqttConfig {};
        const auto broker = settings[SettingIds::mqttBroker].toString().trim();
        if (broker.isNotEmpty()) mqtt::parseBrokerAddress(broker.toStdString(), "broker", config.host, config.port);
        const auto add = [&config](const juce::String& list, bool urgent) -> juce::String {
            for (auto t : juce::StringArray::fromTokens(list, ",", "")) {
                t = t.trim();
                if (t.isEmpty()) continue;
                if (const auto why = mqtt::topicFilterProblem(t.toStdString()); ! why.empty()) return "topic '" + t + "': " + juce::String(why);
                config.topics.push_back({t.toStdString(), 1, urgent});
            }
            return {};
        };
        if (auto why = add(settings[SettingIds::mqttTopics].toString(), false); why.isNotEmpty()) return "MQTT: " + why;
        if (auto why = add(settings[SettingIds::mqttUrgent].toString(), true); why.isNotEmpty()) return "MQTT: " + why;
        mqtt::PresenterOptions options;
        options.timed = settings[SettingIds::messageDisplay].toString() == "timed";
        auto service = std::make_unique<mqtt::MessageService>(std::move(config), std::move(options));
        service->start();
        current_ = service.get();
        services_.push_back(std::move(service));
        return {};
    } catch (const std::exception& e) {
        return "MQTT: " + juce::String(e.what());
    }
}

void MessagesRig::stop()
{
    if (current_ != nullptr) current_->stop();
    current_ = nullptr;
}

juce::String MessagesRig::describe() const
{
    return current_ != nullptr ? juce::String(current_->describe()) : juce::String("stopped");
}

} // namespace armadillo::plugin
