#pragma once
// What one update of the mapping made, handed to where it goes: written once for every clock.
// `play`/`render` (MappingRig) and the block clock of the app and Pd (BlockControl) each had their
// own copy of this walk, with their own counting and their own way of finding a scene parameter
// (issue 45). Now the rig that clocks the mapping only names its sinks (MappingSinks: a MIDI port
// or the host's block, OSC senders or the clock's queue, an MQTT outbox, the stage, the host's
// macros); the order, the counting and the scene parameters are here.
//
// The order: stage commands first (they act at the next step, as every stage command does), then
// MIDI, OSC, MQTT, macros, scene parameters. The output is cleared afterwards.
//
// Threads: the control step's (the token holder, or the source's thread for `play`). Real-time:
// nothing here allocates, locks or blocks, and a sink must not either.
#include "Core/Scene.h"
#include "Mapping/Mapper.h"
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

namespace armadillo::live {

/// The places a rig sends its mapping's output. Every method is called on the control step's
/// thread and must be real-time safe.
class MappingSinks {
public:
    /// A MIDI message (1–3 bytes) at `e.t` on the mapping's timeline; false: not taken (counted).
    virtual bool midi(const mapping::MidiEvent& e) noexcept = 0;
    /// A finished OSC packet for target `p.target` of the set; false: not taken (counted).
    virtual bool osc(const mapping::OscPacket& p) noexcept = 0;
    /// An MQTT publish; false: not taken (no connection, the outbox full; counted).
    virtual bool mqtt(const mapping::MqttMessage& m) noexcept = 0;
    /// A stage command (docs/STAGE.md), applied at the next step.
    virtual void stage(const mapping::StageEvent& e) noexcept = 0;
    /// Macro `index` (0-based) to `value01`; a front end without macros ignores it.
    virtual void macro(int index, float value01) noexcept { (void) index, (void) value01; }

protected:
    ~MappingSinks() = default;
};

/// What the mapping has delivered so far, and what was lost. Written by the control step, read
/// from any thread.
struct MappingTally {
    std::atomic<std::uint64_t> midi {0};          ///< MIDI messages handed to the sink
    std::atomic<std::uint64_t> osc {0};           ///< OSC packets handed to the sink
    std::atomic<std::uint64_t> mqtt {0};          ///< MQTT messages made
    std::atomic<std::uint64_t> stage {0};         ///< stage commands fired
    std::atomic<std::uint64_t> params {0};        ///< scene parameter changes applied
    std::atomic<std::uint64_t> overflow {0};      ///< events the update could not hold (MappingOutput::dropped)
    std::atomic<std::uint64_t> midiDropped {0};   ///< MIDI the sink refused (or malformed)
    std::atomic<std::uint64_t> oscDropped {0};    ///< OSC the sink refused
    std::atomic<std::uint64_t> mqttDropped {0};   ///< MQTT the sink refused
};

/// The running scene's parameters as the set names them: a set's `param` destination `index`
/// is `setIds[index]`, the scene's parameter with that id in `specs` (Scene::parameters()
/// order). Any member null: scene parameters are not applied.
struct SceneParamTarget {
    core::Scene* scene = nullptr;
    const std::vector<std::string>* setIds = nullptr;
    const std::vector<core::ParamSpec>* specs = nullptr;
};

/// Sets one scene parameter a mapping changed (SceneParameters.h's rule for the value); false when
/// the set's index or id names nothing in this scene. String compares over constant lists: no
/// allocation.
bool applySceneParam(const SceneParamTarget& target, const mapping::SceneParamChange& change) noexcept;

/// Hands `out` to `sinks` and the scene, counts into `tally`, and clears `out`.
void deliverMapping(mapping::MappingOutput& out, MappingSinks& sinks, const SceneParamTarget& params, MappingTally& tally) noexcept;

} // namespace armadillo::live
