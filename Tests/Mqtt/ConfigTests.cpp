// The MQTT configuration file and topic filters. Expected matches come from MQTT 3.1.1 §4.7
// (OASIS standard, "Topic wildcards" and its non-normative examples), not from the code.
#include "Core/Errors.h"
#include "Mqtt/MqttConfig.h"
#include <catch2/catch.hpp>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::mqtt;

namespace {

std::string errorOf(const std::string& text)
{
    try {
        parseMqttConfig(text, "home.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "(accepted)";
}

} // namespace

TEST_CASE("broker addresses: host, host:port, [ipv6]:port; bad ones named")
{
    std::string host;
    int port = 1883;
    parseBrokerAddress("localhost", "--mqtt", host, port);
    CHECK(host == "localhost");
    CHECK(port == 1883);
    parseBrokerAddress("10.0.0.2:18830", "--mqtt", host, port);
    CHECK(host == "10.0.0.2");
    CHECK(port == 18830);
    parseBrokerAddress("[::1]:1999", "--mqtt", host, port);
    CHECK(host == "::1");
    CHECK(port == 1999);
    for (const char* bad : {"", ":1883", "host:", "host:0", "host:70000", "host:12ab", "[::1"}) {
        INFO(bad);
        CHECK_THROWS_WITH(parseBrokerAddress(bad, "--mqtt", host, port), Catch::Contains("--mqtt"));
    }
}

TEST_CASE("a whole configuration file is read")
{
    const MqttConfig c = parseMqttConfig(R"({
  "broker": "broker.lan:8883",
  "clientId": "arm-1",
  "username": "arm", "password": "secret",
  "protocol": "5",
  "keepAlive": 20,
  "reconnect": {"min": 0.25, "max": 8},
  "messages": {"topics": ["arm/inbox", {"topic": "door/+/sign", "qos": 1, "urgent": true}],
               "textField": "message.text", "priorityField": "priority", "queue": 4, "maxTextBytes": 300},
  "publish": {"rate": 4}
})",
                                         "home.json");
    CHECK(c.host == "broker.lan");
    CHECK(c.port == 8883);
    CHECK(c.clientId == "arm-1");
    CHECK(c.username == "arm");
    CHECK(c.password == "secret");
    CHECK(c.protocol == 5);
    CHECK(c.keepAlive == 20);
    CHECK(c.reconnectMin == 0.25);
    CHECK(c.reconnectMax == 8.0);
    REQUIRE(c.topics.size() == 2);
    CHECK(c.topics[0].filter == "arm/inbox");
    CHECK_FALSE(c.topics[0].urgent);
    CHECK(c.topics[1].filter == "door/+/sign");
    CHECK(c.topics[1].qos == 1);
    CHECK(c.topics[1].urgent);
    CHECK(c.textField == "message.text");
    CHECK(c.priorityField == "priority");
    CHECK(c.queueCapacity == 4);
    CHECK(c.maxTextBytes == 300);
    CHECK(c.publishRate == 4.0);
    CHECK(c.source == "home.json");
}

TEST_CASE("configuration errors name the file, the line and the key")
{
    CHECK_THAT(errorOf("{\n \"brokr\": \"x\"\n}"), Catch::Contains("home.json:2") && Catch::Contains("brokr") && Catch::Contains("unknown key"));
    CHECK_THAT(errorOf("{\n\n \"broker\": \"x:99999\"}"), Catch::Contains("home.json:3") && Catch::Contains("65535"));
    CHECK_THAT(errorOf("{\"protocol\": \"3\"}"), Catch::Contains("home.json:1") && Catch::Contains("3.1.1"));
    CHECK_THAT(errorOf("{\"keepAlive\": 1}"), Catch::Contains("keepAlive") && Catch::Contains("from 5"));
    CHECK_THAT(errorOf("{\"keepAlive\": \"30\"}"), Catch::Contains("expected a number, found a string"));
    CHECK_THAT(errorOf("{\n\"messages\": {\"topics\": [\n \"a/#/b\"]}}"), Catch::Contains("home.json:3") && Catch::Contains("'#'"));
    CHECK_THAT(errorOf("{\"messages\": {\"topics\": [{\"qos\": 1}]}}"), Catch::Contains("needs \"topic\""));
    CHECK_THAT(errorOf("{\"messages\": {\"topics\": [{\"topic\": \"a\", \"qos\": 3}]}}"), Catch::Contains("qos"));
    CHECK_THAT(errorOf("{\"messages\": {\"queue\": 0}}"), Catch::Contains("messages.queue"));
    CHECK_THAT(errorOf("{\"reconnect\": {\"min\": 5, \"max\": 1}}"), Catch::Contains("max is below min"));
    CHECK_THAT(errorOf("{\"tls\": {\"caFile\": \"/no/such/ca.pem\"}}"), Catch::Contains("home.json") && Catch::Contains("/no/such/ca.pem"));
    CHECK_THAT(errorOf("{\"tls\": {}}"), Catch::Contains("caFile"));
    CHECK_THAT(errorOf("{\"password\": \"p\"}"), Catch::Contains("needs a username"));
    CHECK_THAT(errorOf("{\"broker\": \"x\",}"), Catch::Contains("home.json:1"));   // a JSON syntax error
    CHECK_THAT(errorOf("[1]"), Catch::Contains("expected an object"));
    CHECK_THROWS_WITH(loadMqttConfig("/no/such/mqtt.json"), Catch::Contains("/no/such/mqtt.json"));
}

TEST_CASE("topic filters match as MQTT 3.1.1 section 4.7 says")
{
    // §4.7.1.2: "sport/tennis/player1/#" matches these three.
    CHECK(topicMatches("sport/tennis/player1/#", "sport/tennis/player1"));
    CHECK(topicMatches("sport/tennis/player1/#", "sport/tennis/player1/ranking"));
    CHECK(topicMatches("sport/tennis/player1/#", "sport/tennis/player1/score/wimbledon"));
    CHECK(topicMatches("sport/#", "sport"));   // "#" includes the parent level
    CHECK(topicMatches("#", "anything/at/all"));
    // §4.7.1.3: "sport/tennis/+" matches one level only; "sport/+" does not match "sport" but "sport/".
    CHECK(topicMatches("sport/tennis/+", "sport/tennis/player1"));
    CHECK_FALSE(topicMatches("sport/tennis/+", "sport/tennis/player1/ranking"));
    CHECK_FALSE(topicMatches("sport/+", "sport"));
    CHECK(topicMatches("sport/+", "sport/"));
    CHECK(topicMatches("+/+", "/finance"));
    CHECK(topicMatches("/+", "/finance"));
    CHECK_FALSE(topicMatches("+", "/finance"));
    // §4.7.2: a leading wildcard does not match topics that begin with '$'.
    CHECK_FALSE(topicMatches("#", "$SYS/broker/uptime"));
    CHECK_FALSE(topicMatches("+/monitor/Clients", "$SYS/monitor/Clients"));
    CHECK(topicMatches("$SYS/monitor/+", "$SYS/monitor/Clients"));
    CHECK_FALSE(topicMatches("arm/inbox", "arm/inbox2"));
    // §4.7.1: invalid filters.
    CHECK(topicFilterProblem("sport/tennis#") != "");
    CHECK(topicFilterProblem("sport/tennis/#/ranking") != "");
    CHECK(topicFilterProblem("sport+") != "");
    CHECK(topicFilterProblem("") != "");
    CHECK(topicFilterProblem("sport/+/player1") == "");
    CHECK(topicFilterProblem("+") == "");
}
