// Two arms in the plugin (issue 28, docs/STAGE.md "Two arms"): an OSC sender on loopback as the
// left arm, through the built VST3 as a DAW hosts it. The left arm's pose is sent as
// /armadillo/orientation (INTERFACES.md "OSC"); what the plugin makes of it is heard in its audio
// (theremin-duo: the left arm hanging stops the note, Instruments/ThereminDuoScene.cpp) and seen
// in its MIDI (a mapping on `left.elevation`, docs/MAPPING.md "Two arms"). Waits are event-driven:
// render and pump until the expected output shows, with a deadline.
#include <catch2/catch.hpp>

#include "Common/RealtimeGuard.h"
#include "Core/Pose.h"
#include "Osc/Osc.h"
#include "Osc/OscIo.h"
#include "Plugin/HostedPlugin.h"
#include <cmath>
#include <vector>

using namespace armadillo::test::host;

namespace {

/// A UDP port free on loopback now (the OS's choice; the plugin binds it next).
int freeUdpPort()
{
    juce::DatagramSocket probe;
    REQUIRE(probe.bindToPort(0, "127.0.0.1"));
    const int port = probe.getBoundPort();
    REQUIRE(port > 0);
    return port;
}

/// The plugin's own state document from its text, as a DAW restores one.
void setOwnStateVst3(Hosted& h, const juce::String& xml)
{
    auto own = juce::parseXML(xml);
    REQUIRE(own != nullptr);
    armadillo::test::host::setOwnStateVst3(h, *own);
}

/// Host automation (source 3) on `scene`, the left arm's sender on `port` when `leftOn`, and an
/// optional MAPPING node.
juce::String twoArmState(int scene, bool leftOn, int port, const juce::String& mapping = {})
{
    juce::String s = "<ARMADILLO version=\"1\"><PARAMETERS><PARAM id=\"source\" value=\"3\"/><PARAM id=\"scene\" value=\"" + juce::String(scene)
                     + "\"/></PARAMETERS><SETTINGS leftArmOsc=\"" + juce::String(leftOn ? 1 : 0) + "\" leftArmOscPort=\"" + juce::String(port) + "\"/>";
    if (mapping.isNotEmpty()) s << "<MAPPING name=\"test\" json=\"" << mapping.replace("&", "&amp;").replace("\"", "&quot;").replace("<", "&lt;") << "\"/>";
    return s + "</ARMADILLO>";
}

struct Block {
    double rms = 0.0;
    std::vector<std::vector<std::uint8_t>> midi;
};

/// One block: the left arm's orientation sent first (the sender keeps sending, as a phone does),
/// then the block rendered, then the plugin's message thread pumped.
Block sendAndRender(Hosted& h, armadillo::osc::OscSender& sender, const armadillo::core::Pose& left)
{
    sender.sendOrientation(armadillo::core::poseToQuaternion(left));
    juce::AudioBuffer<float> buffer(2, kBlock);
    juce::MidiBuffer midi;
    buffer.clear();
    h.plugin->processBlock(buffer, midi);
    Block b;
    double s = 0.0;
    for (int i = 0; i < kBlock; ++i) s += double(buffer.getSample(0, i)) * double(buffer.getSample(0, i));
    b.rms = std::sqrt(s / kBlock);
    for (const auto m : midi) b.midi.emplace_back(m.data, m.data + m.numBytes);
    juce::MessageManager::getInstance()->runDispatchLoopUntil(1);
    return b;
}

/// RMS over the last `window` blocks, rendering (and sending) until `done(rms)` or 10 s.
template <typename Done>
double renderUntil(Hosted& h, armadillo::osc::OscSender& sender, const armadillo::core::Pose& left, Done done, int window = 20)
{
    std::vector<double> energies;
    const auto deadline = juce::Time::getMillisecondCounter() + 10000;
    double rms = -1.0;
    while (juce::Time::getMillisecondCounter() < deadline) {
        const Block b = sendAndRender(h, sender, left);
        energies.push_back(b.rms * b.rms);
        if (static_cast<int>(energies.size()) < window) continue;
        double sum = 0.0;
        for (std::size_t i = energies.size() - static_cast<std::size_t>(window); i < energies.size(); ++i) sum += energies[i];
        rms = std::sqrt(sum / window);
        if (done(rms)) break;
    }
    return rms;
}

const armadillo::core::Pose kLeftRaised {30.0, 0.0, 0.0}, kLeftHanging {-85.0, 0.0, 0.0};
const int kDuo = choiceIndex("Scene", "theremin-duo");

} // namespace

TEST_CASE("VST3: an OSC sender as the left arm plays theremin-duo's articulation; off, it is not heard", "[plugin][two-arms]")
{
    REQUIRE(kDuo >= 0);
    const int port = freeUdpPort();
    armadillo::osc::OscSender sender(armadillo::osc::HostPort {"127.0.0.1", port});
    auto h = loadVst3();
    prepare(h);
    setValue(h, "Elevation", 20.0f, -90.0f, 90.0f);   // the right arm plays a note (host automation)

    SECTION("on: the left arm hanging silences the duo, raised it sounds again")
    {
        setOwnStateVst3(h, twoArmState(kDuo, true, port));
        const double raised = renderUntil(h, sender, kLeftRaised, [](double rms) { return rms > 0.02; });
        INFO("raised " << raised);
        CHECK(raised > 0.02);
        const double hanging = renderUntil(h, sender, kLeftHanging, [](double rms) { return rms < 1e-4; });
        INFO("hanging " << hanging);
        CHECK(hanging < 1e-4);   // only the left arm changed: its articulation stops the note
        const double again = renderUntil(h, sender, kLeftRaised, [](double rms) { return rms > 0.02; });
        CHECK(again > 0.02);
        // The state keeps the settings.
        auto own = ownState(h);
        REQUIRE(own->getChildByName("SETTINGS") != nullptr);
        CHECK(own->getChildByName("SETTINGS")->getBoolAttribute("leftArmOsc"));
        CHECK(own->getChildByName("SETTINGS")->getIntAttribute("leftArmOscPort") == port);
    }
    SECTION("off (the default): the same sender changes nothing, the duo keeps sounding")
    {
        setOwnStateVst3(h, twoArmState(kDuo, false, port));
        const double sounding = renderUntil(h, sender, kLeftHanging, [](double rms) { return rms > 0.02; });
        CHECK(sounding > 0.02);
        // 1 s more of the hanging left arm sent: nobody listens, the note goes on.
        double quietest = 1.0;
        for (int i = 0; i < 10; ++i)
            quietest = std::min(quietest, renderUntil(h, sender, kLeftHanging, [](double) { return true; }));
        CHECK(quietest > 0.02);
        auto own = ownState(h);
        CHECK_FALSE(own->getChildByName("SETTINGS")->getBoolAttribute("leftArmOsc"));
    }
    h.plugin->releaseResources();
}

TEST_CASE("VST3: a mapping on left.elevation sends its CC from the left arm's sender, and nothing without it", "[plugin][two-arms]")
{
    const int port = freeUdpPort();
    armadillo::osc::OscSender sender(armadillo::osc::HostPort {"127.0.0.1", port});
    auto h = loadVst3();
    prepare(h);
    const juce::String mapping = R"({"version": 1, "mappings": [
        {"source": "left.elevation", "in": [-90, 90], "to": {"midi": "cc", "channel": 1, "cc": 20}}]})";
    auto lastCc20 = [&](const armadillo::core::Pose& left, int blocks) {
        int value = -1;
        for (int i = 0; i < blocks; ++i)
            for (const auto& m : sendAndRender(h, sender, left).midi)
                if (m.size() == 3 && m[0] == 0xB0 && m[1] == 20) value = m[2];
        return value;
    };
    // CC value of the definition (docs/MAPPING.md: `in` → 0…127): (30 + 90) / 180 · 127 = 84.7.
    const double expected = (30.0 + 90.0) / 180.0 * 127.0;

    SECTION("on")
    {
        setOwnStateVst3(h, twoArmState(0, true, port, mapping));
        int value = -1;
        const auto deadline = juce::Time::getMillisecondCounter() + 10000;
        while (std::abs(value - expected) > 1.0 && juce::Time::getMillisecondCounter() < deadline) value = lastCc20(kLeftRaised, 10);
        CHECK(std::abs(value - expected) <= 1.0);
    }
    SECTION("off")
    {
        setOwnStateVst3(h, twoArmState(0, false, port, mapping));
        CHECK(lastCc20(kLeftRaised, 200) == -1);   // 1 s of the sender: the left arm sends nothing
    }
    h.plugin->releaseResources();
}

TEST_CASE("VST3: processBlock allocates nothing with two arms", "[plugin][two-arms]")
{
    using armadillo::test::RealtimeGuard;
    ARMADILLO_REQUIRE_GUARD();
    {
        RealtimeGuard guard;   // the probe: an allocation on this thread is seen
        auto probe = std::make_unique<std::vector<double>>(16);
        REQUIRE(guard.allocations() >= 2);
    }
    const int port = freeUdpPort();
    armadillo::osc::OscSender sender(armadillo::osc::HostPort {"127.0.0.1", port});
    auto h = loadVst3();
    prepare(h);
    setValue(h, "Elevation", 20.0f, -90.0f, 90.0f);
    setOwnStateVst3(h, twoArmState(kDuo, true, port, R"({"version": 1, "mappings": [
        {"source": "left.elevation", "to": {"midi": "cc", "channel": 1, "cc": 20}},
        {"source": "arms.angle", "in": [0, 180], "to": {"midi": "cc", "channel": 1, "cc": 21}}]})"));
    // The left arm is live (its hanging silenced the duo) before anything is counted.
    REQUIRE(renderUntil(h, sender, kLeftHanging, [](double rms) { return rms < 1e-4; }) < 1e-4);
    render(h, 0.1);
    countDuringProcessing(h, 50, true);   // the host's buffers and queues sized
    BlockCounts total {};
    for (int round = 0; round < 10; ++round) {
        // The sender moves the left arm between batches: the blocks fuse it and play both arms.
        const double elevation = round % 2 == 0 ? 30.0 : -85.0;
        for (int i = 0; i < 5; ++i) sender.sendOrientation(armadillo::core::poseToQuaternion(armadillo::core::Pose {elevation, 10.0 * i, 0.0}));
        const BlockCounts c = countDuringProcessing(h, 20, true);
        total.blocks += c.blocks;
        total.allocations += c.allocations;
        total.deallocations += c.deallocations;
        total.throws += c.throws;
    }
    INFO(total.blocks << " blocks");
    CHECK(total.blocks == 200);
    CHECK(total.allocations == 0);
    CHECK(total.deallocations == 0);
    CHECK(total.throws == 0);
    h.plugin->releaseResources();
}
