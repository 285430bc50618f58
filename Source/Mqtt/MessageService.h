#pragma once
// Messages on the arm as one service (issue 35, docs/MQTT.md): the MQTT client, the inbox its
// messages (and OSC's) wait in, and the presenter that hands them one at a time to the braille
// scene — put together once, for every front end that shows messages (the app's MQTT setup and
// Reader window; `play` and `read` keep their own option parsing around the same parts).
//
// Threads: the client's network thread offers into the inbox; everything else is one owning
// thread (the app's message thread, a command's main loop). The messages handed to a scene are
// owned by the presenter until the scene gives them back: destroy a service only once the scene
// it served has stopped (the app keeps a replaced service until it closes).
#include "Mqtt/ArmMessages.h"
#include "Mqtt/MessageInbox.h"
#include "Mqtt/MqttClient.h"
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace armadillo::mqtt {

class MessageService {
public:
    /// Checks `config` (InputError naming what is wrong); nothing connects before start().
    MessageService(MqttConfig config, PresenterOptions options);
    ~MessageService();
    MessageService(const MessageService&) = delete;
    MessageService& operator=(const MessageService&) = delete;

    /// Starts the client (a broker that is down is no error: it keeps trying, the status says so).
    /// IoError when libmosquitto refuses the configuration.
    void start();
    void stop();

    /// Hands the next message to `scene` when it is free (urgent ones at once); what happened,
    /// in words ("message 3 from 'arm/inbox' on the arm: ...").
    std::vector<std::string> present(braille::BrailleSceneControls& scene) { return presenter_.poll(scene); }
    /// Text from elsewhere (OSC /armadillo/message, a test button): queued as a message from `source`.
    bool offerText(const std::string& text, const std::string& source, int priority) { return inbox_.offerText(text, source, priority); }
    /// A mapping's value for a topic (the arm as a remote): queued for the client's thread, which
    /// applies the rate limit (`maxRate` messages/s; < 0 the configuration's, 0 none) and keeps
    /// the newest value per topic. Real-time, one producer at a time (the control step); false
    /// when it does not fit or the queue is full (counted in the status).
    bool publishValue(std::string_view topic, std::string_view payload, int qos, bool retain, float maxRate) noexcept
    {
        OutgoingMessage o;
        if (!o.set(topic, payload)) return false;
        o.qos = static_cast<std::uint8_t>(qos);
        o.retain = retain;
        o.maxRate = maxRate;
        return client_->publish(o);
    }
    /// Publishes text (a test message to one of the subscribed topics; no rate limit).
    bool publishText(const std::string& topic, const std::string& payload) { return client_->publishText(topic, payload, 1, false); }

    MqttStatus status() const { return client_->status(); }
    InboxStats inbox() const { return inbox_.stats(); }
    std::vector<InboxMessage> recent(std::size_t count = 20) const { return inbox_.recent(count); }
    std::uint64_t shown() const noexcept { return presenter_.shown(); }
    const MqttConfig& config() const noexcept { return config_; }
    MqttClient& client() noexcept { return *client_; }
    /// One line for a status display: "connected to localhost:1883, 2 topics; 5 received, 4 shown,
    /// 1 waiting" (or the state and the last error while it is not connected).
    std::string describe() const;

private:
    MqttConfig config_;
    MessageInbox inbox_;
    MessagePresenter presenter_;
    std::unique_ptr<MqttClient> client_;   // last: its thread stops before the inbox goes
};

} // namespace armadillo::mqtt
