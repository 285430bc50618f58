#pragma once
// Shared helpers of the mapping tests: an arm at a pose, a runner that collects every output,
// and MIDI decoding written from the MIDI 1.0 specification (not from the code under test).
#include "Core/Errors.h"
#include "Core/Pose.h"
#include "Mapping/Mapper.h"
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace armadillo::mapping::test {

/// What parsing `json` as a mapping file (named `source` in messages) says: the error's text, or
/// "(accepted)".
inline std::string parseMessage(const std::string& json, const std::string& source = "bad.json")
{
    try {
        parseMappingDocument(json, source);
    } catch (const core::InputError& e) {
        return e.what();
    }
    return "(accepted)";
}

inline core::ArmState armAt(double elevation, double azimuth, double roll, double t = 0.0)
{
    core::ArmState a;
    a.t = t;
    a.features.pose = core::Pose {elevation, azimuth, roll};
    a.q = poseToQuaternion(a.features.pose);
    a.gyro.setZero();
    a.valid = true;
    return a;
}

/// A Mapper over one document, stepping through poses and collecting every event.
struct Rig {
    Mapper mapper;
    std::unique_ptr<MappingOutput> out = std::make_unique<MappingOutput>();
    std::vector<MidiEvent> midi;
    std::vector<std::vector<std::uint8_t>> osc;
    std::vector<SceneParamChange> params;
    std::vector<std::pair<std::string, std::string>> mqtt;   // topic, payload
    std::array<float, kMacroCount> macro {};
    std::uint32_t macroChanged = 0;

    explicit Rig(const MappingDocument& doc) { mapper.replace(MappingSet::build(doc)); }
    explicit Rig(const std::string& json) : Rig(parseMappingDocument(json, "test.json")) {}

    void collect()
    {
        for (int i = 0; i < out->midiCount; ++i) midi.push_back(out->midi[static_cast<std::size_t>(i)]);
        for (int i = 0; i < out->oscCount; ++i) {
            const OscPacket& p = out->osc[static_cast<std::size_t>(i)];
            osc.emplace_back(p.bytes.begin(), p.bytes.begin() + p.size);
        }
        for (int i = 0; i < out->paramCount; ++i) params.push_back(out->params[static_cast<std::size_t>(i)]);
        for (int i = 0; i < out->mqttCount; ++i) {
            const MqttMessage& m = out->mqtt[static_cast<std::size_t>(i)];
            mqtt.emplace_back(std::string(m.topic.data(), m.topicLength), std::string(m.payload.data(), m.payloadLength));
        }
        for (int k = 0; k < kMacroCount; ++k)
            if (out->macroChanged & (1u << k)) macro[static_cast<std::size_t>(k)] = out->macro[static_cast<std::size_t>(k)];
        macroChanged |= out->macroChanged;
        out->clear();
    }
    /// One control update; returns the number of MIDI events it produced.
    std::size_t step(const core::ArmState& arm, double t, const GestureIn* gestures = nullptr, int count = 0, core::SceneValues scene = {})
    {
        MappingInput in;
        in.t = t;
        in.arm[0] = &arm;
        in.gestures = gestures;
        in.gestureCount = count;
        in.scene = scene;
        const std::size_t before = midi.size();
        mapper.process(in, *out);
        collect();
        return midi.size() - before;
    }
    std::size_t pose(double el, double az, double roll, double t) { return step(armAt(el, az, roll, t), t); }
    std::size_t gesture(const char* name, float value, double t, const core::ArmState& arm = armAt(0, 0, 0))
    {
        GestureIn g {name, value};
        return step(arm, t, &g, 1);
    }
};

/// The latest value of every controller per channel, replaying a stream (MIDI 1.0: status 0xBn).
struct CcState {
    std::map<int, int> value;   // key = channel * 128 + controller
    int get(int channel1, int cc) const
    {
        const auto it = value.find((channel1 - 1) * 128 + cc);
        return it == value.end() ? -1 : it->second;
    }
    void apply(const MidiEvent& e)
    {
        if (e.size == 3 && (e.bytes[0] & 0xF0) == 0xB0) value[(e.bytes[0] & 0x0F) * 128 + e.bytes[1]] = e.bytes[2];
    }
};

} // namespace armadillo::mapping::test
