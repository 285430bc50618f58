#pragma once
// Messages on the arm in the app (issue 35, docs/MQTT.md "In the app"): the message thread's side
// of the core's MessageService (Source/Mqtt): built from the settings (SettingIds::mqtt*), started
// and stopped by the MQTT window, polled by the processor's timer, which hands each message to the
// braille scene when it runs (the messages wait in the inbox otherwise). A service that is
// replaced (new settings) is stopped but kept until the rig goes, because the scene may still hold
// a message it handed over; declare the rig before the engines it serves.
#include "Mqtt/MessageService.h"
#include <juce_data_structures/juce_data_structures.h>
#include <memory>
#include <vector>

namespace armadillo::plugin {

class MessagesRig {
public:
    /// Connects with the settings' broker, topics and display: "" or why not (a bad broker or
    /// topic, a configuration file's error with its line); a broker that is down is no error.
    juce::String start(const juce::ValueTree& settings);
    void stop();
    bool running() const noexcept { return current_ != nullptr; }
    /// The running service (null when stopped).
    mqtt::MessageService* service() noexcept { return current_; }
    const mqtt::MessageService* service() const noexcept { return current_; }
    /// The status line ("stopped" when off).
    juce::String describe() const;

private:
    std::vector<std::unique_ptr<mqtt::MessageService>> services_;   // the current one last; older ones stopped
    mqtt::MessageService* current_ = nullptr;
};

} // namespace armadillo::plugin
