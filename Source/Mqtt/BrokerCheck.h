#pragma once
// `armadillo mqtt check` as a procedure of the messages room (docs/MQTT.md): connect to the broker
// a configuration describes, subscribe to its topics, hand each message heard on as a JSON line
// (topic, bytes, retained, text), optionally publish one text to the one topic first, and say how
// it went. The front end only describes the broker and prints.
//
// Threads: checkBroker() on the caller's thread; onMessage is called on the client's thread
// (one at a time), say and interrupted on the caller's.
#include "Mqtt/MqttConfig.h"
#include <cstdint>
#include <functional>
#include <string>

namespace armadillo::mqtt {

struct ReceivedMessage;

struct BrokerCheckOptions {
    double timeout = 5.0;      ///< s to wait for the connection (IoError after it)
    double seconds = 5.0;      ///< s to listen once connected (0 = only connect)
    long maxCount = 0;         ///< stop after this many messages (0 = no limit)
    bool publish = false;      ///< publish `text` to the one topic once subscribed
    std::string text;
};

struct BrokerCheckResult {
    long heard = 0;
    std::string broker;        ///< HOST:PORT as the client names it
    std::uint64_t connects = 0;
};

/// One message as the check prints it: {"topic":…,"bytes":…,"retained":…,"text":…}; a payload over
/// 4096 bytes or one that is not text is "(not shown: …)".
std::string brokerCheckLine(const ReceivedMessage& message, const MqttConfig& config);

/// Runs the check. IoError when no connection is made within options.timeout (naming the cause).
BrokerCheckResult checkBroker(const MqttConfig& config, const BrokerCheckOptions& options,
                              const std::function<void(const std::string& jsonLine)>& onMessage,
                              const std::function<void(const std::string& text)>& say, const std::function<bool()>& interrupted);

} // namespace armadillo::mqtt
