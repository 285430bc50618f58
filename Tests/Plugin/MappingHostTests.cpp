// The mapping matrix in the plugin (issue 23), hosted as a DAW hosts it (the built VST3 and LV2
// through JUCE's hosting classes): the MIDI out follows the mapping at the sample offset of the
// control step that produced it, the macro parameters reach the host as automation, the state
// round-trips the mapping set, and processBlock stays allocation-free with 64 mappings.
//
// Expected values come from the definitions, computed here independently of the plugin:
//  - IEM SceneRotator's MrHeadTracker MIDI scheme (IEM Plug-in Suite, SceneRotator
//    PluginProcessor.cpp, handleIncomingMidiMessage / processBlock's MIDI loop): yaw, pitch and
//    roll on CC 16/48, 17/49, 18/50 (MSB/LSB), LSB sent first, angle = (128·MSB + LSB)/16384
//    over −180…180°; the arm's yaw/pitch/roll as docs/MAPPING.md defines them (yaw = −(azimuth −
//    forward) wrapped to ±180°, pitch = elevation, roll = roll).
//  - The plugin's control grid (docs/PLUGIN.md "Threads"): one control step every
//    round(48000 / 200) = 240 samples from the first sample after prepareToPlay.
#include <catch2/catch.hpp>

#include "Common/RealtimeGuard.h"
#include "Osc/Osc.h"
#include "Plugin/HostedPlugin.h"
#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace armadillo::test::host;

namespace {

constexpr int kStepSamples = 240;   // 48 kHz / 200 Hz

/// One MIDI event the plugin put out, at its absolute sample since prepareToPlay.
struct Event {
    std::int64_t sample = 0;
    int order = 0;                  ///< position in its block's buffer
    std::vector<std::uint8_t> bytes;
};

/// Renders `blocks` blocks, appending the plugin's MIDI out with absolute sample positions.
/// `clock` counts the samples rendered since prepareToPlay (the caller keeps it).
void renderCollect(Hosted& h, int blocks, std::int64_t& clock, std::vector<Event>& out)
{
    juce::AudioBuffer<float> buffer(2, kBlock);
    juce::MidiBuffer midi;
    for (int b = 0; b < blocks; ++b) {
        buffer.clear();
        midi.clear();
        h.plugin->processBlock(buffer, midi);
        int order = 0;
        for (const auto m : midi)
            out.push_back(Event {clock + m.samplePosition, order++, std::vector<std::uint8_t>(m.data, m.data + m.numBytes)});
        clock += kBlock;
        juce::MessageManager::getInstance()->runDispatchLoopUntil(1);
    }
}

/// The plugin's chunk inside an LV2 state (Turtle) from JUCE's LV2 host: the string literal of
/// the plugin's "StateString" property, which JUCE's LV2 client stores as base64 of its
/// getStateInformation (juce_LV2_Client.cpp, store()).
juce::String ownStateLv2Payload(const juce::String& ttl)
{
    const int key = ttl.indexOf("StateString");
    if (key < 0) return {};
    const int open = ttl.indexOfChar(key, '"');
    const int close = open < 0 ? -1 : ttl.indexOfChar(open + 1, '"');
    return close > open ? ttl.substring(open + 1, close) : juce::String();
}

/// The plugin's own state document given to the plugin through the host, as a DAW restores a
/// session: VST3 wraps it in JUCE's VST3PluginState; LV2 puts it where the plugin's saved state
/// string sits in a state the host got from the plugin.
void setOwnState(Hosted& h, const juce::String& xml)
{
    auto own = juce::parseXML(xml);
    REQUIRE(own != nullptr);
    juce::MemoryBlock payload;
    juce::AudioProcessor::copyXmlToBinary(*own, payload);
    if (! h.lv2) {
        juce::XmlElement state("VST3PluginState");
        state.createNewChildElement("IComponent")->addTextElement(payload.toBase64Encoding());
        juce::MemoryBlock blob;
        juce::AudioProcessor::copyXmlToBinary(state, blob);
        h.plugin->setStateInformation(blob.getData(), static_cast<int>(blob.getSize()));
        return;
    }
    // JUCE's LV2 client keeps the plugin's chunk as one base64 string literal in the state's
    // Turtle (juce_LV2_Client.cpp, the state property written by its save()); swap ours in.
    juce::MemoryBlock current;
    h.plugin->getStateInformation(current);
    const auto ttl = current.toString();
    const auto mine = ownStateLv2Payload(ttl);
    REQUIRE(mine.isNotEmpty());
    const auto replaced = ttl.replace(mine, payload.toBase64Encoding());
    h.plugin->setStateInformation(replaced.toRawUTF8(), static_cast<int>(replaced.getNumBytesAsUTF8()));
}

/// Mapping node of a state document: a preset by name, or a document.
juce::String stateWith(const juce::String& mappingAttributes, const juce::String& settings = {})
{
    // source 3 = host automation, scene 0 = monitor (INTERFACES.md choice orders).
    return "<ARMADILLO version=\"1\"><PARAMETERS><PARAM id=\"source\" value=\"3\"/><PARAM id=\"scene\" value=\"0\"/></PARAMETERS>"
           "<SETTINGS " + settings + "/><MAPPING " + mappingAttributes + "/></ARMADILLO>";
}

juce::String jsonAttribute(const juce::String& json)
{
    return "name=\"test\" json=\"" + json.replace("&", "&amp;").replace("\"", "&quot;").replace("<", "&lt;") + "\"";
}

double wrap180(double deg)
{
    double a = std::fmod(deg + 180.0, 360.0);
    if (a < 0.0) a += 360.0;
    return a - 180.0;
}

/// The newest value of each controller (channel 1–16, cc 0–127) and, per MSB controller, whether
/// its LSB (cc+32) came before it in the same block at the same sample.
struct CcState {
    std::map<std::pair<int, int>, int> value;
    std::map<std::pair<int, int>, bool> lsbFirst;
};

CcState ccs(const std::vector<Event>& events)
{
    CcState s;
    const Event* previous = nullptr;
    for (const auto& e : events) {
        if (e.bytes.size() == 3 && (e.bytes[0] & 0xF0) == 0xB0) {
            const int ch = (e.bytes[0] & 0x0F) + 1, cc = e.bytes[1];
            s.value[{ch, cc}] = e.bytes[2];
            if (cc < 32)
                s.lsbFirst[{ch, cc}] = previous != nullptr && previous->sample == e.sample && previous->bytes.size() == 3
                                       && previous->bytes[0] == e.bytes[0] && previous->bytes[1] == cc + 32;
        }
        previous = &e;
    }
    return s;
}

/// SceneRotator's decoding of a 14-bit pair on channel 1.
double sceneRotatorDegrees(const CcState& s, int msbCc)
{
    const auto msb = s.value.find({1, msbCc}), lsb = s.value.find({1, msbCc + 32});
    REQUIRE(msb != s.value.end());
    REQUIRE(lsb != s.value.end());
    return -180.0 + 360.0 * (128.0 * msb->second + lsb->second) / 16384.0;
}

void checkSceneRotator(Hosted& h)
{
    prepare(h);
    setOwnState(h, stateWith("name=\"scenerotator\""));
    std::int64_t clock = 0;
    std::vector<Event> events;
    renderCollect(h, 20, clock, events);   // the set and the state reach the control side
    struct P { double elevation, azimuth, roll; };
    for (const P p : {P {20.0, 30.0, -40.0}, P {-35.5, 250.25, 170.0}, P {60.0, 181.0, 5.5}, P {-5.0, 359.0, -179.0}}) {
        setValue(h, "Elevation", static_cast<float>(p.elevation), -90.0f, 90.0f);
        setValue(h, "Azimuth", static_cast<float>(p.azimuth), 0.0f, 360.0f);
        setValue(h, "Roll", static_cast<float>(p.roll), -180.0f, 180.0f);
        events.clear();
        renderCollect(h, 40, clock, events);   // 0.2 s
        // The host's parameter steps are float: compare with the values the plugin was given.
        const double elevation = valueOf(h, "Elevation", -90.0f, 90.0f), azimuth = valueOf(h, "Azimuth", 0.0f, 360.0f),
                     roll = valueOf(h, "Roll", -180.0f, 180.0f);
        const auto s = ccs(events);
        INFO("pose " << elevation << " / " << azimuth << " / " << roll << ", " << events.size() << " events");
        CHECK(sceneRotatorDegrees(s, 16) == Approx(wrap180(-azimuth)).margin(0.05));
        CHECK(sceneRotatorDegrees(s, 17) == Approx(elevation).margin(0.05));
        CHECK(sceneRotatorDegrees(s, 18) == Approx(roll).margin(0.05));
        for (int cc : {16, 17, 18}) {
            INFO("CC " << cc);
            CHECK(s.lsbFirst.at({1, cc}));
        }
        // Only what the set names: CC pairs on channel 1, nothing else (no classic CC 16-18 7-bit
        // stream on other channels, no notes).
        for (const auto& e : events) {
            REQUIRE(e.bytes.size() == 3);
            CHECK(e.bytes[0] == 0xB0);
            CHECK(std::set<int> {16, 17, 18, 48, 49, 50}.count(e.bytes[1]) == 1);
        }
    }
    h.plugin->releaseResources();
}

} // namespace

TEST_CASE("VST3: the scenerotator mapping's CC pairs decode to the pose by SceneRotator's arithmetic")
{
    auto h = loadVst3();
    checkSceneRotator(h);
}

TEST_CASE("LV2: the scenerotator mapping's CC pairs decode to the pose by SceneRotator's arithmetic")
{
    auto h = loadLv2();
    checkSceneRotator(h);
}

TEST_CASE("VST3: mapped MIDI sits at the sample offset of the control step that produced it")
{
    auto h = loadVst3();
    prepare(h);
    setOwnState(h, stateWith(jsonAttribute(R"({"version": 1, "mappings": [
        {"source": "elevation", "in": [-90, 90], "to": {"midi": "cc", "channel": 2, "cc": 20}}]})")));
    std::int64_t clock = 0;
    std::vector<Event> events;
    renderCollect(h, 10, clock, events);
    int checked = 0;
    for (int i = 0; i < 30; ++i) {
        // A host sets automation between blocks; the plugin's first step in the block reads it.
        setValue(h, "Elevation", static_cast<float>(-60.0 + 4.0 * i), -90.0f, 90.0f);
        const std::int64_t blockStart = clock;
        events.clear();
        renderCollect(h, 1, clock, events);
        const std::int64_t firstStep = (blockStart + kStepSamples - 1) / kStepSamples * kStepSamples;
        INFO("block at " << blockStart << ": " << events.size() << " events");
        REQUIRE(events.size() == 1);   // one step saw the change; a 7-bit CC per 1.4 degrees
        CHECK(events[0].sample == firstStep);
        CHECK(events[0].bytes[0] == 0xB1);
        CHECK(events[0].bytes[1] == 20);
        CHECK(int(events[0].bytes[2]) == int(std::lround((-60.0 + 4.0 * i + 90.0) / 180.0 * 127.0)));
        ++checked;
    }
    CHECK(checked == 30);
}

TEST_CASE("VST3: without a saved mapping the classic wiring plays on the saved MIDI channel")
{
    // A session from before the mapping: no MAPPING node, midiChannel 5. The classic preset
    // sends elevation on CC 16 (0 = -90 deg, 127 = +90 deg) on that channel (docs/PLUGIN.md).
    auto h = loadVst3();
    prepare(h);
    setOwnState(h, "<ARMADILLO version=\"1\"><PARAMETERS><PARAM id=\"source\" value=\"3\"/><PARAM id=\"scene\" value=\"0\"/>"
                   "</PARAMETERS><SETTINGS midiChannel=\"5\"/></ARMADILLO>");
    std::int64_t clock = 0;
    std::vector<Event> events;
    renderCollect(h, 10, clock, events);
    setValue(h, "Elevation", 45.0f, -90.0f, 90.0f);
    events.clear();
    renderCollect(h, 10, clock, events);
    const auto s = ccs(events);
    REQUIRE(s.value.count({5, 16}) == 1);
    CHECK(s.value.at({5, 16}) == std::lround(135.0 / 180.0 * 127.0));
    auto own = ownState(h);
    REQUIRE(own->getChildByName("MAPPING") != nullptr);
    CHECK(own->getChildByName("MAPPING")->getStringAttribute("name") == "classic");
}

TEST_CASE("VST3: a damaged saved mapping is refused by name and the classic wiring runs")
{
    auto h = loadVst3();
    prepare(h);
    setOwnState(h, stateWith(jsonAttribute(R"({"version": 1, "mappings": [{"source": "elbow", "to": {"midi": "cc", "cc": 1}}]})")));
    auto own = ownState(h);
    REQUIRE(own->getChildByName("MAPPING") != nullptr);
    CHECK(own->getChildByName("MAPPING")->getStringAttribute("name") == "classic");
    std::int64_t clock = 0;
    std::vector<Event> events;
    renderCollect(h, 5, clock, events);
    setValue(h, "Elevation", -30.0f, -90.0f, 90.0f);
    renderCollect(h, 10, clock, events);
    CHECK(ccs(events).value.count({1, 16}) == 1);
}

TEST_CASE("VST3: the macro parameters reach the host as automation with change gestures")
{
    auto h = loadVst3();
    prepare(h);
    for (int i = 1; i <= 8; ++i) {
        auto* p = h.param("Macro " + juce::String(i));
        INFO("Macro " << i);
        REQUIRE(p != nullptr);
        CHECK(p->isAutomatable());
    }
    struct Recorder : juce::AudioProcessorParameter::Listener {
        std::atomic<int> changes {0}, begins {0}, ends {0};
        std::atomic<float> last {-1.0f};
        void parameterValueChanged(int, float v) override
        {
            ++changes;
            last = v;
        }
        void parameterGestureChanged(int, bool starting) override { (starting ? begins : ends) += 1; }
    } recorder;
    auto* macro = h.param("Macro 3");
    // Listening before the set comes: the first write (and its gesture's begin) may come from
    // the idle clock while the state loads, before any block (a slow host, a sanitizer build).
    macro->addListener(&recorder);
    setOwnState(h, stateWith(jsonAttribute(R"({"version": 1, "mappings": [
        {"source": "elevation", "in": [-90, 90], "to": {"macro": 3}}]})")));
    for (const float elevation : {45.0f, -45.0f}) {
        setValue(h, "Elevation", elevation, -90.0f, 90.0f);
        const float expected = (elevation + 90.0f) / 180.0f;
        // Event-driven: pump until the host saw the value (or 10 s pass).
        const auto deadline = juce::Time::getMillisecondCounter() + 10000;
        std::int64_t clock = 0;
        std::vector<Event> events;
        while (std::abs(recorder.last - expected) > 0.002f && juce::Time::getMillisecondCounter() < deadline) {
            renderCollect(h, 2, clock, events);
            juce::MessageManager::getInstance()->runDispatchLoopUntil(5);
        }
        INFO("elevation " << elevation << ": host saw " << recorder.last.load());
        CHECK(recorder.last == Approx(expected).margin(0.002));
        CHECK(macro->getValue() == Approx(expected).margin(0.002));
    }
    // The gesture closes once the value stops changing (docs/PLUGIN.md "Macro parameters").
    const auto deadline = juce::Time::getMillisecondCounter() + 5000;
    std::int64_t clock = 0;
    std::vector<Event> events;
    while (recorder.ends < 1 && juce::Time::getMillisecondCounter() < deadline) {
        renderCollect(h, 2, clock, events);
        juce::MessageManager::getInstance()->runDispatchLoopUntil(5);
    }
    macro->removeListener(&recorder);
    CHECK(recorder.begins >= 1);
    CHECK(recorder.ends >= 1);
    CHECK(recorder.changes >= 2);
    // The other macros stay untouched.
    CHECK(h.param("Macro 1")->getValue() == 0.0f);
}

TEST_CASE("VST3: the state round-trips the mapping set")
{
    const juce::String json = R"({"version": 1, "name": "round trip", "mappings": [
        {"source": "elevation", "in": [-45, 45], "to": {"midi": "cc14", "channel": 3, "cc": 7}},
        {"source": "roll", "in": [-90, 90], "curve": "linear", "to": {"midi": "pitchbend", "channel": 2}},
        {"source": "azimuth", "to": {"midi": "notes", "channel": 4, "velocity": 100,
           "zones": [[0, 90, 60], [90, 180, 62], [180, 270, 64], [270, 360, 65]]}},
        {"source": "elevation", "in": [-90, 90], "out": [0, 1], "to": {"osc": "/synth/cutoff"}}]})";
    juce::String savedName, savedJson;
    juce::MemoryBlock saved;
    {
        auto h = loadVst3();
        prepare(h);
        setOwnState(h, stateWith(jsonAttribute(json)));
        render(h, 0.05);
        h.plugin->getStateInformation(saved);
        auto own = ownState(h);
        REQUIRE(own->getChildByName("MAPPING") != nullptr);
        savedName = own->getChildByName("MAPPING")->getStringAttribute("name");
        savedJson = own->getChildByName("MAPPING")->getStringAttribute("json");
        CHECK(savedName == "test");
        CHECK(savedJson.contains("cc14"));
        CHECK(savedJson.contains("/synth/cutoff"));
    }
    auto h = loadVst3();
    prepare(h);
    h.plugin->setStateInformation(saved.getData(), static_cast<int>(saved.getSize()));
    auto own = ownState(h);
    REQUIRE(own->getChildByName("MAPPING") != nullptr);
    CHECK(own->getChildByName("MAPPING")->getStringAttribute("name") == savedName);
    CHECK(own->getChildByName("MAPPING")->getStringAttribute("json") == savedJson);
    // And it plays the restored set: elevation 22.5 is 3/4 of [-45, 45] on CC 7/39 (MSB/LSB), channel 3.
    std::int64_t clock = 0;
    std::vector<Event> events;
    setValue(h, "Elevation", 22.5f, -90.0f, 90.0f);
    renderCollect(h, 10, clock, events);
    const auto s = ccs(events);
    REQUIRE(s.value.count({3, 7}) == 1);
    REQUIRE(s.value.count({3, 39}) == 1);
    const double elevation = valueOf(h, "Elevation", -90.0f, 90.0f);
    const long expected = std::clamp(std::lround((elevation + 45.0) / 90.0 * 16383.0), 0L, 16383L);
    CHECK(std::abs(128L * s.value.at({3, 7}) + s.value.at({3, 39}) - expected) <= 1);
}

TEST_CASE("VST3: processBlock allocates nothing with 64 mappings, automated")
{
    using armadillo::test::RealtimeGuard;
    ARMADILLO_REQUIRE_GUARD();
    {
        // The probe: an allocation on this thread is seen.
        RealtimeGuard guard;
        auto probe = std::make_unique<std::vector<double>>(16);
        REQUIRE(guard.allocations() >= 2);
    }
    // 64 mappings of every destination kind the plugin delivers on the control side: 14-bit CC,
    // 7-bit CC, pitch bend, NRPN, pressure, zone notes, gesture notes, program changes, OSC to the
    // default target (127.0.0.1), macros.
    std::ostringstream json;
    json << R"({"version": 1, "mappings": [)";
    const char* sources[] {"elevation", "azimuth", "roll", "yaw", "speed", "qw", "qx", "fluxFace"};
    for (int i = 0; i < 64; ++i) {
        const char* src = sources[i % 8];
        if (i > 0) json << ",";
        json << R"({"source": ")" << src << R"(", "to": )";
        switch (i % 10) {
        case 0: json << R"({"midi": "cc14", "channel": 1, "cc": )" << (i % 32) << "}"; break;
        case 1: json << R"({"midi": "cc", "channel": 2, "cc": )" << (i % 120) << "}"; break;
        case 2: json << R"({"midi": "pitchbend", "channel": )" << (1 + i % 16) << "}"; break;
        case 3: json << R"({"midi": "nrpn", "channel": 3, "number": )" << (i * 100) << "}"; break;
        case 4: json << R"({"midi": "pressure", "channel": 4})"; break;
        case 5:
            json << R"({"midi": "notes", "channel": 5, "velocity": 90, "zones": [[0, 90, 60], [90, 180, 62], [180, 270, 64], [270, 360, 65]]})";
            break;
        case 6: json << R"({"midi": "cc", "channel": 6, "cc": 1})"; break;
        case 7: json << R"({"osc": "/armadillo-test/)" << i << R"("})"; break;
        case 8: json << R"({"macro": )" << (1 + i % 8) << "}"; break;
        default: json << R"({"midi": "cc14", "channel": 7, "cc": 2, "lsbFirst": true})"; break;
        }
        json << "}";
    }
    json << "]}";
    auto h = loadVst3();
    prepare(h);
    setOwnState(h, stateWith(jsonAttribute(juce::String(json.str()))));
    for (int i = 0; i < 5; ++i) juce::MessageManager::getInstance()->runDispatchLoopUntil(5);
    auto own = ownState(h);
    REQUIRE(own->getChildByName("MAPPING") != nullptr);
    REQUIRE(own->getChildByName("MAPPING")->getStringAttribute("name") == "test");   // taken, not refused
    render(h, 0.2);                          // the set swaps in; the host sizes its buffers
    countDuringProcessing(h, 100, true);     // and its parameter queues and event lists
    const BlockCounts c = countDuringProcessing(h, 400, true);
    INFO(c.blocks << " blocks, " << c.midiEvents << " MIDI events out, " << c.locks << " locks");
    CHECK(c.midiEvents > 400);               // the mappings did play
    CHECK(c.allocations == 0);
    CHECK(c.deallocations == 0);
    CHECK(c.throws == 0);

    // Swapping sets while it plays: each new set is compiled on the message thread and taken
    // by pointer in the next control step, the old one freed back on the message thread.
    for (int swap = 0; swap < 3; ++swap) {
        INFO("swap " << swap);
        setOwnState(h, stateWith(swap % 2 == 0 ? juce::String("name=\"scenerotator\"") : jsonAttribute(juce::String(json.str()))));
        const BlockCounts s = countDuringProcessing(h, 50, true);
        CHECK(s.allocations == 0);
        CHECK(s.deallocations == 0);
        CHECK(s.throws == 0);
    }
}

TEST_CASE("VST3: the mapping's OSC destinations leave from the control clock to the OSC out target")
{
    // A loopback receiver on a free port is the OSC out target (settings oscOutHost/oscOutPort);
    // the frame stream stays off (oscOutEnabled 0): only the mapping sends.
    juce::DatagramSocket receiver;
    REQUIRE(receiver.bindToPort(0, "127.0.0.1"));
    const int port = receiver.getBoundPort();
    REQUIRE(port > 0);
    auto h = loadVst3();
    prepare(h);
    setOwnState(h, stateWith(jsonAttribute(R"({"version": 1, "mappings": [
        {"source": "elevation", "in": [-90, 90], "out": [0, 1], "to": {"osc": "/synth/cutoff"}}]})"),
                             "oscOutEnabled=\"0\" oscOutHost=\"127.0.0.1\" oscOutPort=\"" + juce::String(port) + "\""));
    setValue(h, "Elevation", 36.0f, -90.0f, 90.0f);
    const double expected = (valueOf(h, "Elevation", -90.0f, 90.0f) + 90.0) / 180.0;
    // Event-driven: render and pump until a datagram with the expected value arrives (or 10 s).
    double got = -1.0;
    std::string address;
    const auto deadline = juce::Time::getMillisecondCounter() + 10000;
    std::int64_t clock = 0;
    std::vector<Event> events;
    while (std::abs(got - expected) > 1e-4 && juce::Time::getMillisecondCounter() < deadline) {
        renderCollect(h, 2, clock, events);
        if (receiver.waitUntilReady(true, 5) != 1) continue;
        std::uint8_t bytes[512];
        const int n = receiver.read(bytes, sizeof bytes, false);
        if (n <= 0) continue;
        armadillo::osc::decodeOscPacket(bytes, static_cast<std::size_t>(n), [&](const armadillo::osc::OscMessage& m) {
            address = std::string(m.address);
            double v = 0.0;
            if (m.count == 1 && m.args[0].asNumber(v)) got = v;
        });
    }
    CHECK(address == "/synth/cutoff");
    CHECK(got == Approx(expected).margin(1e-4));
}

TEST_CASE("VST3: a scene-parameter destination plays the running scene's parameter")
{
    // roll → theremin.base (Hz at the bottom elevation; Instruments/Theremin.h), in its own unit:
    // roll 90° of [-180, 180] → 110 + 0.75 × 220 = 275 Hz. The theremin's pitch map (thesis §3.5)
    // then scales by 275/220 against the default base; the host's own parameter stays 220 Hz.
    auto h = loadVst3();
    prepare(h);
    setOwnState(h, "<ARMADILLO version=\"1\"><PARAMETERS><PARAM id=\"source\" value=\"3\"/><PARAM id=\"scene\" value=\"1\"/>"
                   "</PARAMETERS><MAPPING name=\"test\" json=\""
                   + juce::String(R"({"version": 1, "mappings": [{"source": "roll", "in": [-180, 180], "out": [110, 330],
                        "to": {"param": "theremin.base"}}]})").replace("\"", "&quot;")
                   + "\"/></ARMADILLO>");
    setValue(h, "Azimuth", 0.0f, 0.0f, 360.0f);
    setValue(h, "Roll", 90.0f, -180.0f, 180.0f);
    setValue(h, "Elevation", -20.0f, -90.0f, 90.0f);
    render(h, 0.3);   // the theremin swaps in, the mapping sets its base
    const auto audio = render(h, 0.35);
    const double roll = valueOf(h, "Roll", -180.0f, 180.0f), elevation = valueOf(h, "Elevation", -90.0f, 90.0f);
    const double base = 110.0 + (roll + 180.0) / 360.0 * 220.0;
    const double hz = frequency(audio, static_cast<std::size_t>(0.12 * kRate));
    INFO("roll " << roll << " -> base " << base << " Hz; measured " << hz << " Hz");
    CHECK(hz == Approx(expectedThereminHz(elevation) * base / 220.0).epsilon(0.01));
    auto* hostBase = h.param("theremin: Base frequency");
    REQUIRE(hostBase != nullptr);
    CHECK(hostBase->getCurrentValueAsText().getDoubleValue() == Approx(220.0).margin(0.5));
}
