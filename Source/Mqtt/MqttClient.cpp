#include "Mqtt/MqttClient.h"
#include "Core/Errors.h"
#include <mosquitto.h>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <mqtt_protocol.h>
#include <unistd.h>

namespace armadillo::mqtt {

const char* connectionStateName(ConnectionState s) noexcept
{
    switch (s) {
    case ConnectionState::Stopped: return "stopped";
    case ConnectionState::Connecting: return "connecting";
    case ConnectionState::Connected: return "connected";
    case ConnectionState::Reconnecting: return "reconnecting";
    }
    return "?";
}

bool OutgoingMessage::set(std::string_view t, std::string_view p) noexcept
{
    if (t.size() >= kMaxTopic || p.size() > kMaxPayload || t.empty()) return false;
    std::memcpy(topic, t.data(), t.size());
    topic[t.size()] = '\0';
    std::memcpy(payload, p.data(), p.size());
    topicLength = static_cast<std::uint16_t>(t.size());
    payloadLength = static_cast<std::uint16_t>(p.size());
    return true;
}

namespace {

std::once_flag libraryInit;
std::atomic<int> clientCounter {0};

double secondsNow()
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string errorText(int rc)
{
    if (rc == MOSQ_ERR_ERRNO) return std::strerror(errno);
    return mosquitto_strerror(rc);
}

} // namespace

MqttClient::MqttClient(MqttConfig config) : config_(std::move(config))
{
    std::call_once(libraryInit, [] { mosquitto_lib_init(); });
    status_.broker = config_.host + ":" + std::to_string(config_.port);
}

MqttClient::~MqttClient()
{
    stop();
    if (mosq_) mosquitto_destroy(mosq_);
}

void MqttClient::setMessageHandler(std::function<void(const ReceivedMessage&)> handler) { handler_ = std::move(handler); }

void MqttClient::start()
{
    if (running_.load()) return;
    if (!mosq_) {
        std::string id = config_.clientId;
        if (id.empty()) id = "armadillo-" + std::to_string(::getpid()) + "-" + std::to_string(clientCounter.fetch_add(1) + 1);
        mosq_ = mosquitto_new(id.c_str(), true, this);
        if (!mosq_) throw core::IoError("MQTT: cannot create a client (" + std::string(std::strerror(errno)) + ")");
        mosquitto_int_option(mosq_, MOSQ_OPT_PROTOCOL_VERSION, config_.protocol == 5 ? MQTT_PROTOCOL_V5 : MQTT_PROTOCOL_V311);
        if (!config_.username.empty()) {
            const int rc = mosquitto_username_pw_set(mosq_, config_.username.c_str(), config_.password.empty() ? nullptr : config_.password.c_str());
            if (rc != MOSQ_ERR_SUCCESS) throw core::IoError("MQTT: username/password refused: " + errorText(rc));
        }
        if (!config_.caFile.empty()) {
            const int rc = mosquitto_tls_set(mosq_, config_.caFile.c_str(), nullptr, config_.certFile.empty() ? nullptr : config_.certFile.c_str(),
                                             config_.keyFile.empty() ? nullptr : config_.keyFile.c_str(), nullptr);
            if (rc != MOSQ_ERR_SUCCESS)
                throw core::IoError("MQTT: TLS with CA file '" + config_.caFile + "' refused by libmosquitto: " + errorText(rc));
        }
        mosquitto_connect_callback_set(mosq_, &MqttClient::onConnect);
        mosquitto_disconnect_callback_set(mosq_, &MqttClient::onDisconnect);
        mosquitto_message_callback_set(mosq_, &MqttClient::onMessage);
        mosquitto_subscribe_callback_set(mosq_, &MqttClient::onSubscribe);
    }
    {
        std::lock_guard lock(statusMutex_);
        status_.state = ConnectionState::Connecting;
    }
    running_.store(true);
    thread_ = std::thread([this] { run(); });
}

void MqttClient::stop()
{
    if (!running_.exchange(false)) return;
    if (thread_.joinable()) thread_.join();
    std::lock_guard lock(statusMutex_);
    status_.state = ConnectionState::Stopped;
}

bool MqttClient::publish(const OutgoingMessage& message) noexcept
{
    if (outbox_.push(message)) return true;
    outboxDropped_.fetch_add(1, std::memory_order_relaxed);
    return false;
}

bool MqttClient::publishText(const std::string& topic, const std::string& payload, int qos, bool retain)
{
    if (topic.empty() || payload.size() > 256u * 1024u * 1024u) return false;
    std::lock_guard lock(textMutex_);
    textOut_.push_back({topic, payload, qos, retain});
    return true;
}

MqttStatus MqttClient::status() const
{
    std::lock_guard lock(statusMutex_);
    MqttStatus s = status_;
    s.outboxDropped = outboxDropped_.load(std::memory_order_relaxed);
    return s;
}

bool MqttClient::waitConnected(double seconds) const
{
    const double deadline = secondsNow() + seconds;
    while (status().state != ConnectionState::Connected) {
        if (secondsNow() > deadline) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return true;
}

void MqttClient::noteError(const std::string& why)
{
    std::lock_guard lock(statusMutex_);
    status_.lastError = why;
}

bool MqttClient::attemptConnect()
{
    connackOk_ = false;
    // Non-blocking: the TCP connection completes (or fails) inside mosquitto_loop, so stop() never
    // waits for an unreachable host's connect timeout (minutes). Only the name lookup blocks.
    errno = 0;
    const int rc = mosquitto_connect_async(mosq_, config_.host.c_str(), config_.port, config_.keepAlive);
    if (rc == MOSQ_ERR_SUCCESS) return true;
    noteError("cannot connect to " + status_.broker + ": " + errorText(rc));
    return false;
}

void MqttClient::run()
{
    double backoff = config_.reconnectMin, nextAttempt = 0.0;
    auto scheduleRetry = [&](double now) {
        nextAttempt = now + backoff;
        std::lock_guard lock(statusMutex_);
        status_.state = ConnectionState::Reconnecting;
        status_.nextAttemptIn = backoff;
        status_.subscriptions = 0;
        backoff = std::min(backoff * 2.0, config_.reconnectMax);
    };
    socketUp_ = false;
    while (running_.load()) {
        const double now = secondsNow();
        if (!socketUp_) {
            drainOutbox(now, false);   // keeps the latest value per topic for when the broker is back
            if (now >= nextAttempt) {
                if (attemptConnect()) {
                    socketUp_ = true;
                } else {
                    {
                        std::lock_guard lock(statusMutex_);
                        ++status_.failedAttempts;
                    }
                    scheduleRetry(secondsNow());
                }
            } else {
                const double wait = std::min(0.02, nextAttempt - now);
                std::this_thread::sleep_for(std::chrono::duration<double>(std::max(wait, 0.001)));
            }
            continue;
        }
        const int rc = mosquitto_loop(mosq_, 20, 64);
        if (connackOk_) {
            backoff = config_.reconnectMin;
            drainOutbox(secondsNow(), true);
        }
        if (rc != MOSQ_ERR_SUCCESS) {
            socketUp_ = false;
            {
                std::lock_guard lock(statusMutex_);
                if (connackOk_) {
                    ++status_.connectionLosses;
                    status_.lastError = "connection to " + status_.broker + " lost: " + errorText(rc);
                } else {
                    // The attempt failed before the broker accepted it (refused, unreachable, TLS,
                    // or the broker's refusal already noted by onConnect).
                    ++status_.failedAttempts;
                    if (rc != MOSQ_ERR_NO_CONN || status_.lastError.empty() || status_.lastError.rfind("the broker", 0) != 0)
                        status_.lastError = "cannot connect to " + status_.broker + ": " + errorText(rc);
                }
            }
            connackOk_ = false;
            mosquitto_disconnect(mosq_);
            scheduleRetry(secondsNow());
        }
    }
    if (socketUp_) {
        drainOutbox(secondsNow(), connackOk_, true);   // the last values, whatever their rate
        mosquitto_disconnect(mosq_);
        mosquitto_loop(mosq_, 50, 1);   // lets the DISCONNECT go out
    }
    socketUp_ = false;
}

bool MqttClient::send(const char* topic, const void* payload, int length, int qos, bool retain)
{
    const int rc = mosquitto_publish(mosq_, nullptr, topic, length, payload, qos, retain);
    if (rc == MOSQ_ERR_NO_CONN || rc == MOSQ_ERR_CONN_LOST) return false;   // kept for the next connection
    std::lock_guard lock(statusMutex_);
    if (rc == MOSQ_ERR_SUCCESS) {
        ++status_.published;
    } else {
        ++status_.refusedPublishes;
        status_.lastError = "publishing to '" + std::string(topic) + "' refused: " + errorText(rc);
    }
    return true;
}

void MqttClient::drainOutbox(double now, bool connected, bool last)
{
    OutgoingMessage m;
    std::uint64_t coalesced = 0;
    while (outbox_.pop(m)) {
        auto it = pending_.find(std::string_view(m.topic, m.topicLength));
        const bool unlimited = (m.maxRate < 0.0f ? config_.publishRate : static_cast<double>(m.maxRate)) <= 0.0;
        // A topic without a rate limit sends every value while connected; only a waiting one
        // (the broker was away) is replaced by the newer.
        if (connected && unlimited && (it == pending_.end() || !it->second.waiting) &&
            send(m.topic, m.payload, m.payloadLength, m.qos, m.retain))
            continue;
        if (it == pending_.end()) it = pending_.emplace(std::string(m.topic, m.topicLength), Pending {}).first;
        if (it->second.waiting) ++coalesced;
        it->second.message = m;
        it->second.waiting = true;
    }
    if (coalesced) {
        std::lock_guard lock(statusMutex_);
        status_.coalesced += coalesced;
    }
    if (!connected) return;
    for (auto& [topic, p] : pending_) {
        if (!p.waiting) continue;
        const double rate = p.message.maxRate < 0.0f ? config_.publishRate : static_cast<double>(p.message.maxRate);
        if (rate > 0.0 && now - p.lastSent < 1.0 / rate && !last) continue;
        if (!send(p.message.topic, p.message.payload, p.message.payloadLength, p.message.qos, p.message.retain)) return;
        p.waiting = false;
        p.lastSent = now;
    }
    std::unique_lock lock(textMutex_);
    while (!textOut_.empty()) {
        ReceivedMessage t = std::move(textOut_.front());
        textOut_.pop_front();
        lock.unlock();
        if (!send(t.topic.c_str(), t.payload.data(), static_cast<int>(t.payload.size()), t.qos, t.retained)) {
            lock.lock();
            textOut_.push_front(std::move(t));
            return;
        }
        lock.lock();
    }
}

void MqttClient::onConnect(::mosquitto* m, void* self, int rc)
{
    auto* c = static_cast<MqttClient*>(self);
    if (rc != 0) {
        c->noteError("the broker " + c->status_.broker + " refused the connection: " + mosquitto_connack_string(rc));
        mosquitto_disconnect(m);
        return;
    }
    c->connackOk_ = true;
    {
        std::lock_guard lock(c->statusMutex_);
        ++c->status_.connects;
        c->status_.subscriptions = 0;
        c->status_.nextAttemptIn = 0.0;
        if (c->config_.topics.empty()) c->status_.state = ConnectionState::Connected;
    }
    for (const auto& t : c->config_.topics) {
        const int s = mosquitto_subscribe(m, nullptr, t.filter.c_str(), t.qos);
        if (s != MOSQ_ERR_SUCCESS) c->noteError("cannot subscribe to '" + t.filter + "': " + errorText(s));
    }
}

void MqttClient::onDisconnect(::mosquitto*, void*, int) {}

void MqttClient::onSubscribe(::mosquitto*, void* self, int, int count, const int* granted)
{
    auto* c = static_cast<MqttClient*>(self);
    std::lock_guard lock(c->statusMutex_);
    for (int i = 0; i < count; ++i) {
        if (granted[i] >= 0 && granted[i] <= 2) ++c->status_.subscriptions;
        else c->status_.lastError = "the broker refused a subscription (code " + std::to_string(granted[i]) + ")";
    }
    if (c->status_.subscriptions >= static_cast<int>(c->config_.topics.size())) c->status_.state = ConnectionState::Connected;
}

void MqttClient::onMessage(::mosquitto*, void* self, const ::mosquitto_message* msg)
{
    auto* c = static_cast<MqttClient*>(self);
    {
        std::lock_guard lock(c->statusMutex_);
        ++c->status_.received;
    }
    if (!c->handler_ || !msg || !msg->topic) return;
    ReceivedMessage r;
    r.topic = msg->topic;
    if (msg->payloadlen > 0) r.payload.assign(static_cast<const char*>(msg->payload), static_cast<std::size_t>(msg->payloadlen));
    r.qos = msg->qos;
    r.retained = msg->retain;
    try {
        c->handler_(r);
    } catch (const std::exception& e) {
        c->noteError(std::string("a message on '") + r.topic + "' could not be handled: " + e.what());
    }
}

} // namespace armadillo::mqtt
