#pragma once
// Messages for the arm to read (issue 35, docs/MQTT.md): text from subscribed MQTT topics (the
// UTF-8 payload, or a JSON field named in the configuration) and from OSC
// (`/armadillo/message "text" [priority]`), waiting in a bounded queue until the reader is free.
// When the queue is full the OLDEST waiting message is dropped and counted; urgent messages (a
// priority ≥ 1, or a topic marked urgent) are taken before the others. Bad messages are refused
// with a reason and counted, never cut or guessed at.
//
// Thread-safe (a mutex): producers are the MQTT network thread and the OSC thread, the consumer
// the front end's main loop; never used on the real-time control step.
#include "Mqtt/MqttConfig.h"
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <vector>

namespace armadillo::mqtt {

struct ReceivedMessage;

struct InboxMessage {
    std::uint64_t id = 0;       ///< 1, 2, … in order of arrival
    std::string text;           ///< valid UTF-8, one line, trimmed, not empty
    std::string source;         ///< the topic, or "osc"
    bool urgent = false;
};

struct InboxStats {
    std::uint64_t offered = 0;      ///< messages that arrived
    std::uint64_t accepted = 0;     ///< queued
    std::uint64_t taken = 0;        ///< handed to the reader (pop)
    std::uint64_t droppedOldest = 0;///< queued, then dropped because the queue overflowed
    std::uint64_t refused = 0;      ///< not queued: invalid UTF-8, bad JSON, a missing field, too long, empty
    std::string lastRefusal;        ///< why the last refused message was refused, naming its source
    std::size_t waiting = 0;
    std::size_t capacity = 0;
};

/// The text of a payload as `config` says (textField / priorityField), or false with `why`.
/// Line breaks and tabs become spaces; other control characters and invalid UTF-8 are refused.
bool messageText(const std::string& payload, const MqttConfig& config, std::string& text, int& priority, std::string& why);

class MessageInbox {
public:
    explicit MessageInbox(const MqttConfig& config);

    /// An MQTT message on a subscribed topic: its text extracted and queued; false when refused.
    bool offer(const ReceivedMessage& message);
    /// Text from elsewhere (OSC): checked as a payload is, queued; false when refused.
    bool offerText(const std::string& text, const std::string& source, int priority);

    /// The next message: the oldest urgent one, else the oldest. False when none waits.
    bool pop(InboxMessage& out);
    bool urgentWaiting() const;
    InboxStats stats() const;
    /// The last messages queued (at most `count`, newest last), for a UI's message list.
    std::vector<InboxMessage> recent(std::size_t count = 20) const;

private:
    bool queue(std::string text, const std::string& source, bool urgent);
    void refuse(const std::string& source, const std::string& why);

    MqttConfig config_;
    mutable std::mutex mutex_;
    std::deque<InboxMessage> waiting_;
    std::deque<InboxMessage> recent_;
    InboxStats stats_;
    std::uint64_t nextId_ = 1;
};

} // namespace armadillo::mqtt
