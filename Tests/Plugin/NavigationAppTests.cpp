// Issue 34 in the app: the Navigation window runs the navigation scene (Source/Navigation, the one
// `armadillo navigate` runs) in place of the chosen scene, fed by positions over OSC on a real
// UDP port, and shows and says the next waypoint, its distance and bearing. The processor runs as
// the standalone app's does (blocks from the "sound card", the message thread's timer).
#include <catch2/catch.hpp>

#include "Plugin/MessagePump.h"
#include "Navigation/Geodesy.h"
#include "Navigation/Route.h"
#include "Osc/Osc.h"
#include "Plugin/NavigationPanel.h"
#include "Plugin/TactorsPanel.h"
#include "Plugin/MqttPanel.h"
#include "Plugin/ReaderPanel.h"
#include "Mqtt/Broker.h"
#include "Plugin/PluginProcessor.h"
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>
#include <algorithm>
#include <mutex>


using namespace armadillo;
using namespace armadillo::plugin;

namespace {

/// A UDP port nobody listens on now (bound to 0, read back, closed).
int freeUdpPort()
{
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    REQUIRE(fd >= 0);
    sockaddr_in a {};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    REQUIRE(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
    socklen_t len = sizeof a;
    REQUIRE(::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) == 0);
    ::close(fd);
    return ntohs(a.sin_port);
}

void sendPosition(int port, double lat, double lon)
{
    const auto packet = osc::encodeOscMessage("/armadillo/position", {osc::OscArg::float64(lat), osc::OscArg::float64(lon),
                                                                         osc::OscArg::float64(4.0)});
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    REQUIRE(fd >= 0);
    sockaddr_in a {};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    CHECK(::sendto(fd, packet.data(), packet.size(), 0, reinterpret_cast<sockaddr*>(&a), sizeof a) == static_cast<ssize_t>(packet.size()));
    ::close(fd);
}

} // namespace

TEST_CASE("app: the Navigation window walks a route from OSC positions; name, distance and bearing shown and said", "[plugin][navigation]")
{
    const auto dir = juce::File::createTempFile("armadillo-nav");
    REQUIRE(dir.createDirectory());
    const auto routeFile = dir.getChildFile("walk.json");
    REQUIRE(routeFile.replaceWithText(R"({"name": "Test walk", "waypoints": [
        {"lat": 48.1492, "lon": 11.5678, "name": "Start"},
        {"lat": 48.1497396, "lon": 11.5678, "name": "Entrance"},
        {"lat": 48.1499644, "lon": 11.568474, "name": "Lobby"}]})"));

    ArmadilloProcessor processor;
    processor.prepareToPlay(48000.0, 480);
    NavigationPanel panel(processor);
    panel.setSize(640, 460);
    CHECK(panel.waypointLabel().getText() == "Not walking");

    // A bad route and a bad port: said, nothing started.
    const auto bad = dir.getChildFile("bad.json");
    REQUIRE(bad.replaceWithText("[{\"lat\": 95, \"lon\": 0}, {\"lat\": 1, \"lon\": 1}]"));
    auto why = processor.startNavigation(bad, navigation::NavigationRig::Source::Osc, "9004");
    CHECK(why.contains("bad.json"));
    CHECK_FALSE(processor.navigation().running());
    why = processor.startNavigation(routeFile, navigation::NavigationRig::Source::Osc, "0");
    CHECK(why.isNotEmpty());
    CHECK_FALSE(processor.navigation().running());
    // gpsd that is not there: refused, naming where it looked.
    const int nobody = freeUdpPort();
    why = processor.startNavigation(routeFile, navigation::NavigationRig::Source::Gpsd, "127.0.0.1:" + juce::String(nobody));
    CHECK(why.contains(juce::String(nobody)));
    CHECK_FALSE(processor.navigation().running());

    const int port = freeUdpPort();
    why = processor.startNavigation(routeFile, navigation::NavigationRig::Source::Osc, juce::String(port));
    INFO(why);
    REQUIRE(why.isEmpty());
    REQUIRE(processor.navigation().running());

    // 30 m south of the Entrance, standing.
    const navigation::LatLon here {48.1494696, 11.5678};
    const navigation::LatLon entrance {48.1497396, 11.5678};
    juce::AudioBuffer<float> buffer(2, 480);
    juce::MidiBuffer midi;
    navigation::NavigationStatus s;
    for (int i = 0; i < 400 && (s.waypoint == 0 || s.fix != navigation::FixState::Ok); ++i) {
        if (i % 20 == 0) sendPosition(port, here.lat, here.lon);
        buffer.clear();
        processor.processBlock(buffer, midi);   // the control step runs the navigation scene
        midi.clear();
        armadillo::testing::pumpMessages(2);   // the timer offers the engine
        s = processor.navigation().status();
    }
    REQUIRE(s.waypoint == 2);   // the first point is the start: guidance goes to the Entrance
    REQUIRE(s.fix == navigation::FixState::Ok);
    CHECK(juce::String(s.name) == "Entrance");
    CHECK(s.distanceM == Approx(navigation::distanceM(here, entrance)).margin(2.0));
    CHECK(s.bearingDeg == Approx(0.0).margin(2.0));
    armadillo::testing::pumpMessages(300);   // the panel's timer
    CHECK(panel.waypointLabel().getText() == "Entrance");
    CHECK(panel.distanceLabel().getText() == juce::String(juce::roundToInt(s.distanceM)) + " m");
    CHECK(panel.bearingLabel().getText().contains("north"));
    const auto said = panel.spokenStatus();
    CHECK(said.contains("Waypoint 2 of 3, Entrance"));
    CHECK(said.contains("bearing"));
    {
        const auto shot = panel.createComponentSnapshot(panel.getLocalBounds());
        const auto shots = juce::File::getSpecialLocation(juce::File::tempDirectory).getChildFile("armadillo-ui-shots");
        shots.createDirectory();
        juce::FileOutputStream png(shots.getChildFile("navigation-window.png"));
        png.setPosition(0);
        png.truncate();
        CHECK(juce::PNGImageFormat().writeImageToStream(shot, png));
    }

    processor.stopNavigation();
    CHECK_FALSE(processor.navigation().running());
    armadillo::testing::pumpMessages(300);
    CHECK(panel.waypointLabel().getText() == "Not walking");
    processor.releaseResources();
    dir.deleteRecursively();
}

TEST_CASE("app: the Tactors window: every control titled, one test button per channel, a test buzz said", "[plugin][tactors][ui]")
{
    ArmadilloProcessor processor;
    processor.prepareToPlay(48000.0, 480);
    TactorsPanel panel(processor);
    panel.setSize(640, 380);
    int titled = 0, buttons = 0;
    for (auto* c : panel.getChildren()) {
        if (! c->isVisible() || ! c->getWantsKeyboardFocus()) continue;
        INFO("a focusable control without a title: " << c->getName());
        CHECK(c->getTitle().isNotEmpty());
        ++titled;
        if (c->getTitle().startsWith("Test tactor channel")) ++buttons;
    }
    CHECK(buttons == 9);   // one per motor (12 with the back motors)
    CHECK(titled >= 13);
    processor.settings().setProperty(SettingIds::backMotors, true, nullptr);
    armadillo::testing::pumpMessages(400);
    buttons = 0;
    for (auto* c : panel.getChildren())
        if (c->isVisible() && c->getTitle().startsWith("Test tactor channel")) ++buttons;
    CHECK(buttons == 12);
    CHECK(processor.testTactorChannel(11).isEmpty());   // a back motor's channel buzzes too (m12)
    armadillo::testing::pumpMessages(700);                                  // its 0.5 s buzz over, the scene has the motors again
    processor.settings().setProperty(SettingIds::backMotors, false, nullptr);
    CHECK(processor.testTactorChannel(11).contains("silent"));   // without the back motors there is no channel 12
    // A test buzz through the whole rig: said, with the motor's name.
    panel.testButton(2).triggerClick();
    armadillo::testing::pumpMessages(300);
    CHECK(panel.status().getText().contains("Channel 3: motor m3"));
    // A map with a silent channel: that channel's test says so.
    processor.settings().setProperty(SettingIds::tactorMap, "1,-,3", nullptr);
    CHECK(processor.testTactorChannel(1).contains("silent"));
    // In a host there is no device output to open; the bus is the host's to route.
    CHECK(processor.setTactorOutput(true).contains("route the Tactors output bus"));
    // The window as a reader sees it.
    const auto shot = panel.createComponentSnapshot(panel.getLocalBounds());
    const auto shots = juce::File::getSpecialLocation(juce::File::tempDirectory).getChildFile("armadillo-ui-shots");
    shots.createDirectory();
    juce::FileOutputStream png(shots.getChildFile("tactors-window.png"));
    png.setPosition(0);
    png.truncate();
    CHECK(juce::PNGImageFormat().writeImageToStream(shot, png));
    processor.releaseResources();
}

TEST_CASE("app: MQTT messages: connect from the MQTT window, a published message reaches the arm and the Reader window", "[plugin][mqtt]")
{
    test::Broker broker;
    broker.start();
    ArmadilloProcessor processor;
    auto* scene = processor.parameters().getParameter(ParamIds::scene);
    const auto& scenes = processor.sceneTable().scenes;
    int braille = -1;
    for (std::size_t i = 0; i < scenes.size(); ++i)
        if (scenes[i].scene == "braille") braille = static_cast<int>(i);
    REQUIRE(braille >= 0);
    scene->setValueNotifyingHost(scene->convertTo0to1(static_cast<float>(braille)));
    processor.prepareToPlay(48000.0, 480);
    auto& settings = processor.settings();
    settings.setProperty(SettingIds::mqttBroker, "127.0.0.1:" + juce::String(broker.port()), nullptr);
    settings.setProperty(SettingIds::mqttTopics, "arm/inbox", nullptr);
    settings.setProperty(SettingIds::messageDisplay, "timed", nullptr);
    MqttPanel panel(processor);
    panel.setSize(640, 330);
    ReaderPanel reader(processor);
    reader.setSize(640, 860);

    // A bad topic: said, nothing connects.
    settings.setProperty(SettingIds::mqttTopics, "arm/#/x", nullptr);
    CHECK(processor.setMessages(true).contains("arm/#/x"));
    CHECK_FALSE(processor.messages().running());
    settings.setProperty(SettingIds::mqttTopics, "arm/inbox", nullptr);

    panel.connectToggle().triggerClick();   // Connect, as a user presses it
    armadillo::testing::pumpMessages(50);
    REQUIRE(processor.messages().running());
    juce::AudioBuffer<float> buffer(2, 480);
    juce::MidiBuffer midi;
    const auto run = [&](double seconds, const std::function<bool()>& done) {
        const double end = juce::Time::getMillisecondCounterHiRes() + seconds * 1000.0;
        while (juce::Time::getMillisecondCounterHiRes() < end && ! done()) {
            buffer.clear();
            processor.processBlock(buffer, midi);
            midi.clear();
            armadillo::testing::pumpMessages(5);
        }
        return done();
    };
    REQUIRE(run(10.0, [&] { return processor.messages().service()->status().state == mqtt::ConnectionState::Connected; }));
    armadillo::testing::pumpMessages(300);   // the window's timer
    CHECK(panel.status().getText().contains("connected to 127.0.0.1:" + juce::String(broker.port())));
    // The window's test message goes out to the first topic and comes back as a message.
    panel.testButton().triggerClick();
    REQUIRE(run(10.0, [&] { return processor.messages().service()->inbox().accepted >= 1; }));
    // One from elsewhere (a chat bridge's publish): queued, shown on the arm, listed.
    REQUIRE(processor.messages().service()->publishText("arm/inbox", "door open"));
    REQUIRE(run(15.0, [&] { return processor.messages().service()->shown() >= 1 && processor.messageLog().joinIntoString("\n").contains("door open"); }));
    armadillo::testing::pumpMessages(600);   // the Reader window's timer
    const auto list = reader.messagesText();
    INFO(list);
    CHECK(list.contains("door open"));
    CHECK(list.contains("(from arm/inbox)"));
    CHECK(list.contains("on the arm"));
    CHECK(processor.messageLog().joinIntoString("\n").contains("test"));

    // The arm as a remote: a mapping's mqtt destination goes out through the same connection
    // (host automation moves the elevation; a second client of the test hears the topic).
    const auto mapFile = juce::File::createTempFile("remote.json");
    REQUIRE(mapFile.replaceWithText(R"({"version": 1, "mappings": [{"source": "elevation", "in": [-90, 90], "out": [0, 100],
        "to": {"mqtt": {"topic": "arm/elevation", "payload": "{round}", "qos": 0, "retain": false, "rate": 20}}}]})"));
    {
        auto access = processor.mapping();
        INFO(access->loadFile(mapFile.getFullPathName().toStdString()));
    }
    mqtt::MqttConfig listenConfig;
    listenConfig.host = "127.0.0.1";
    listenConfig.port = broker.port();
    listenConfig.topics.push_back({"arm/elevation", 0, false});
    mqtt::MqttClient listener(listenConfig);
    std::mutex heardMutex;
    std::vector<std::string> heard;
    listener.setMessageHandler([&](const mqtt::ReceivedMessage& m) {
        std::lock_guard<std::mutex> lock(heardMutex);
        heard.push_back(m.payload);
    });
    listener.start();
    REQUIRE(listener.waitConnected(10.0));
    auto* source = processor.parameters().getParameter(ParamIds::source);
    source->setValueNotifyingHost(source->convertTo0to1(3.0f));   // host automation
    auto* elevation = processor.parameters().getParameter(ParamIds::elevation);
    for (float el : {-45.0f, 0.0f, 45.0f}) {
        elevation->setValueNotifyingHost(elevation->convertTo0to1(el));
        run(0.3, [] { return false; });
    }
    REQUIRE(run(10.0, [&] {
        std::lock_guard<std::mutex> lock(heardMutex);
        return std::find(heard.begin(), heard.end(), "75") != heard.end();   // 45° of [-90, 90] → 75 of [0, 100]
    }));
    {
        std::lock_guard<std::mutex> lock(heardMutex);
        CHECK(std::find(heard.begin(), heard.end(), "25") != heard.end());   // −45°
    }
    listener.stop();
    mapFile.deleteFile();
    processor.setMessages(false);
    CHECK_FALSE(processor.messages().running());
    processor.releaseResources();
}
