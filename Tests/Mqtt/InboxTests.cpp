// Messages for the arm: text from payloads and JSON fields, refusals with reasons, the bounded
// queue (oldest dropped and counted), urgent first; and the same through a real broker: a flood,
// a 1 MB payload, invalid UTF-8, a JSON field missing.
#include "Broker.h"
#include "Common/Eventually.h"
#include "Mqtt/MessageInbox.h"
#include "Mqtt/MqttClient.h"
#include <catch2/catch.hpp>

using namespace armadillo;
using namespace armadillo::mqtt;
using armadillo::testing::eventually;

namespace {

MqttConfig inboxConfig(std::size_t capacity = 16)
{
    MqttConfig c;
    c.queueCapacity = capacity;
    c.topics = {{"arm/inbox", 1, false}, {"door/+", 1, true}};
    return c;
}

ReceivedMessage on(const std::string& topic, const std::string& payload) { return {topic, payload, 1, false}; }

} // namespace

TEST_CASE("a payload's text: UTF-8 checked, line breaks as spaces, JSON fields, refusals with reasons")
{
    MqttConfig plain;
    std::string text, why;
    int priority = -1;
    CHECK(messageText("Do not\r\nenter\t now ", plain, text, priority, why));
    CHECK(text == "Do not enter now");
    CHECK(priority == 0);
    CHECK(messageText("caf\xC3\xA9 \xE2\x9C\x93", plain, text, priority, why));   // é ✓ kept as they are
    CHECK(text == "caf\xC3\xA9 \xE2\x9C\x93");
    for (const std::string& bad : {std::string("a\xC3"), std::string("\xC0\xAF"), std::string("\xED\xA0\x80"), std::string("\xF5\x80\x80\x80"),
                                  std::string("ok\xFF")}) {
        CHECK_FALSE(messageText(bad, plain, text, priority, why));
        CHECK_THAT(why, Catch::Contains("invalid UTF-8 at byte"));
    }
    CHECK_FALSE(messageText("bell\x07", plain, text, priority, why));
    CHECK_THAT(why, Catch::Contains("control character 7"));
    CHECK_FALSE(messageText("  \n ", plain, text, priority, why));
    CHECK_THAT(why, Catch::Contains("no text"));

    MqttConfig json;
    json.textField = "message.text";
    json.priorityField = "priority";
    CHECK(messageText(R"({"message": {"text": "EXIT"}, "priority": 2})", json, text, priority, why));
    CHECK(text == "EXIT");
    CHECK(priority == 1);
    CHECK(messageText(R"({"message": {"text": "en"}})", json, text, priority, why));
    CHECK(priority == 0);
    CHECK_FALSE(messageText(R"({"message": {"body": "EXIT"}})", json, text, priority, why));
    CHECK_THAT(why, Catch::Contains("no field \"message.text\""));
    CHECK_FALSE(messageText(R"({"message": {"text": 3}})", json, text, priority, why));
    CHECK_THAT(why, Catch::Contains("not a string"));
    CHECK_FALSE(messageText(R"({"message": )", json, text, priority, why));
    CHECK_THAT(why, Catch::Contains("not JSON"));
    CHECK_FALSE(messageText(R"({"message": {"text": "x"}, "priority": "high"})", json, text, priority, why));
    CHECK_THAT(why, Catch::Contains("not a number"));
}

TEST_CASE("the inbox: bounded, oldest dropped with a count, urgent first, refusals counted")
{
    MessageInbox inbox(inboxConfig(3));
    for (const char* t : {"one", "two", "three", "four", "five"}) CHECK(inbox.offer(on("arm/inbox", t)));
    InboxStats s = inbox.stats();
    CHECK(s.offered == 5);
    CHECK(s.accepted == 5);
    CHECK(s.droppedOldest == 2);
    CHECK(s.waiting == 3);
    CHECK(inbox.offer(on("door/front", "en")));   // an urgent topic
    CHECK(inbox.urgentWaiting());
    CHECK(inbox.offerText("fire", "osc", 1));      // an urgent OSC message
    CHECK_FALSE(inbox.offer(on("arm/inbox", "bad \xFF")));
    CHECK_FALSE(inbox.offerText("", "osc", 0));
    s = inbox.stats();
    CHECK(s.refused == 2);
    CHECK_THAT(s.lastRefusal, Catch::Contains("'osc'") && Catch::Contains("no text"));
    CHECK(s.droppedOldest == 4);   // 3 waiting of capacity 3 took two more: "three" and "four" went
    std::vector<std::string> order;
    std::vector<bool> urgent;
    InboxMessage m;
    while (inbox.pop(m)) {
        order.push_back(m.text);
        urgent.push_back(m.urgent);
    }
    CHECK(order == std::vector<std::string> {"en", "fire", "five"});
    CHECK(urgent == std::vector<bool> {true, true, false});
    CHECK_FALSE(inbox.urgentWaiting());
    const auto recent = inbox.recent(3);
    REQUIRE(recent.size() == 3);
    CHECK(recent.back().text == "fire");
    CHECK(recent.back().source == "osc");
    CHECK(recent.front().id < recent.back().id);
}

TEST_CASE("through a real broker: a flood, a 1 MB payload, invalid UTF-8 and a missing JSON field")
{
    test::Broker broker;
    broker.start();
    MqttConfig c = inboxConfig(16);
    c.host = "127.0.0.1";
    c.port = broker.port();
    MessageInbox inbox(c);
    MqttClient sub(c);
    sub.setMessageHandler([&](const ReceivedMessage& m) { inbox.offer(m); });
    sub.start();
    MqttConfig pc;
    pc.host = "127.0.0.1";
    pc.port = broker.port();
    MqttClient pub(pc);
    pub.start();
    REQUIRE(sub.waitConnected(30));
    REQUIRE(pub.waitConnected(30));

    SECTION("a flood of 500: the last 16 wait, 484 counted as dropped, none lost that fits")
    {
        for (int i = 0; i < 500; ++i) REQUIRE(pub.publishText("arm/inbox", "message " + std::to_string(i), 1));
        REQUIRE(eventually([&] { return inbox.stats().offered == 500; }, 120.0));
        const InboxStats s = inbox.stats();
        CHECK(s.accepted == 500);
        CHECK(s.droppedOldest == 484);
        CHECK(s.waiting == 16);
        InboxMessage m;
        for (int i = 484; i < 500; ++i) {
            REQUIRE(inbox.pop(m));
            CHECK(m.text == "message " + std::to_string(i));
        }
        CHECK_FALSE(inbox.pop(m));
    }
    SECTION("1 MB, invalid UTF-8 and JSON refused with reasons; the messages around them arrive")
    {
        REQUIRE(pub.publishText("arm/inbox", "before", 1));
        REQUIRE(pub.publishText("arm/inbox", std::string(1024 * 1024, 'a'), 1));
        REQUIRE(pub.publishText("arm/inbox", "caf\xC3", 1));
        REQUIRE(pub.publishText("door/back", "ex", 1));
        REQUIRE(pub.publishText("arm/inbox", "after", 1));
        REQUIRE(eventually([&] { return inbox.stats().offered == 5; }, 60.0));
        const InboxStats s = inbox.stats();
        CHECK(s.accepted == 3);
        CHECK(s.refused == 2);
        CHECK_THAT(s.lastRefusal, Catch::Contains("'arm/inbox'") && Catch::Contains("invalid UTF-8"));
        InboxMessage m;
        REQUIRE(inbox.pop(m));
        CHECK(m.text == "ex");   // urgent topic first
        REQUIRE(inbox.pop(m));
        CHECK(m.text == "before");
        REQUIRE(inbox.pop(m));
        CHECK(m.text == "after");
        CHECK(sub.status().received == 5);
    }
    SECTION("a JSON field missing")
    {
        MqttConfig jc = c;
        jc.textField = "text";
        MessageInbox jsonInbox(jc);
        MqttConfig jsub = jc;
        jsub.topics = {{"json/inbox", 1, false}};
        MqttClient js(jsub);
        js.setMessageHandler([&](const ReceivedMessage& m) { jsonInbox.offer(m); });
        js.start();
        REQUIRE(js.waitConnected(30));
        REQUIRE(pub.publishText("json/inbox", R"({"from": "door", "body": "en"})", 1));
        REQUIRE(pub.publishText("json/inbox", R"({"from": "anna", "text": "on my way"})", 1));
        REQUIRE(eventually([&] { return jsonInbox.stats().offered == 2; }));
        const InboxStats s = jsonInbox.stats();
        CHECK(s.refused == 1);
        CHECK_THAT(s.lastRefusal, Catch::Contains("json/inbox") && Catch::Contains("no field \"text\""));
        InboxMessage m;
        REQUIRE(jsonInbox.pop(m));
        CHECK(m.text == "on my way");
    }
}
