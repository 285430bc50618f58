#pragma once
// The mapping matrix (Source/Mapping) as the command line runs it, for `render --map` and
// `play --map`: the set built for the engine's scene, the Mapper stepped once per control update,
// and its outputs delivered through the one delivery every clock uses (MappingDelivery.h) to this
// rig's sinks — MIDI to a sink (a Standard MIDI File, an ALSA sequencer port), OSC packets to their
// UDP targets, MQTT messages to a sink (the MQTT client's outbox), stage commands to a sink; scene
// parameters to the scene (Scene::setParameter, which any thread may call). Macros have no host
// here and are ignored.
//
// Threads: built on the starting thread; step()/finish() on the control thread. step() allocates
// nothing (the Mapper is real-time; sending is a non-blocking sendto and the sink's own work).
#include "Live/Outputs/MappingDelivery.h"
#include "Osc/OscIo.h"
#include "Engine/Engine.h"
#include "Mapping/Mapper.h"
#include <memory>
#include <string>
#include <vector>

namespace armadillo::live {

struct MappingRigOptions {
    /// Where OSC destinations that name no host/port go ("HOST:PORT", `--osc-out`); empty: 127.0.0.1:9000.
    std::string oscDefault;
    bool sendOsc = true;        ///< false: OSC messages are counted, not sent (render without --osc-out)
    std::string sourceName;     ///< the mapping's name for messages ("preset classic", a path)
    double forwardDeg = 0.0;    ///< the forward direction to start from (azimuth, °; `--forward`)
};

/// Receives every MIDI event in order (allocation-free function pointer, unlike std::function).
using MidiSink = void (*)(void* context, const mapping::MidiEvent& event);
/// Receives every MQTT message (docs/MQTT.md), on the control thread: real-time (the MQTT client's
/// SPSC outbox); false when it could not take it (counted as dropped).
using MqttSink = bool (*)(void* context, const mapping::MqttMessage& message);
/// Receives every stage command a `"stage"` destination fired (docs/STAGE.md), on the control thread.
using StageSink = void (*)(void* context, const mapping::StageEvent& event);

class MappingRig final : private MappingSinks {
public:
    /// Builds the set for this engine's scene: InputError for a scene parameter the scene lacks or
    /// an OSC message that does not encode; IoError for an OSC target that cannot be resolved.
    MappingRig(const mapping::MappingDocument& doc, engine::Engine& engine, const MappingRigOptions& options);
    ~MappingRig();
    MappingRig(const MappingRig&) = delete;
    MappingRig& operator=(const MappingRig&) = delete;

    void setMidiSink(MidiSink sink, void* context) noexcept
    {
        sink_ = sink;
        sinkContext_ = context;
    }
    /// Where MQTT destinations' messages go (`--mqtt`); none: counted only.
    void setMqttSink(MqttSink sink, void* context) noexcept
    {
        mqttSink_ = sink;
        mqttContext_ = context;
    }
    /// Where stage commands go (`play` applies them to its set list / engine); none: counted only.
    void setStageSink(StageSink sink, void* context) noexcept
    {
        stageSink_ = sink;
        stageContext_ = context;
    }
    /// One control update as the instrument's step gives it (Instrument::mappingInput): both arms
    /// (the left null with one arm: its sources and the relative arms.* sources then have no value
    /// and send nothing), the scene's values, the step's gestures, stage commands only in panic (so
    /// a mapped resume is still heard); `engine` the one that sounds (scene parameters).
    void step(const mapping::MappingInput& in, engine::Engine& engine) noexcept;
    /// The end: gesture notes end at their due time, held notes (zones, postures) at t.
    void finish(double t) noexcept;
    /// Panic at t (docs/STAGE.md), as the plugin does: every sounding note ended, then CC 120 and
    /// CC 123 on all 16 channels (Mapper::panic), to the sink (`play --midi-out`'s port).
    void panic(double t) noexcept;
    /// MIDI events panics sent (counted in midiEvents() too).
    std::uint64_t panicMidiEvents() const noexcept { return panicMidi_; }

    mapping::Mapper& mapper() noexcept { return mapper_; }
    std::uint64_t midiEvents() const noexcept { return tally_.midi.load(std::memory_order_relaxed); }
    std::uint64_t oscMessages() const noexcept { return tally_.osc.load(std::memory_order_relaxed); }
    std::uint64_t oscSent() const noexcept;
    /// Events lost: more than one update could hold, and what a sink refused.
    std::uint64_t dropped() const noexcept;
    /// Stage commands the mapping fired.
    std::uint64_t stageCommands() const noexcept { return tally_.stage.load(std::memory_order_relaxed); }
    /// MQTT messages the mapping made (sent to the sink, or counted only without one).
    std::uint64_t mqttMessages() const noexcept { return tally_.mqtt.load(std::memory_order_relaxed); }

private:
    /// The update's output to the sinks; scene parameters to `engine`'s scene (null: not applied).
    void deliver(engine::Engine* engine) noexcept;
    bool midi(const mapping::MidiEvent& e) noexcept override;
    bool osc(const mapping::OscPacket& p) noexcept override;
    bool mqtt(const mapping::MqttMessage& m) noexcept override;
    void stage(const mapping::StageEvent& e) noexcept override;

    mapping::Mapper mapper_;
    std::unique_ptr<mapping::MappingOutput> out_;
    std::vector<std::unique_ptr<osc::OscSender>> senders_;   // per MappingSet::oscTargets() index (null: not sent)
    std::vector<core::ParamSpec> specs_;   // the scene's parameters, as the set was built for them
    MidiSink sink_ = nullptr;
    void* sinkContext_ = nullptr;
    StageSink stageSink_ = nullptr;
    void* stageContext_ = nullptr;
    MqttSink mqttSink_ = nullptr;
    void* mqttContext_ = nullptr;
    MappingTally tally_;
    std::uint64_t panicMidi_ = 0;
};

} // namespace armadillo::live
