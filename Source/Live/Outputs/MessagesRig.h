#pragma once
// Messages on the arm for an instrument that starts and stops them while it runs (issue 35,
// docs/MQTT.md "In the app"; below JUCE since issue 45): the core's MessageService (Source/Mqtt)
// built from a front end's settings, started and stopped by its MQTT window, polled by its timer,
// which hands each message to the braille scene when it runs (the messages wait in the inbox
// otherwise). A service that is replaced (new settings) is stopped but kept until the rig goes,
// because the scene may still hold a message it handed over; declare the rig before the engines
// it serves.
#include "Mqtt/MessageService.h"
#include <memory>
#include <string>
#include <vector>

namespace armadillo::live {

/// Messages as a front end's settings name them (plain text, as the CLI's options take them).
struct MessagesSettings {
    std::string configFile;   ///< a configuration file (docs/MQTT.md), "" = none
    std::string broker;       ///< HOST[:PORT] ("" = the file's, else localhost:1883)
    std::string topics;       ///< topic filters, comma-separated
    std::string urgent;       ///< topic filters whose messages interrupt, comma-separated
    bool timed = false;       ///< the display: timed (true) or rolled (false)
};

class MessagesRig {
public:
    /// Connects with the settings' broker, topics and display: "" or why not, beginning "MQTT: "
    /// (a bad broker or topic, a configuration file's error with its line); a broker that is down
    /// is no error.
    std::string start(const MessagesSettings& settings);
    /// A configuration already read (the command line's options): the service built through the
    /// registry, current but not connected (its start() connects). Throws InputError for a bad
    /// configuration. A running service is stopped first.
    mqtt::MessageService& open(mqtt::MqttConfig config, mqtt::PresenterOptions options);
    void stop();
    bool running() const noexcept { return current_ != nullptr; }
    /// The running service (null when stopped).
    mqtt::MessageService* service() noexcept { return current_; }
    const mqtt::MessageService* service() const noexcept { return current_; }
    /// The status line ("stopped" when off).
    std::string describe() const;

private:
    std::vector<std::unique_ptr<mqtt::MessageService>> services_;   // the current one last; older ones stopped
    mqtt::MessageService* current_ = nullptr;
};

} // namespace armadillo::live
