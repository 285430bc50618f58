#include "Mqtt/BrokerCheck.h"
#include "Core/Errors.h"
#include "Core/Json.h"
#include "Mqtt/MessageInbox.h"
#include "Mqtt/MqttClient.h"
#include <chrono>
#include <mutex>
#include <thread>

namespace armadillo::mqtt {

std::string brokerCheckLine(const ReceivedMessage& m, const MqttConfig& config)
{
    std::string line = "{\"topic\":";
    core::appendJsonString(line, m.topic);
    line += ",\"bytes\":" + std::to_string(m.payload.size()) + ",\"retained\":" + (m.retained ? "true" : "false") + ",\"text\":";
    MqttConfig plain;
    plain.textField = config.textField;
    std::string text, why;
    int priority = 0;
    if (m.payload.size() <= 4096 && messageText(m.payload, plain, text, priority, why)) core::appendJsonString(line, text);
    else core::appendJsonString(line, "(not shown: " + (m.payload.size() > 4096 ? std::to_string(m.payload.size()) + " bytes" : why) + ")");
    return line + "}";
}

BrokerCheckResult checkBroker(const MqttConfig& config, const BrokerCheckOptions& options,
                              const std::function<void(const std::string&)>& onMessage, const std::function<void(const std::string&)>& say,
                              const std::function<bool()>& interrupted)
{
    std::mutex mutex;
    long heard = 0;
    MqttClient client(config);
    client.setMessageHandler([&](const ReceivedMessage& m) {
        const std::string line = brokerCheckLine(m, config);
        std::lock_guard lock(mutex);
        ++heard;
        onMessage(line);
    });
    client.start();
    say("connecting to " + config.host + ":" + std::to_string(config.port));
    if (!client.waitConnected(options.timeout)) {
        const MqttStatus s = client.status();
        client.stop();
        throw core::IoError("mqtt check: no connection to " + s.broker + " within " + std::to_string(options.timeout).substr(0, 4) + " s: " +
                            (s.lastError.empty() ? std::string("no answer") : s.lastError));
    }
    std::string subscribed = "connected to " + config.host + ":" + std::to_string(config.port) + ", subscribed to";
    for (const auto& t : config.topics) subscribed += " '" + t.filter + "'";
    char listening[64];
    std::snprintf(listening, sizeof listening, "; listening for %g s", options.seconds);
    say(subscribed + listening);
    if (options.publish && !config.topics.empty()) client.publishText(config.topics[0].filter, options.text, 1);
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.seconds);
    while (!interrupted() && std::chrono::steady_clock::now() < end) {
        {
            std::lock_guard lock(mutex);
            if (options.maxCount > 0 && heard >= options.maxCount) break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    const MqttStatus s = client.status();
    client.stop();
    std::lock_guard lock(mutex);
    return {heard, s.broker, s.connects};
}

} // namespace armadillo::mqtt
