// MQTT payloads for the arm to read (Mqtt/MessageInbox.h): the text as a configuration takes it
// (the whole payload, or a JSON field, nested, with a priority field), queued in a small inbox.
// Input: a byte choosing the configuration, then the payload.
#include "FuzzTarget.h"
#include "Mqtt/MessageInbox.h"
#include "Mqtt/MqttClient.h"

ARMADILLO_FUZZ_TARGET(mqtt_payload)
{
    using namespace armadillo::mqtt;
    armadillo::fuzz::Bytes in(data, size);
    const std::uint8_t mode = in.byte();
    MqttConfig config;
    switch (mode % 4) {
    case 0: break;
    case 1: config.textField = "text"; break;
    case 2: config.textField = "message.body"; config.priorityField = "priority"; break;
    default: config.textField = "a.b.c"; config.priorityField = "p.q"; break;
    }
    config.queueCapacity = 2;
    config.maxTextBytes = 1 + (mode >> 2) * 16;
    std::string text, why;
    int priority = 0;
    const std::string payload(in.rest());
    (void)messageText(payload, config, text, priority, why);
    MessageInbox inbox(config);
    ReceivedMessage message;
    message.topic = "armadillo/messages";
    message.payload = payload;
    (void)inbox.offer(message);
    (void)inbox.offerText(payload, "osc", mode & 1);
    InboxMessage out;
    while (inbox.pop(out)) {}
    (void)topicMatches(payload, "armadillo/messages/x");
    (void)topicMatches("armadillo/+/#", payload);
}
