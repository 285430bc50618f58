// Issue 47 in the app: Setup → Web page serves the app's own instrument (live::BlockInstrument,
// the page of `play --web`), over a real loopback socket. The processor runs as the standalone
// app's does (blocks from the "sound card", the message thread's timer); the window is driven as
// a user drives it (the toggle clicked).
#include <catch2/catch.hpp>

#include "Plugin/MessagePump.h"
#include "Common/HttpProbe.h"
#include "Plugin/PluginProcessor.h"
#include "Plugin/WebPanel.h"
#include <cmath>
#include <cstdlib>


using namespace armadillo;
using namespace armadillo::plugin;

namespace {

double numberAfter(const std::string& text, const std::string& key)
{
    const std::size_t at = text.find("\"" + key + "\":");
    return at == std::string::npos ? std::nan("") : std::atof(text.c_str() + at + key.size() + 3);
}

} // namespace

TEST_CASE("app: Setup → Web page serves the app's instrument: the pose as text, its parameters, Panic, closed when off", "[plugin][web]")
{
    ArmadilloProcessor processor;
    auto& apvts = processor.parameters();
    const auto& scenes = processor.sceneTable().scenes;
    int theremin = -1;
    for (std::size_t i = 0; i < scenes.size(); ++i)
        if (scenes[i].scene == "theremin") theremin = static_cast<int>(i);
    REQUIRE(theremin >= 0);
    const auto& entry = scenes[static_cast<std::size_t>(theremin)];
    std::size_t param = 0;
    while (param < entry.specs.size() && (! entry.exposed[param] || entry.specs[param].choices.size() > 0)) ++param;
    REQUIRE(param < entry.specs.size());
    const core::ParamSpec spec = entry.specs[param];
    auto setParam = [&](const char* id, float value) {
        auto* p = apvts.getParameter(id);
        p->setValueNotifyingHost(p->convertTo0to1(value));
    };
    setParam(ParamIds::scene, static_cast<float>(theremin));
    setParam(ParamIds::source, static_cast<float>(live::SourceKind::HostAutomation));
    setParam(ParamIds::elevation, 30.0f);
    processor.prepareToPlay(48000.0, 480);
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

    // Closed by default: nothing listens, the window says so.
    WebPanel panel(processor);
    panel.setSize(640, 400);
    CHECK_FALSE(panel.serveToggle().getToggleState());
    CHECK(processor.webAddress().isEmpty());

    panel.serveToggle().triggerClick();   // on, as a user clicks it
    armadillo::testing::pumpMessages(20);
    const auto address = processor.webAddress();
    REQUIRE(address.startsWith("http://127.0.0.1:"));
    CHECK(static_cast<bool>(processor.settings()[SettingIds::webEnabled]));
    const int port = address.fromLastOccurrenceOf(":", false, false).getIntValue();
    REQUIRE(port > 0);
    armadillo::testing::pumpMessages(300);   // the window's timer
    CHECK(panel.address().getText() == address);
    if (const char* dir = std::getenv("ARMADILLO_SNAPSHOT_DIR")) {   // for a person to look at (docs/images)
        juce::PNGImageFormat png;
        juce::FileOutputStream out(juce::File(dir).getChildFile("web-page-window.png"));
        if (out.openedOk()) png.writeImageToStream(panel.createComponentSnapshot(panel.getLocalBounds()), out);
    }

    // The page's status: the scene, and the elevation the host automation gives the arm.
    std::string reply;
    REQUIRE(run(10.0, [&] {
        return armadillo::testing::httpSend(port, armadillo::testing::httpGet(port, "/api/status"), &reply) == 200
               && std::abs(numberAfter(reply, "elevation_deg") - 30.0) < 3.0 && reply.find("\"scene\":\"theremin\"") != std::string::npos;
    }));
    CHECK(reply.find("host automation") != std::string::npos);

    // The scene's parameters are the host's: listed with their values, and set from the page as a
    // host parameter (clamped to its range).
    REQUIRE(armadillo::testing::httpSend(port, armadillo::testing::httpGet(port, "/api/scene"), &reply) == 200);
    CHECK(reply.find("\"" + spec.id + "\"") != std::string::npos);
    const std::string self = "http://127.0.0.1:" + std::to_string(port);
    const std::string token = armadillo::testing::pageToken(port);
    REQUIRE(token.size() == 32);
    const double wanted = spec.max + 1000.0;   // beyond the range: the top of it
    REQUIRE(armadillo::testing::httpSend(port, armadillo::testing::httpPost(port, "/api/param", "id=" + spec.id + "&value=" + std::to_string(wanted), self, token),
                                         &reply) == 200);
    auto* hostParam = apvts.getParameter(juce::String(spec.id));
    REQUIRE(hostParam != nullptr);
    REQUIRE(run(5.0, [&] { return std::abs(hostParam->convertFrom0to1(hostParam->getValue()) - spec.max) < 1e-3 * (1.0 + std::abs(spec.max)); }));

    // Refused: a foreign Host, a foreign Origin (nothing reaches the stage).
    CHECK(armadillo::testing::httpSend(port, "GET /api/status HTTP/1.1\r\nHost: evil.example\r\nConnection: close\r\n\r\n") == 403);
    CHECK(armadillo::testing::httpSend(port, armadillo::testing::httpPost(port, "/api/stage", "panic", "http://evil.example", token)) == 403);
    run(0.2, [] { return false; });
    CHECK_FALSE(processor.panicked());

    // Panic from the page: the stage holds it, the published motors are all off.
    REQUIRE(armadillo::testing::httpSend(port, armadillo::testing::httpPost(port, "/api/stage", "panic", self, token)) == 200);
    REQUIRE(run(5.0, [&] { return processor.panicked(); }));
    run(0.3, [] { return false; });
    const auto frame = processor.latestFrame();
    for (int m = 0; m < frame.motorCount; ++m) CHECK(frame.motors[static_cast<std::size_t>(m)] == 0);
    armadillo::testing::pumpMessages(300);
    CHECK(processor.webLog().joinIntoString("\n").contains("panic"));

    // The sensitivity test from the page: the Reader window's own test runs (on the message
    // thread), asks, takes an answer, and gives the motors back when cancelled.
    processor.resume();
    REQUIRE(armadillo::testing::httpSend(port, armadillo::testing::httpPost(port, "/api/touch", "begin", self, token)) == 200);
    REQUIRE(run(5.0, [&] { return processor.touchTest().state() != procedures::TouchTest::State::Idle; }));
    REQUIRE(run(10.0, [&] {
        return armadillo::testing::httpSend(port, armadillo::testing::httpGet(port, "/api/status"), &reply) == 200
               && reply.find("\"asking\":true") != std::string::npos && reply.find("felt it?") != std::string::npos;
    }));
    const int asked = processor.touchTest().stimuli();
    REQUIRE(armadillo::testing::httpSend(port, armadillo::testing::httpPost(port, "/api/touch", "not-felt", self, token)) == 200);
    REQUIRE(run(10.0, [&] { return processor.touchTest().stimuli() > asked; }));
    REQUIRE(armadillo::testing::httpSend(port, armadillo::testing::httpPost(port, "/api/touch", "cancel", self, token)) == 200);
    REQUIRE(run(5.0, [&] { return processor.touchTest().state() == procedures::TouchTest::State::Idle; }));

    // The scene chooser: the host's scene parameter follows the page's choice.
    int cymbal = -1;
    for (std::size_t i = 0; i < scenes.size(); ++i)
        if (scenes[i].scene == "cymbal") cymbal = static_cast<int>(i);
    REQUIRE(cymbal >= 0);
    REQUIRE(armadillo::testing::httpSend(port, armadillo::testing::httpGet(port, "/api/scene"), &reply) == 200);
    CHECK(reply.find("\"cymbal\"") != std::string::npos);
    CHECK(reply.find("\"scene_choice\":\"\"") != std::string::npos);
    CHECK(armadillo::testing::httpSend(port, armadillo::testing::httpPost(port, "/api/scene", "scene=nothing", self, token)) == 409);
    REQUIRE(armadillo::testing::httpSend(port, armadillo::testing::httpPost(port, "/api/scene", "scene=cymbal", self, token)) == 200);
    auto* sceneParam = apvts.getParameter(ParamIds::scene);
    REQUIRE(run(5.0, [&] { return static_cast<int>(std::lround(sceneParam->convertFrom0to1(sceneParam->getValue()))) == cymbal; }));
    REQUIRE(run(5.0, [&] {
        return armadillo::testing::httpSend(port, armadillo::testing::httpGet(port, "/api/status"), &reply) == 200
               && reply.find("\"scene\":\"cymbal\"") != std::string::npos;
    }));

    // Given an address (here loopback's, as a network address would be): reopened there, and
    // every request needs the token the address shown carries.
    processor.settings().setProperty(SettingIds::webBind, "127.0.0.1", nullptr);
    armadillo::testing::pumpMessages(20);
    const auto withToken = processor.webAddress();
    REQUIRE(withToken.contains("?token="));
    const int tokenPort = withToken.fromLastOccurrenceOf(":", false, false).getIntValue();
    CHECK(armadillo::testing::httpSend(tokenPort, armadillo::testing::httpGet(tokenPort, "/api/status")) == 403);
    const auto path = "/api/status?token=" + withToken.fromFirstOccurrenceOf("?token=", false, false).toStdString();
    CHECK(armadillo::testing::httpSend(tokenPort, armadillo::testing::httpGet(tokenPort, path)) == 200);

    // Off from the window: the port closes.
    panel.serveToggle().triggerClick();
    armadillo::testing::pumpMessages(20);
    CHECK(processor.webAddress().isEmpty());
    CHECK_FALSE(static_cast<bool>(processor.settings()[SettingIds::webEnabled]));
    CHECK(armadillo::testing::httpSend(tokenPort, armadillo::testing::httpGet(tokenPort, "/api/status")) == 0);
    processor.releaseResources();
}
