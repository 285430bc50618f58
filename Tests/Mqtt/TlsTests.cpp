// TLS with a CA file against a real Mosquitto TLS listener: the test makes its own certificate
// authority and a server certificate for "localhost" with openssl (in its scratch folder), starts
// mosquitto with them, and connects with the CA file; a client trusting another CA is refused,
// and its status says why.
#include "Broker.h"
#include "Common/Eventually.h"
#include "Mqtt/MqttClient.h"
#include <catch2/catch.hpp>
#include <cstdlib>
#include <mutex>

using namespace armadillo;
using namespace armadillo::mqtt;

namespace {

/// A CA (ca.pem, ca.key) in `dir`, and when `server`, a key and certificate for localhost signed by it.
bool makeCertificates(const std::string& dir, bool server)
{
    std::string cmd = "cd '" + dir + "' && openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj '/CN=ARMadillo test CA' "
                                     "-keyout ca.key -out ca.pem >/dev/null 2>&1";
    if (server)
        cmd += " && openssl req -newkey rsa:2048 -nodes -subj '/CN=localhost' -keyout server.key -out server.csr >/dev/null 2>&1"
               " && printf 'subjectAltName=DNS:localhost,IP:127.0.0.1\\n' > san.ext"
               " && openssl x509 -req -in server.csr -CA ca.pem -CAkey ca.key -CAcreateserial -days 2 -extfile san.ext -out server.pem >/dev/null 2>&1"
               // mosquitto started as root drops to its own user, which must read them (a throwaway test key)
               " && chmod 644 server.key server.pem ca.pem";
    return std::system(cmd.c_str()) == 0;
}

} // namespace

TEST_CASE("TLS with a CA file: connects to a TLS broker; a client trusting another CA is refused", "[mqtt][tls]")
{
    const auto base = test::scratchDir("armadillo-mqtt-tests");
    const std::string good = (base / "tls-good").string(), other = (base / "tls-other").string();
    std::filesystem::create_directories(good);
    std::filesystem::create_directories(other);
    REQUIRE(makeCertificates(good, true));
    REQUIRE(makeCertificates(other, false));
    test::Broker broker("cafile " + good + "/ca.pem\ncertfile " + good + "/server.pem\nkeyfile " + good + "/server.key\n");
    broker.start();

    MqttConfig c;
    c.host = "localhost";
    c.port = broker.port();
    c.caFile = good + "/ca.pem";
    c.topics = {{"secure/#", 1, false}};
    c.reconnectMin = 0.05;
    c.reconnectMax = 0.2;
    std::mutex mutex;
    std::vector<std::string> heard;
    MqttClient sub(c);
    sub.setMessageHandler([&](const ReceivedMessage& m) {
        std::lock_guard lock(mutex);
        heard.push_back(m.payload);
    });
    sub.start();
    const bool connected = sub.waitConnected(30);
    INFO("subscriber: " << sub.status().lastError);
    REQUIRE(connected);
    MqttConfig pc = c;
    pc.topics.clear();
    MqttClient pub(pc);
    pub.start();
    REQUIRE(pub.waitConnected(30));
    REQUIRE(pub.publishText("secure/x", "over TLS", 1));
    REQUIRE(armadillo::testing::eventually([&] {
        std::lock_guard lock(mutex);
        return !heard.empty();
    }));
    CHECK(heard.front() == "over TLS");

    MqttConfig wrong = pc;
    wrong.caFile = other + "/ca.pem";
    MqttClient stranger(wrong);
    stranger.start();
    REQUIRE(armadillo::testing::eventually([&] { return stranger.status().failedAttempts + stranger.status().connectionLosses >= 2; }));
    const MqttStatus s = stranger.status();
    CHECK(s.connects == 0);
    CHECK(s.state == ConnectionState::Reconnecting);
    CHECK_FALSE(s.lastError.empty());
    INFO(s.lastError);
}
