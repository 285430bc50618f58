// The MQTT destination (issue 35, docs/MQTT.md): the file format and its errors, the payload
// template, sending on change, zones and thresholds, real-time formatting; and the Home Assistant
// preset's payloads against Home Assistant's documented MQTT schemas:
//  - MQTT Light, JSON schema (https://www.home-assistant.io/integrations/light.mqtt/#json-schema):
//    the command topic takes a JSON object whose "state" is "ON" or "OFF" and whose optional
//    "brightness" is a whole number from 0 to brightness_scale (default 255); other documented
//    keys are color_temp, color, effect, flash, transition, white, color_mode;
//  - MQTT Switch (https://www.home-assistant.io/integrations/switch.mqtt/): the command topic takes
//    payload_on / payload_off, by default "ON" and "OFF".
// The checks below are written from those pages, not from the code under test.
#include "Common/RealtimeGuard.h"
#include "Core/Json.h"
#include "Mapping/MappingHelpers.h"
#include <catch2/catch.hpp>
#include <algorithm>
#include <limits>
#include <map>
#include <set>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::mapping;
using namespace armadillo::mapping::test;

namespace {

/// Home Assistant's MQTT light JSON schema, command side: "" when `payload` conforms, else why.
std::string haJsonLightProblem(const std::string& payload, int brightnessScale = 255)
{
    armadillo::core::JsonValue v;
    try {
        v = armadillo::core::parseJson(payload, "payload");
    } catch (const std::exception& e) {
        return std::string("not JSON: ") + e.what();
    }
    if (v.kind != armadillo::core::JsonValue::Kind::Object) return "not a JSON object";
    static const std::set<std::string> documented {"state", "brightness", "color_temp", "color", "effect", "flash", "transition", "white", "color_mode"};
    for (const auto& [k, x] : v.object)
        if (!documented.count(k)) return "undocumented key " + k;
    const armadillo::core::JsonValue* state = v.find("state");
    if (!state || state->kind != armadillo::core::JsonValue::Kind::String || (state->string != "ON" && state->string != "OFF"))
        return "\"state\" must be \"ON\" or \"OFF\"";
    if (const armadillo::core::JsonValue* b = v.find("brightness")) {
        if (b->kind != armadillo::core::JsonValue::Kind::Number || b->number != std::floor(b->number)) return "\"brightness\" must be a whole number";
        if (b->number < 0 || b->number > brightnessScale) return "\"brightness\" outside 0…" + std::to_string(brightnessScale);
    }
    return {};
}

} // namespace

TEST_CASE("MQTT destinations: the file format and its errors", "[mapping][mqtt]")
{
    const MappingDocument doc = parseMappingDocument(
        R"({"version": 1, "mappings": [{"source": "elevation", "in": [-90, 90], "out": [0, 100],
            "to": {"mqtt": {"topic": "home/lamp/set", "payload": "{\"brightness\": {value}}", "qos": 1, "retain": true, "rate": 4}}}]})",
        "m.json");
    REQUIRE(doc.mappings.size() == 1);
    const DestinationSpec& d = doc.mappings[0].to;
    CHECK(d.kind == DestinationKind::Mqtt);
    CHECK(d.address == "home/lamp/set");
    CHECK(d.payload == "{\"brightness\": {value}}");
    CHECK(d.qos == 1);
    CHECK(d.retain);
    CHECK(d.rate == 4.0);
    // It survives a round trip through the writer.
    const MappingDocument again = parseMappingDocument(toJson(doc), "again.json");
    CHECK(again.mappings[0].to.payload == d.payload);
    CHECK(again.mappings[0].to.rate == 4.0);
    CHECK(again.mappings[0].to.retain);

    const auto bad = [](const std::string& to) {
        return parseMessage(R"({"version": 1, "mappings": [{"source": "elevation", "to": )" + to + "}]}");
    };
    CHECK_THAT(bad(R"({"mqtt": {"payload": "x"}})"), Catch::Contains("needs \"topic\""));
    CHECK_THAT(bad(R"({"mqtt": {"topic": "a/+/b"}})"), Catch::Contains("no wildcards"));
    CHECK_THAT(bad(R"({"mqtt": {"topic": "a", "payload": "{valu}"}})"), Catch::Contains("unknown placeholder {valu}"));
    CHECK_THAT(bad(R"({"mqtt": {"topic": "a", "qos": 3}})"), Catch::Contains("qos"));
    CHECK_THAT(bad(R"({"mqtt": {"topic": "a", "rate": -1}})"), Catch::Contains("rate"));
    CHECK_THAT(bad(R"({"mqtt": {"topic": "a", "retain": 1}})"), Catch::Contains("retain"));
    CHECK_THAT(bad(R"({"mqtt": {"topic": "a", "colour": 1}})"), Catch::Contains("colour"));
    CHECK_THAT(bad(R"({"mqtt": {"topic": "a"}, "osc": "/x"})"), Catch::Contains("exactly one"));
    CHECK_THAT(bad(R"({"mqtt": "a"})"), Catch::Contains("bad.json"));
}

TEST_CASE("MQTT destinations: the payload follows the value, sent when it changes; zones and thresholds", "[mapping][mqtt]")
{
    Rig rig(R"({"version": 1, "mappings": [
        {"source": "elevation", "in": [-90, 90], "out": [0, 255],
         "to": {"mqtt": {"topic": "arm/{arm}/level", "payload": "{\"brightness\": {round}, \"raw\": {value}}"}}},
        {"source": "roll", "threshold": 45, "to": {"mqtt": {"topic": "arm/switch", "payload": "{state} {on}"}}},
        {"source": "azimuth", "zones": [[0, 90, 1], [90, 180, 2]], "to": {"mqtt": {"topic": "arm/zone/{zone}", "payload": "{zone} {on}"}}}]})");
    rig.pose(0, 45, 0, 0.0);
    rig.pose(0, 45, 0, 0.005);    // nothing changed: nothing sent
    rig.pose(90, 135, 60, 0.010);
    rig.pose(90, 135, 0, 0.015);
    std::vector<std::pair<std::string, std::string>> expected {
        {"arm/0/level", "{\"brightness\": 128, \"raw\": 127.5}"},
        {"arm/zone/1", "1 1"},
        {"arm/0/level", "{\"brightness\": 255, \"raw\": 255}"},
        {"arm/switch", "ON 1"},
        {"arm/zone/1", "1 0"},   // zone 1 left (as OSC's $on), zone 2 entered
        {"arm/zone/2", "2 1"},
        {"arm/switch", "OFF 0"},
    };
    // Order within one update follows the mappings; compare as sets per update.
    std::multiset<std::pair<std::string, std::string>> got(rig.mqtt.begin(), rig.mqtt.end()), want(expected.begin(), expected.end());
    std::string sent;
    for (const auto& [topic, payload] : rig.mqtt) sent += topic + " " + payload + "\n";
    INFO(sent);
    CHECK(got == want);
}

TEST_CASE("The panel's knobs, level and selection as sources: a remote (panel.knob, panel.level, panel.selected)", "[mapping][mqtt][panel]")
{
    SourceSpec s;
    for (const char* name : {"panel.knob", "panel.level", "panel.selected"}) {
        REQUIRE(parseSourceName(name, s));
        CHECK(sourceName(s) == name);
        CHECK_FALSE(isArmSource(s.kind));
    }
    CHECK_FALSE(parseSourceName("left.panel.knob", s));   // the panel is the scene's, not an arm's
    // Each knob a zone [k − 0.5, k + 0.5]: entering sends ON to its topic, leaving OFF (Home Assistant's
    // switch payloads); the selected knob's number on its own topic; the level as 1/0.
    Rig rig(R"({"version": 1, "mappings": [
        {"source": "panel.knob", "zones": [[2.5, 3.5, 3], [3.5, 4.5, 4], [4.5, 5.5, 5], [12.5, 13.5, 13]],
         "to": {"mqtt": {"topic": "panel/knob/{zone}", "payload": "{state}"}}},
        {"source": "panel.selected", "out": [0, 17], "to": {"mqtt": {"topic": "panel/selected", "payload": "{round}"}}},
        {"source": "panel.level", "out": [0, 1], "to": {"mqtt": {"topic": "panel/level", "payload": "{round}"}}}]})");
    const ArmState arm = armAt(45, 0, 0);
    const auto panel = [](float knob, float level, float selected) {
        SceneValues v;
        v.panelKnob = knob;
        v.panelLevel = level;
        v.panelSelected = selected;
        return v;
    };
    const float none = std::numeric_limits<float>::quiet_NaN();
    rig.step(arm, 0.000, nullptr, 0, SceneValues {});       // another scene: no panel values, nothing sent
    CHECK(rig.mqtt.empty());
    rig.step(arm, 0.005, nullptr, 0, panel(4, 1, none));    // knob 4 under the arm, nothing selected yet
    rig.step(arm, 0.010, nullptr, 0, panel(5, 1, none));    // dialled one knob on: 4 left at once, 5 entered
    rig.step(arm, 0.015, nullptr, 0, panel(5, 1, 5));       // a quick roll selects it
    rig.step(arm, 0.020, nullptr, 0, panel(14, 0, 5));      // down to the lower level: knob 5 + 9, no zone
    rig.step(arm, 0.025, nullptr, 0, panel(13, 0, 5));
    rig.step(arm, 0.030, nullptr, 0, panel(13, 0, 13));
    const std::vector<std::pair<std::string, std::string>> expected {
        {"panel/knob/4", "ON"},  {"panel/level", "1"},
        {"panel/knob/4", "OFF"}, {"panel/knob/5", "ON"},
        {"panel/selected", "5"},
        {"panel/knob/5", "OFF"}, {"panel/level", "0"},
        {"panel/knob/13", "ON"},
        {"panel/selected", "13"},
    };
    std::multiset<std::pair<std::string, std::string>> got(rig.mqtt.begin(), rig.mqtt.end()), want(expected.begin(), expected.end());
    std::string sent;
    for (const auto& [topic, payload] : rig.mqtt) sent += topic + " " + payload + "\n";
    INFO(sent);
    CHECK(got == want);
}

TEST_CASE("MQTT destinations format without allocating or locking", "[mapping][mqtt][realtime]")
{
    Rig rig(R"({"version": 1, "mappings": [{"source": "elevation", "in": [-90, 90], "out": [0, 1],
         "to": {"mqtt": {"topic": "arm/level", "payload": "{\"level\": {value}, \"state\": \"{state}\"}"}}}]})");
    ARMADILLO_REQUIRE_GUARD();
    std::vector<ArmState> arms;
    for (int i = 0; i < 500; ++i) arms.push_back(armAt(-90.0 + 0.36 * i, 0, 0, i * 0.005));
    MappingInput in;
    int made = 0;
    {
        armadillo::test::RealtimeGuard guard;
        for (const ArmState& a : arms) {
            in.t = a.t;
            in.arm[0] = &a;
            rig.mapper.process(in, *rig.out);
            made += rig.out->mqttCount;
            rig.out->clear();
        }
        CHECK(guard.allocations() == 0);
        CHECK(guard.locks() == 0);
    }
    CHECK(made >= 400);   // the probe: messages were really made under the guard
}

TEST_CASE("The Home Assistant preset's payloads follow Home Assistant's MQTT light (JSON schema) and switch", "[mapping][mqtt][presets]")
{
    // The checker itself first: it refuses what the schema refuses.
    CHECK(haJsonLightProblem(R"({"state": "ON", "brightness": 255})").empty());
    CHECK_FALSE(haJsonLightProblem(R"({"state": "on"})").empty());
    CHECK_FALSE(haJsonLightProblem(R"({"brightness": 10})").empty());
    CHECK_FALSE(haJsonLightProblem(R"({"state": "ON", "brightness": 256})").empty());
    CHECK_FALSE(haJsonLightProblem(R"({"state": "ON", "brightness": 12.5})").empty());
    CHECK_FALSE(haJsonLightProblem(R"({"state": "ON", "level": 3})").empty());

    const auto names = presetNames();
    REQUIRE(std::find(names.begin(), names.end(), "homeassistant") != names.end());
    Rig rig(loadMapping("homeassistant"));
    // A sweep through every elevation and roll, and the arm hanging down.
    double t = 0.0;
    for (double el = -90; el <= 90; el += 1.5)
        for (double roll : {-90.0, 0.0, 70.0}) rig.pose(el, 0, roll, t += 0.005);
    for (double el = 90; el >= -90; el -= 3) rig.pose(el, 0, 0, t += 0.005);
    int light = 0, switches = 0, on = 0, off = 0;
    std::set<int> brightness;
    for (const auto& [topic, payload] : rig.mqtt) {
        INFO(topic << ": " << payload);
        if (topic == "armadillo/light/set") {
            ++light;
            CHECK(haJsonLightProblem(payload).empty());
            const armadillo::core::JsonValue v = armadillo::core::parseJson(payload, "p");
            if (const armadillo::core::JsonValue* b = v.find("brightness")) brightness.insert(static_cast<int>(b->number));
            (v.find("state")->string == "ON" ? on : off)++;
        } else if (topic == "armadillo/switch/set") {
            ++switches;
            CHECK((payload == "ON" || payload == "OFF"));
        } else {
            FAIL("unexpected topic " << topic);
        }
    }
    CHECK(light > 50);
    CHECK(switches >= 2);
    CHECK(off >= 1);   // the arm hanging down switched it off
    CHECK(*brightness.begin() == 1);
    CHECK(*brightness.rbegin() == 255);
}

TEST_CASE("The homeassistant-panel preset: the panel's knobs as Home Assistant MQTT switches, its selections and position", "[mapping][mqtt][presets][panel]")
{
    const auto names = presetNames();
    REQUIRE(std::find(names.begin(), names.end(), "homeassistant-panel") != names.end());
    Rig rig(loadMapping("homeassistant-panel"));
    const ArmState arm = armAt(45, 0, 0);
    const float none = std::numeric_limits<float>::quiet_NaN();
    double t = 0.0;
    // The panel as a wearer plays it: knob 4 (upper) selected, dialled to 5 and selected, 5
    // selected again, down to the lower level (knob 14) and selected there.
    const auto update = [&](float knob, float selected, const char* gesture = nullptr) {
        SceneValues v;
        v.panelKnob = knob;
        v.panelLevel = knob < 9 ? 1.0f : 0.0f;
        v.panelSelected = selected;
        GestureIn g {gesture, selected};
        rig.step(arm, t += 0.005, gesture ? &g : nullptr, gesture ? 1 : 0, v);
    };
    update(4, none);
    update(4, 4, "select");
    update(5, 4);
    update(5, 5, "select");
    update(5, 5, "select");   // the same knob again: the switches stay, the event is sent
    update(14, 5);
    update(14, 14, "select");
    std::map<std::string, std::vector<std::string>> byTopic;
    for (const auto& [topic, payload] : rig.mqtt) {
        byTopic[topic].push_back(payload);
        // Home Assistant's MQTT switch takes payload_on "ON" and payload_off "OFF"; the sensor
        // and the trigger here carry whole knob numbers 0..17.
        if (topic.rfind("armadillo/panel/", 0) == 0 && topic.size() > 4 && topic.compare(topic.size() - 4, 4, "/set") == 0)
            CHECK((payload == "ON" || payload == "OFF"));
    }
    CHECK(byTopic["armadillo/panel/4/set"] == std::vector<std::string> {"ON", "OFF"});
    CHECK(byTopic["armadillo/panel/5/set"] == std::vector<std::string> {"ON", "OFF"});
    CHECK(byTopic["armadillo/panel/14/set"] == std::vector<std::string> {"ON"});
    CHECK(byTopic["armadillo/panel/select"] == std::vector<std::string> {"4", "5", "5", "14"});
    CHECK(byTopic["armadillo/panel/knob"] == std::vector<std::string> {"4", "5", "14"});
    CHECK(byTopic.size() == 5);
}
