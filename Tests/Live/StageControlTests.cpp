// Stage commands (docs/STAGE.md): the OSC addresses and keys, refused input, and the control
// port over loopback UDP.
#include "Common/Eventually.h"
#include "Osc/Osc.h"
#include "Live/Stage/StageControl.h"
#include <catch2/catch.hpp>
#include <arpa/inet.h>
#include <atomic>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>
#include <vector>

using namespace armadillo;
using namespace armadillo::live;

namespace {
/// Decodes an encoded message back into an OscMessage and parses it as a stage command.
bool parse(const std::vector<std::uint8_t>& bytes, core::StageCommand& out, std::string& why)
{
    bool result = false;
    std::string error;
    const bool ok = osc::decodeOscPacket(bytes.data(), bytes.size(), [&](const osc::OscMessage& m) { result = stageCommandFromOsc(m, out, why); }, &error);
    return ok && result;
}
} // namespace

TEST_CASE("stage: OSC addresses become commands; anything else is refused with a reason", "[stage]")
{
    using K = core::StageCommand::Kind;
    core::StageCommand c;
    std::string why;
    REQUIRE(parse(osc::encodeOscMessage("/armadillo/panic", {}), c, why));
    CHECK(c.kind == K::Panic);
    REQUIRE(parse(osc::encodeOscMessage("/armadillo/resume", {}), c, why));
    CHECK(c.kind == K::Resume);
    REQUIRE(parse(osc::encodeOscMessage("/armadillo/cue/next", {}), c, why));
    CHECK(c.kind == K::CueNext);
    REQUIRE(parse(osc::encodeOscMessage("/armadillo/cue/prev", {}), c, why));
    CHECK(c.kind == K::CuePrev);
    REQUIRE(parse(osc::encodeOscMessage("/armadillo/cue", {osc::OscArg::int32(3)}), c, why));
    CHECK(c.kind == K::CueGoto);
    CHECK(c.cue == 3);
    REQUIRE(parse(osc::encodeOscMessage("/armadillo/cue", {osc::OscArg::float32(2.0f)}), c, why));
    CHECK(c.cue == 2);
    CHECK(describe(c) == "cue 2");
    for (const auto& bad : {osc::encodeOscMessage("/armadillo/cue", {}), osc::encodeOscMessage("/armadillo/cue", {osc::OscArg::int32(-1)}),
                            osc::encodeOscMessage("/armadillo/cue", {osc::OscArg::float32(1.5f)}),
                            osc::encodeOscMessage("/armadillo/cue", {osc::OscArg::string("one")}),
                            osc::encodeOscMessage("/armadillo/panik", {})}) {
        why.clear();
        CHECK_FALSE(parse(bad, c, why));
        CHECK_FALSE(why.empty());
    }
}

TEST_CASE("stage: keys", "[stage]")
{
    using K = core::StageCommand::Kind;
    core::StageCommand c;
    REQUIRE(stageCommandFromKey('p', c));
    CHECK(c.kind == K::Panic);
    REQUIRE(stageCommandFromKey(27, c));
    CHECK(c.kind == K::Panic);
    REQUIRE(stageCommandFromKey('r', c));
    CHECK(c.kind == K::Resume);
    REQUIRE(stageCommandFromKey(' ', c));
    CHECK(c.kind == K::CueNext);
    REQUIRE(stageCommandFromKey('b', c));
    CHECK(c.kind == K::CuePrev);
    REQUIRE(stageCommandFromKey('7', c));
    CHECK((c.kind == K::CueGoto && c.cue == 7));
    CHECK_FALSE(stageCommandFromKey('x', c));
    CHECK_FALSE(stageCommandFromKey('\n', c));
}

TEST_CASE("stage: the control port takes commands over loopback UDP and counts what it refuses", "[stage][osc]")
{
    std::atomic<int> panics {0}, cues {0}, lastCue {-1};
    StageControlReceiver receiver(0, [&](const core::StageCommand& c) {
        if (c.kind == core::StageCommand::Kind::Panic) ++panics;
        if (c.kind == core::StageCommand::Kind::CueGoto) {
            lastCue = c.cue;
            ++cues;
        }
    });
    REQUIRE(receiver.port() > 0);
    receiver.start();
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    REQUIRE(fd >= 0);
    sockaddr_in to {};
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<std::uint16_t>(receiver.port()));
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    auto send = [&](const std::vector<std::uint8_t>& bytes) {
        ::sendto(fd, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
    };
    send(osc::encodeOscMessage("/armadillo/panic", {}));
    send(osc::encodeOscMessage("/armadillo/cue", {osc::OscArg::int32(2)}));
    send(osc::encodeOscMessage("/armadillo/imu", {osc::OscArg::float32(1.0f)}));   // not a stage command
    send({0x01, 0x02, 0x03});                                                          // not OSC
    CHECK(armadillo::testing::eventually([&] { return receiver.commands() == 2 && receiver.refused() == 2; }));
    CHECK(panics == 1);
    CHECK(cues == 1);
    CHECK(lastCue == 2);
    ::close(fd);
    receiver.stop();
}

TEST_CASE("stage: /armadillo/message carries a text and a priority for the arm (issue 35)", "[stage][osc][mqtt]")
{
    std::vector<std::pair<std::string, int>> texts;
    int commands = 0;
    StageControlReceiver receiver(0, [&](const core::StageCommand&) { ++commands; });
    const auto send = [&](const std::vector<std::uint8_t>& bytes) { receiver.handleDatagram(bytes.data(), bytes.size()); };
    // Without a text handler the message is refused (counted), not taken for a command.
    send(osc::encodeOscMessage("/armadillo/message", {osc::OscArg::string("exit")}));
    CHECK(receiver.refused() == 1);
    receiver.setTextHandler([&](const std::string& t, int priority) { texts.emplace_back(t, priority); });
    send(osc::encodeOscMessage("/armadillo/message", {osc::OscArg::string("exit")}));
    send(osc::encodeOscMessage("/armadillo/message", {osc::OscArg::string("fire"), osc::OscArg::int32(2)}));
    send(osc::encodeOscMessage("/armadillo/message", {osc::OscArg::string("later"), osc::OscArg::float32(0.5f)}));
    send(osc::encodeOscMessage("/armadillo/message", {}));                                   // no text
    send(osc::encodeOscMessage("/armadillo/message", {osc::OscArg::int32(3)}));           // not a string
    send(osc::encodeOscMessage("/armadillo/message", {osc::OscArg::string("a"), osc::OscArg::string("b")}));
    CHECK(texts == std::vector<std::pair<std::string, int>> {{"exit", 0}, {"fire", 1}, {"later", 0}});
    CHECK(receiver.refused() == 4);
    CHECK(receiver.commands() == 3);
    CHECK(commands == 0);
}
