// One mapping update's output through the one delivery every clock uses (MappingDelivery.h):
// the order the sinks hear it in, what each sink refused counted apart, the update's own
// overflow, scene parameters found by the set's id in the running scene's list (clamped to the
// range, a choice rounded), and the output cleared for the next update.
#include "Live/Outputs/MappingDelivery.h"
#include <catch2/catch.hpp>
#include <cstring>
#include <string>
#include <vector>

using namespace armadillo;

namespace {

class RecordingScene final : public core::Scene {
public:
    std::string_view name() const override { return "recording"; }
    void prepare(const core::SceneConfig&) override {}
    void control(const core::ControlInput&, core::SceneOutput&) override {}
    void setParameter(int index, float value) noexcept override { set.push_back({index, value}); }
    std::vector<std::pair<int, float>> set;
};

class RecordingSinks final : public live::MappingSinks {
public:
    std::vector<std::string> heard;
    int oscCalls = 0, mqttCalls = 0;
    bool midi(const mapping::MidiEvent& e) noexcept override
    {
        heard.push_back("midi " + std::to_string(e.bytes[0]));
        return true;
    }
    bool osc(const mapping::OscPacket& p) noexcept override
    {
        heard.push_back("osc " + std::to_string(p.target));
        return ++oscCalls != 1;   // the first one is refused
    }
    bool mqtt(const mapping::MqttMessage& m) noexcept override
    {
        heard.push_back("mqtt " + std::string(m.topic.data(), m.topicLength));
        return ++mqttCalls != 2;   // the second one is refused
    }
    void stage(const mapping::StageEvent& e) noexcept override { heard.push_back("stage " + std::to_string(e.mapping)); }
    void macro(int index, float value01) noexcept override { heard.push_back("macro " + std::to_string(index) + " " + std::to_string(value01)); }
};

mapping::MqttMessage message(const char* topic)
{
    mapping::MqttMessage m;
    m.topicLength = static_cast<std::uint16_t>(std::strlen(topic));
    std::memcpy(m.topic.data(), topic, m.topicLength);
    return m;
}

} // namespace

TEST_CASE("deliverMapping: the order, each sink's refusals counted apart, scene parameters by id, the output cleared", "[live][mapping]")
{
    mapping::MappingOutput out;
    out.stage[0].mapping = 4;
    out.stage[1].mapping = 7;
    out.stageCount = 2;
    out.midi[0] = {0.0, 3, {0x90, 60, 100}};
    out.midi[1] = {0.0, 0, {0xB0, 1, 2}};   // malformed: no bytes
    out.midi[2] = {0.0, 2, {0xC0, 5, 0}};
    out.midiCount = 3;
    out.osc[0].target = 1;
    out.osc[1].target = 2;
    out.oscCount = 2;
    out.mqtt[0] = message("arm/pitch");
    out.mqtt[1] = message("arm/roll");
    out.mqttCount = 2;
    out.macro[0] = 0.25f;
    out.macro[3] = 1.0f;
    out.macroChanged = (1u << 0) | (1u << 3);
    out.params[0] = {1, 0.5f, true};     // "depth": half its range
    out.params[1] = {0, 9.0f, false};    // "mode": above its last choice → the last, rounded
    out.params[2] = {2, 0.5f, true};     // an id this scene lacks: not applied
    out.params[3] = {7, 0.5f, true};     // an index past the set's list: not applied
    out.paramCount = 4;
    out.dropped = 5;

    const std::vector<std::string> setIds {"mode", "depth", "elsewhere"};
    const std::vector<core::ParamSpec> specs {{"depth", "Depth", -12.0f, 12.0f, 0.0f, "st", {}}, {"mode", "Mode", 0.0f, 2.0f, 0.0f, "", {"a", "b", "c"}}};
    RecordingScene scene;
    RecordingSinks sinks;
    live::MappingTally tally;
    live::deliverMapping(out, sinks, {&scene, &setIds, &specs}, tally);

    CHECK(sinks.heard == std::vector<std::string> {"stage 4", "stage 7", "midi 144", "midi 192", "osc 1", "osc 2", "mqtt arm/pitch", "mqtt arm/roll",
                                                   "macro 0 0.250000", "macro 3 1.000000"});
    REQUIRE(scene.set.size() == 2);
    CHECK(scene.set[0] == std::pair<int, float> {0, 0.0f});   // depth is the scene's parameter 0: half of −12…12
    CHECK(scene.set[1] == std::pair<int, float> {1, 2.0f});   // mode, parameter 1: clamped to its last choice
    CHECK(tally.stage == 2);
    CHECK(tally.midi == 2);
    CHECK(tally.midiDropped == 1);
    CHECK(tally.osc == 1);
    CHECK(tally.oscDropped == 1);
    CHECK(tally.mqtt == 2);
    CHECK(tally.mqttDropped == 1);
    CHECK(tally.params == 2);
    CHECK(tally.overflow == 5);
    CHECK(out.midiCount == 0);
    CHECK(out.oscCount == 0);
    CHECK(out.mqttCount == 0);
    CHECK(out.stageCount == 0);
    CHECK(out.paramCount == 0);
    CHECK(out.macroChanged == 0u);
    CHECK(out.dropped == 0u);

    // Without a scene target (the end of a render, a panic) nothing reaches a scene.
    out.params[0] = {1, 0.5f, true};
    out.paramCount = 1;
    live::deliverMapping(out, sinks, {}, tally);
    CHECK(scene.set.size() == 2);
    CHECK(tally.params == 2);
}
