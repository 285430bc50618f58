#pragma once
// The MQTT connection and what is done with it, configured once per process (issue 35,
// docs/MQTT.md): the broker and how to reach it, the topics whose messages the arm reads, how a
// message's text is found, and the default publishing rate of the arm as a remote. Read from a
// JSON file (`--mqtt-config FILE`); command-line options (`--mqtt HOST[:PORT]`, `--messages`)
// override the file's broker and topics.
#include <cstddef>
#include <string>
#include <vector>

namespace armadillo::mqtt {

/// A topic filter to subscribe to ("+" and "#" wildcards allowed, MQTT 3.1.1 §4.7).
struct TopicSubscription {
    std::string filter;
    int qos = 0;            ///< 0, 1 or 2
    bool urgent = false;    ///< its messages interrupt what the reader is reading
};

struct MqttConfig {
    std::string host = "localhost";
    int port = 1883;
    std::string clientId;           ///< "" = "armadillo-<pid>"
    std::string username, password; ///< "" = none
    std::string caFile;             ///< TLS when not empty: the CA certificate (PEM) that signs the broker's
    std::string certFile, keyFile;  ///< TLS client certificate and key (optional, both or neither)
    int protocol = 4;               ///< 4 = MQTT 3.1.1, 5 = MQTT 5
    int keepAlive = 30;             ///< s between pings when idle (MQTT's keep-alive, ≥ 5)
    double reconnectMin = 0.5;      ///< s before the first reconnection attempt
    double reconnectMax = 30.0;     ///< s, the back-off doubles up to this

    // Messages in (MessageInbox).
    std::vector<TopicSubscription> topics;
    std::string textField;          ///< "" = the payload is the text; else the JSON object's field ("a.b" nests)
    std::string priorityField;      ///< "" = none; else a JSON number field, ≥ 1 = urgent
    std::size_t queueCapacity = 16; ///< messages waiting; the oldest is dropped (and counted) beyond it
    std::size_t maxTextBytes = 2000;///< longer texts are refused (and counted), never cut

    // The arm as a remote.
    double publishRate = 10.0;      ///< default messages per second per topic (0 = no limit)

    std::string source;             ///< where it was read from ("" = defaults / command line), for messages
};

/// "HOST", "HOST:PORT", "[IPV6]:PORT" → host and port (port kept when absent). Throws
/// InputError("", 0, option, why) on an empty host or a bad port.
void parseBrokerAddress(const std::string& text, const std::string& option, std::string& host, int& port);

/// Reads a configuration file (format in docs/MQTT.md). Unknown keys, wrong types and values out
/// of range are refused with InputError naming the file, line and key; a missing TLS file too.
MqttConfig loadMqttConfig(const std::string& path);
/// The same from text (`source` names it in messages).
MqttConfig parseMqttConfig(const std::string& text, const std::string& source);

/// Checks a configuration put together from options (throws InputError naming `source`).
void validateMqttConfig(const MqttConfig& config);

/// True when `topic` (a concrete topic name) matches `filter` ("+" one level, "#" the rest).
bool topicMatches(const std::string& filter, const std::string& topic) noexcept;
/// Why a topic filter is not valid ("" when it is): empty, "#" not last, wildcards inside a level.
std::string topicFilterProblem(const std::string& filter);

} // namespace armadillo::mqtt
