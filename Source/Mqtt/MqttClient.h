#pragma once
// One MQTT connection per process (issue 35, docs/MQTT.md), over libmosquitto, on its own network
// thread: it connects, subscribes to the configured topics (again after every reconnection),
// hands each message to a handler on that thread, and publishes what the real-time side queued.
// Reconnection backs off from MqttConfig::reconnectMin, doubling up to reconnectMax.
//
// Threads: start()/stop() and the constructor on the owner's thread; publish() from ONE producer
// that may be real-time (the control step: an SPSC queue of fixed-size records, no lock, no
// allocation); publishText() from any non-real-time thread (a mutex); status() from any thread
// (a mutex-guarded snapshot, for a UI timer or the command line — never from the control step).
#include "Core/SpscQueue.h"
#include "Mqtt/MqttConfig.h"
#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>

struct mosquitto;
struct mosquitto_message;

namespace armadillo::mqtt {

enum class ConnectionState : int {
    Stopped,       ///< not started, or stopped
    Connecting,    ///< the first attempt is under way
    Connected,     ///< connected and subscribed (when there are topics)
    Reconnecting,  ///< the connection failed or was lost; attempts continue with back-off
};
const char* connectionStateName(ConnectionState s) noexcept;   ///< "stopped", "connecting", ...

struct MqttStatus {
    ConnectionState state = ConnectionState::Stopped;
    std::string broker;               ///< "host:port"
    std::string lastError;            ///< the last failure in words ("" none yet)
    std::uint64_t connects = 0;       ///< successful connections (2 or more = it reconnected)
    std::uint64_t connectionLosses = 0;
    std::uint64_t failedAttempts = 0; ///< connection attempts that failed
    double nextAttemptIn = 0.0;       ///< s until the next attempt (while Reconnecting)
    std::uint64_t received = 0;       ///< messages received on subscribed topics
    std::uint64_t published = 0;      ///< messages handed to the broker
    std::uint64_t outboxDropped = 0;  ///< real-time publishes refused: the queue was full
    std::uint64_t coalesced = 0;      ///< values replaced by a newer one for the same topic before they went out
    std::uint64_t refusedPublishes = 0; ///< publishes the library refused (too long, bad topic), see lastError
    int subscriptions = 0;            ///< topic filters the broker accepted on this connection
};

/// A value to publish, queued from the real-time side: fixed size, trivially copyable.
struct OutgoingMessage {
    static constexpr std::size_t kMaxTopic = 160;
    static constexpr std::size_t kMaxPayload = 440;
    char topic[kMaxTopic] {};
    char payload[kMaxPayload] {};
    std::uint16_t topicLength = 0, payloadLength = 0;
    std::uint8_t qos = 0;
    bool retain = false;
    float maxRate = -1.0f;            ///< messages/s for this topic; < 0 = MqttConfig::publishRate; 0 = no limit

    /// Fills topic and payload; false (nothing changed) when either does not fit. Real-time.
    bool set(std::string_view t, std::string_view p) noexcept;
};

struct ReceivedMessage {
    std::string topic;
    std::string payload;
    int qos = 0;
    bool retained = false;
};

class MqttClient {
public:
    explicit MqttClient(MqttConfig config);
    ~MqttClient();
    MqttClient(const MqttClient&) = delete;
    MqttClient& operator=(const MqttClient&) = delete;

    /// Called on the network thread for each message on a subscribed topic (before start()).
    void setMessageHandler(std::function<void(const ReceivedMessage&)> handler);
    /// Starts the network thread. Throws IoError when libmosquitto refuses the configuration
    /// (a TLS file it cannot use, out of memory). A broker that is down is not an error: the
    /// status says Reconnecting and attempts continue.
    void start();
    /// Disconnects and joins the network thread (connecting is non-blocking: at most a name lookup
    /// and one 20 ms loop pass are waited for). While connected, the values still waiting for
    /// their topic's rate limit go out first: the last value is sent even when the session ends
    /// within 1/rate of it.
    void stop();

    /// Real-time, one producer: queues a value; false (and counted) when the queue is full.
    bool publish(const OutgoingMessage& message) noexcept;
    /// Any non-real-time thread: queues text for a topic (no rate limit); false when too long.
    bool publishText(const std::string& topic, const std::string& payload, int qos = 0, bool retain = false);

    MqttStatus status() const;
    const MqttConfig& config() const noexcept { return config_; }
    /// Waits (polling the status, up to `seconds`) until connected; for the command line's check.
    bool waitConnected(double seconds) const;

private:
    struct Pending {
        OutgoingMessage message {};
        bool waiting = false;
        double lastSent = -1e9;       // s on the thread's clock
    };
    void run();
    bool attemptConnect();
    /// `last`: the connection is about to close, so values waiting for their rate limit go now.
    void drainOutbox(double now, bool connected, bool last = false);
    bool send(const char* topic, const void* payload, int length, int qos, bool retain);
    void noteError(const std::string& why);
    static void onConnect(::mosquitto*, void*, int rc);
    static void onDisconnect(::mosquitto*, void*, int rc);
    static void onMessage(::mosquitto*, void*, const ::mosquitto_message*);
    static void onSubscribe(::mosquitto*, void*, int mid, int count, const int* granted);

    MqttConfig config_;
    ::mosquitto* mosq_ = nullptr;
    std::function<void(const ReceivedMessage&)> handler_;
    std::thread thread_;
    std::atomic<bool> running_ {false};
    bool socketUp_ = false;               // network thread only: a connection exists (CONNACK or not)
    bool connackOk_ = false;              // network thread only

    core::SpscQueue<OutgoingMessage, 1024> outbox_;
    std::atomic<std::uint64_t> outboxDropped_ {0};
    std::map<std::string, Pending, std::less<>> pending_;   // network thread only: the latest value per topic

    std::mutex textMutex_;
    std::deque<ReceivedMessage> textOut_;      // publishText(): topic, payload, qos, retained = retain

    mutable std::mutex statusMutex_;
    MqttStatus status_;
};

} // namespace armadillo::mqtt
