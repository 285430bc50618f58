// The instrument on the block clock, assembled once (Live/Session/BlockInstrument.h, issue 45): built with
// nothing but the host's cells and an engine, it runs the control step on its own idle clock with
// the simulated arm as source, steers to a pose, applies a panic through its stage, and stops —
// the clock and every part — once, however often it is asked.
#include "Common/HttpProbe.h"
#include "Engine/Engine.h"
#include "Live/Session/BlockInstrument.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::engine;

namespace {
struct Cells {
    std::atomic<float> elevation {0.0f}, azimuth {0.0f}, roll {0.0f}, source {static_cast<float>(live::SourceKind::Simulator)};
    live::BlockControl::Cells cells() { return {&elevation, &azimuth, &roll, &source}; }
};

void installEngine(live::BlockInstrument& instrument, const std::string& scene)
{
    EngineConfig config;
    config.scene = scene;
    config.sceneConfig.sampleRate = 48000.0;
    auto slot = std::make_unique<live::EngineSlot>();
    slot->engine = std::make_unique<Engine>(config);
    slot->sceneName = config.scene;
    instrument.install(std::move(slot));
    instrument.prepare(config.sceneConfig.sampleRate);
}

/// Polls `done` until it holds or `seconds` of wall time pass (no fixed sleep decides a result).
template <typename F>
bool within(double seconds, F done)
{
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
        if (done()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return done();
}
} // namespace

TEST_CASE("block instrument: its idle clock runs the step from the simulated arm, its stage panics, stop() ends it once",
          "[live][instrument]")
{
    Cells cells;
    live::SceneParameterTable table;
    live::BlockInstrument instrument(live::BlockInstrument::Host {cells.cells(), &table, [] { return 1; }});
    installEngine(instrument, "theremin");
    instrument.rig().setSimulatorWandering(false);
    Pose target;
    target.elevationDeg = 40.0;
    target.azimuthDeg = 20.0;
    instrument.rig().steerSimulator(target);
    REQUIRE(instrument.control().latestFrame().serial == 0);   // nothing runs before start()
    instrument.start();

    // The step runs (frames count up) and follows the steered arm.
    REQUIRE(within(5.0, [&] {
        const auto f = instrument.control().latestFrame();
        return f.valid && std::abs(f.pose[0] - target.elevationDeg) < 3.0;
    }));
    CHECK(instrument.sourceSamples(live::SourceKind::Simulator) > 0);
    CHECK(instrument.control().source() == live::SourceKind::Simulator);

    // A panic through the stage (the one switch) silences every motor at a following step.
    instrument.stage().apply(StageCommand {StageCommand::Kind::Panic});
    REQUIRE(within(2.0, [&] { return instrument.stage().panicked(); }));
    const auto afterPanic = instrument.control().latestFrame().serial;
    REQUIRE(within(2.0, [&] { return instrument.control().latestFrame().serial > afterPanic + 5; }));
    const auto frame = instrument.control().latestFrame();
    for (int m = 0; m < frame.motorCount; ++m) CHECK(frame.motors[static_cast<std::size_t>(m)] == 0);

    // stop(): no step after it, and a second stop (the destructor's) is harmless.
    instrument.stop();
    const auto last = instrument.control().latestFrame().serial;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));   // 10 idle periods: none may step
    CHECK(instrument.control().latestFrame().serial == last);
    instrument.stop();
    instrument.start();   // not after stop(): the instrument stays stopped
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    CHECK(instrument.control().latestFrame().serial == last);
}

// The web page from the block instrument (issue 47: the app's Setup → Web page): the page's
// status follows the steered arm, the page's Panic reaches the instrument's one switch and
// silences the motors, a parameter goes through the host, and a foreign Host or Origin is refused
// before anything reaches the instrument. Over real loopback sockets.
TEST_CASE("block instrument: its web page shows the arm, its Panic silences the motors, the host sets its parameters",
          "[live][instrument][web]")
{
    Cells cells;
    live::SceneParameterTable table;
    live::BlockInstrument instrument(live::BlockInstrument::Host {cells.cells(), &table, [] { return 1; }});
    installEngine(instrument, "theremin");
    instrument.rig().setSimulatorWandering(false);
    Pose target;
    target.elevationDeg = 35.0;
    target.azimuthDeg = -10.0;
    instrument.rig().steerSimulator(target);
    instrument.start();
    std::atomic<int> hostSets {0};
    live::BlockWebView::Host host;
    host.parameters = [] { return std::vector<web::ParameterInfo> {{"theremin.range", "Range", "st", 12.0, 48.0, 24.0, {}}}; };
    host.setParameter = [&](const std::string& id, double value, double& set) {
        if (id != "theremin.range") return false;
        set = std::clamp(value, 12.0, 48.0);
        ++hostSets;
        return true;
    };
    REQUIRE(instrument.startWeb(web::WebConfig {true, 0, ""}, host).empty());
    REQUIRE(instrument.webServer() != nullptr);
    const int port = instrument.webServer()->port();
    CHECK(instrument.webServer()->address() == "http://127.0.0.1:" + std::to_string(port) + "/");
    instrument.refreshWeb("theremin");   // the message thread's part

    // The status: the scene, the source, and the elevation of the steered arm.
    std::string reply;
    REQUIRE(within(5.0, [&] {
        if (testing::httpSend(port, testing::httpGet(port, "/api/status"), &reply) != 200) return false;
        const std::size_t at = reply.find("\"elevation_deg\":");
        return at != std::string::npos && std::abs(std::stod(reply.substr(at + 16)) - target.elevationDeg) < 3.0;
    }));
    CHECK(reply.find("\"scene\":\"theremin\"") != std::string::npos);
    CHECK(reply.find("simulated forearm (steered)") != std::string::npos);
    CHECK(reply.find("the device calibration needs a device") != std::string::npos);   // no device connected: said

    // The guided device calibration from the page, on the device (the simulated forearm in-process):
    // begun, its first step shown, every step skipped to the end, the result offered as a file.
    const std::string selfUrl = "http://127.0.0.1:" + std::to_string(port);
    const std::string pageToken = testing::pageToken(port);
    instrument.rig().connectDevice(live::DeviceConnection::kSimulatedPort, 57600, "");
    REQUIRE(instrument.rig().deviceConnected());
    CHECK(testing::httpSend(port, testing::httpPost(port, "/api/calibration", "begin", selfUrl, pageToken)) == 200);
    instrument.refreshWeb("theremin");   // the message thread takes the command
    REQUIRE(testing::httpSend(port, testing::httpGet(port, "/api/status"), &reply) == 200);
    CHECK(reply.find("\"calibration\":{\"available\":true") != std::string::npos);
    CHECK(reply.find("\"running\":true,\"finished\":false,\"step\":1,\"steps\":7") != std::string::npos);
    CHECK(testing::httpSend(port, testing::httpGet(port, "/api/calibration.json")) == 404);
    for (int step = 0; step < 7; ++step) {
        CHECK(testing::httpSend(port, testing::httpPost(port, "/api/calibration", "skip", selfUrl, pageToken)) == 200);
        instrument.refreshWeb("theremin");
    }
    REQUIRE(testing::httpSend(port, testing::httpGet(port, "/api/status"), &reply) == 200);
    CHECK(reply.find("calibration complete") != std::string::npos);
    REQUIRE(testing::httpSend(port, testing::httpGet(port, "/api/calibration.json"), &reply) == 200);
    CHECK(reply.find("\"gyro\"") != std::string::npos);
    instrument.rig().disconnectDevice();

    // Refused before the instrument: a foreign Host, a foreign Origin.
    const std::string self = "http://127.0.0.1:" + std::to_string(port);
    const std::string token = testing::pageToken(port);
    REQUIRE(token.size() == 32);
    CHECK(testing::httpSend(port, "GET /api/status HTTP/1.1\r\nHost: evil.example\r\nConnection: close\r\n\r\n") == 403);
    CHECK(testing::httpSend(port, testing::httpPost(port, "/api/stage", "panic", "http://evil.example", token)) == 403);
    CHECK_FALSE(instrument.stage().panicked());

    // A parameter through the host, clamped there.
    CHECK(testing::httpSend(port, testing::httpPost(port, "/api/param", "id=theremin.range&value=99", self, token), &reply) == 200);
    CHECK(hostSets == 1);
    CHECK(reply.find("\"value\":48.0000") != std::string::npos);

    // Panic from the page: the stage holds it and every motor of the following steps is off.
    CHECK(testing::httpSend(port, testing::httpPost(port, "/api/stage", "panic", self, token)) == 200);
    REQUIRE(within(2.0, [&] { return instrument.stage().panicked(); }));
    const auto afterPanic = instrument.control().latestFrame().serial;
    REQUIRE(within(2.0, [&] { return instrument.control().latestFrame().serial > afterPanic + 5; }));
    const auto frame = instrument.control().latestFrame();
    for (int m = 0; m < frame.motorCount; ++m) CHECK(frame.motors[static_cast<std::size_t>(m)] == 0);
    CHECK(testing::httpSend(port, testing::httpPost(port, "/api/stage", "resume", self, token)) == 200);
    REQUIRE(within(2.0, [&] { return !instrument.stage().panicked(); }));

    // Off: the port is closed; stop() closes it too when it is on.
    instrument.stopWeb();
    CHECK(instrument.webServer() == nullptr);
    CHECK(testing::httpSend(port, testing::httpGet(port, "/api/status")) == 0);
    REQUIRE(instrument.startWeb(web::WebConfig {true, 0, ""}, host).empty());
    const int second = instrument.webServer()->port();
    instrument.stop();
    CHECK(testing::httpSend(second, testing::httpGet(second, "/api/status")) == 0);
}
