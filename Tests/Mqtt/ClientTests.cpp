// The MQTT client against a real Mosquitto broker that each test starts on a free loopback port
// (Broker.h): round trips with wildcards and both protocol versions, a broker down at start, a
// broker killed and restarted mid-session, a flood, the per-topic rate limit, a real-time publish.
// Waits are on conditions with generous deadlines, never on sleeps.
#define ARMADILLO_REALTIME_GUARD_IMPLEMENTATION
#include "Common/RealtimeGuard.h"
#include "Broker.h"
#include "Common/Eventually.h"
#include "Core/Errors.h"
#include "Mqtt/MqttClient.h"
#include <fstream>
#include <catch2/catch.hpp>
#include <mutex>
#include <vector>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::mqtt;
using armadillo::testing::eventually;

namespace {

MqttConfig configFor(const test::Broker& broker, std::vector<std::string> topics = {}, int qos = 0)
{
    MqttConfig c;
    c.host = "127.0.0.1";
    c.port = broker.port();
    c.reconnectMin = 0.05;
    c.reconnectMax = 0.4;
    for (auto& t : topics) c.topics.push_back({t, qos, false});
    return c;
}

/// A subscriber that keeps what it heard.
struct Listener {
    explicit Listener(MqttConfig config) : client(std::move(config))
    {
        client.setMessageHandler([this](const ReceivedMessage& m) {
            std::lock_guard lock(mutex);
            heard.push_back(m);
        });
        client.start();
    }
    std::vector<ReceivedMessage> copy()
    {
        std::lock_guard lock(mutex);
        return heard;
    }
    std::size_t count()
    {
        std::lock_guard lock(mutex);
        return heard.size();
    }
    bool heardPayload(const std::string& p)
    {
        std::lock_guard lock(mutex);
        for (const auto& m : heard)
            if (m.payload == p) return true;
        return false;
    }
    MqttClient client;
    std::mutex mutex;
    std::vector<ReceivedMessage> heard;
};

OutgoingMessage value(const std::string& topic, int v, float rate, bool retain = false, int qos = 1)
{
    OutgoingMessage m;
    REQUIRE(m.set(topic, std::to_string(v)));
    m.maxRate = rate;
    m.retain = retain;
    m.qos = static_cast<std::uint8_t>(qos);
    return m;
}

} // namespace

TEST_CASE("a message goes through a real broker to a wildcard subscriber, MQTT 3.1.1 and 5")
{
    test::Broker broker;
    broker.start();
    for (int protocol : {4, 5}) {
        INFO("protocol " << protocol);
        MqttConfig sub = configFor(broker, {"arm/+/inbox", "door/#"}, 1);
        sub.protocol = protocol;
        Listener listener(sub);
        REQUIRE(listener.client.waitConnected(30));
        CHECK(listener.client.status().subscriptions == 2);
        MqttConfig pubConfig = configFor(broker);
        pubConfig.protocol = protocol;
        MqttClient pub(pubConfig);
        pub.start();
        REQUIRE(pub.waitConnected(30));
        REQUIRE(pub.publishText("arm/alice/inbox", "hello arm", 1));
        REQUIRE(pub.publishText("door/front", "EN", 1));
        REQUIRE(pub.publishText("elsewhere/x", "not for us", 1));
        REQUIRE(pub.publishText("arm/alice/inbox", "last", 1));
        REQUIRE(eventually([&] { return listener.heardPayload("last"); }));
        const auto heard = listener.copy();
        REQUIRE(heard.size() == 3);   // the probe: "last" came after the unsubscribed topic's message
        CHECK(heard[0].topic == "arm/alice/inbox");
        CHECK(heard[0].payload == "hello arm");
        CHECK(heard[1].topic == "door/front");
        CHECK(heard[1].payload == "EN");
        CHECK(pub.status().published == 4);
        CHECK(listener.client.status().received == 3);
        CHECK(std::string(connectionStateName(pub.status().state)) == "connected");
    }
}

TEST_CASE("a broker down at start: the status says reconnecting and why, then it connects")
{
    test::Broker broker;   // not started: its port refuses connections
    MqttClient client(configFor(broker, {"arm/inbox"}));
    client.start();
    REQUIRE(eventually([&] { return client.status().failedAttempts >= 2; }));
    MqttStatus s = client.status();
    CHECK(s.state == ConnectionState::Reconnecting);
    CHECK_THAT(s.lastError, Catch::Contains("cannot connect to 127.0.0.1:" + std::to_string(broker.port())) &&
                                Catch::Contains("refused"));
    CHECK(s.connects == 0);
    broker.start();
    REQUIRE(client.waitConnected(30));
    s = client.status();
    CHECK(s.connects == 1);
    CHECK(s.subscriptions == 1);
    client.stop();
    CHECK(client.status().state == ConnectionState::Stopped);
}

TEST_CASE("a broker killed and restarted mid-session: reconnection, resubscription, the latest value kept")
{
    test::Broker broker;
    broker.start();
    Listener listener(configFor(broker, {"arm/remote/#"}, 1));
    MqttClient pub(configFor(broker));
    pub.start();
    REQUIRE(listener.client.waitConnected(30));
    REQUIRE(pub.waitConnected(30));

    // Before: 20 values, no rate limit, all arrive in order.
    for (int v = 1; v <= 20; ++v) REQUIRE(pub.publish(value("arm/remote/x", v, 0.0f, true)));
    REQUIRE(eventually([&] { return listener.heardPayload("20"); }));

    broker.stop();
    REQUIRE(eventually([&] { return pub.status().state == ConnectionState::Reconnecting; }));
    REQUIRE(eventually([&] { return listener.client.status().state == ConnectionState::Reconnecting; }));
    CHECK_THAT(pub.status().lastError, Catch::Contains("lost") || Catch::Contains("cannot connect"));
    // During the outage: ten values; only the latest per topic can wait for the broker.
    for (int v = 21; v <= 30; ++v) REQUIRE(pub.publish(value("arm/remote/x", v, 0.0f, true)));
    REQUIRE(eventually([&] { return pub.status().coalesced >= 9; }));

    broker.start();
    REQUIRE(pub.waitConnected(30));
    REQUIRE(listener.client.waitConnected(30));
    // Retained, so the subscriber hears it even if it subscribed after the publisher's reconnection.
    REQUIRE(eventually([&] { return listener.heardPayload("30"); }));
    for (int v = 31; v <= 40; ++v) REQUIRE(pub.publish(value("arm/remote/x", v, 0.0f, true)));
    REQUIRE(eventually([&] { return listener.heardPayload("40"); }));

    std::vector<int> got;
    for (const auto& m : listener.copy())
        if (got.empty() || std::to_string(got.back()) != m.payload) got.push_back(std::stoi(m.payload));   // QoS 1 may repeat one
    std::vector<int> expected;
    for (int v = 1; v <= 20; ++v) expected.push_back(v);
    expected.push_back(30);
    for (int v = 31; v <= 40; ++v) expected.push_back(v);
    CHECK(got == expected);
    const MqttStatus s = pub.status();
    CHECK(s.connects == 2);
    CHECK(s.connectionLosses == 1);
    CHECK(s.coalesced == 9);
    CHECK(s.outboxDropped == 0);
    CHECK(listener.client.status().connects == 2);
}

TEST_CASE("a flood of 3000 messages arrives whole and in order")
{
    test::Broker broker;
    broker.start();
    Listener listener(configFor(broker, {"flood"}, 1));
    MqttClient pub(configFor(broker));
    pub.start();
    REQUIRE(listener.client.waitConnected(30));
    REQUIRE(pub.waitConnected(30));
    constexpr int kCount = 3000;
    for (int i = 0; i < kCount; ++i) REQUIRE(pub.publishText("flood", std::to_string(i), 1));
    const bool all = eventually([&] { return listener.count() >= kCount; }, 120.0);
    INFO("heard " << listener.count() << ", published " << pub.status().published << ", last error: " << pub.status().lastError
                  << "; subscriber: " << listener.client.status().lastError);
    REQUIRE(all);
    const auto heard = listener.copy();
    REQUIRE(heard.size() == kCount);
    for (int i = 0; i < kCount; ++i) REQUIRE(heard[static_cast<std::size_t>(i)].payload == std::to_string(i));
}

TEST_CASE("the per-topic rate limit: at most N per second, the last value always sent")
{
    test::Broker broker;
    broker.start();
    Listener listener(configFor(broker, {"rate/#"}, 1));
    MqttClient pub(configFor(broker));
    pub.start();
    REQUIRE(listener.client.waitConnected(30));
    REQUIRE(pub.waitConnected(30));
    const auto start = std::chrono::steady_clock::now();
    constexpr double kRate = 5.0;
    for (int v = 0; v < 200; ++v) {
        REQUIRE(pub.publish(value("rate/a", v, static_cast<float>(kRate))));
        REQUIRE(pub.publish(value("rate/b", 1000 + v, 0.0f)));   // unlimited: every value
    }
    REQUIRE(eventually([&] { return listener.heardPayload("199"); }));
    REQUIRE(eventually([&] { return listener.heardPayload("1199"); }));
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    int a = 0, b = 0;
    for (const auto& m : listener.copy()) (m.topic == "rate/a" ? a : b)++;
    // Bounds computed from the time this run took, not asserted on time: one send per 1/rate.
    CHECK(a >= 1);
    CHECK(a <= 1 + static_cast<int>(elapsed * kRate) + 1);
    CHECK(b == 200);
    CHECK(pub.status().coalesced >= static_cast<std::uint64_t>(200 - a));
}

TEST_CASE("the last value is sent when the client stops within its topic's rate window")
{
    test::Broker broker;
    broker.start();
    Listener listener(configFor(broker, {"last/#"}, 1));
    MqttClient pub(configFor(broker));
    pub.start();
    REQUIRE(listener.client.waitConnected(30));
    REQUIRE(pub.waitConnected(30));
    constexpr float kRate = 0.1f;   // one message per 10 s for the topic
    REQUIRE(pub.publish(value("last/x", 1, kRate)));
    REQUIRE(eventually([&] { return listener.heardPayload("1"); }));
    // Within the window: 2 waits, 3 replaces it (coalesced); then the session ends.
    REQUIRE(pub.publish(value("last/x", 2, kRate)));
    REQUIRE(pub.publish(value("last/x", 3, kRate)));
    REQUIRE(eventually([&] { return pub.status().coalesced >= 1; }));
    pub.stop();
    CHECK(eventually([&] { return listener.heardPayload("3"); }, 20.0));
    CHECK_FALSE(listener.heardPayload("2"));
    CHECK(pub.status().published == 2);
}

TEST_CASE("publish() from the control step neither allocates nor locks; a full queue is counted")
{
    test::Broker broker;   // never started: nothing drains but coalescing, so the queue can be filled
    MqttClient client(configFor(broker));
    OutgoingMessage m;
    REQUIRE(m.set("arm/remote/level", "{\"brightness\": 128}"));
    ARMADILLO_REQUIRE_GUARD();
    {
        test::RealtimeGuard guard;
        for (int i = 0; i < 1024; ++i) CHECK(client.publish(m));
        CHECK_FALSE(client.publish(m));   // the 1025th: full (the client is not started)
        CHECK(guard.allocations() == 0);
        CHECK(guard.locks() == 0);
    }
    {
        // The probe works: a std::string of this size allocates and the guard sees it.
        test::RealtimeGuard probe;
        std::string big(500, 'x');
        CHECK(probe.allocations() > 0);
    }
    CHECK(client.status().outboxDropped == 1);
    OutgoingMessage tooLong;
    CHECK_FALSE(tooLong.set(std::string(OutgoingMessage::kMaxTopic, 't'), "1"));
    CHECK_FALSE(tooLong.set("t", std::string(OutgoingMessage::kMaxPayload + 1, 'p')));
    CHECK_FALSE(tooLong.set("", "1"));
}

TEST_CASE("a TLS CA file libmosquitto cannot use is an error naming the file")
{
    const std::string bad = (test::scratchDir("armadillo-mqtt-tests") / "not-a-ca.pem").string();
    std::ofstream(bad) << "this is not a certificate\n";
    MqttConfig c;
    c.caFile = bad;
    c.port = test::freeTcpPort();
    MqttClient client(c);
    // libmosquitto only checks that the file is readable; OpenSSL reads it at connect: the status says why.
    try {
        client.start();
    } catch (const IoError& e) {
        CHECK_THAT(e.what(), Catch::Contains(bad));
        return;
    }
    REQUIRE(eventually([&] { return client.status().failedAttempts >= 1; }));
    CHECK_FALSE(client.status().lastError.empty());
}
