#include "Live/Outputs/MappingDelivery.h"
#include "Live/Step/SceneParameters.h"

namespace armadillo::live {
namespace {

void count(std::atomic<std::uint64_t>& n, std::uint64_t by = 1) noexcept
{
    n.fetch_add(by, std::memory_order_relaxed);
}

} // namespace

bool applySceneParam(const SceneParamTarget& target, const mapping::SceneParamChange& change) noexcept
{
    if (target.scene == nullptr || target.setIds == nullptr || target.specs == nullptr) return false;
    const std::vector<std::string>& ids = *target.setIds;
    if (change.index < 0 || static_cast<std::size_t>(change.index) >= ids.size()) return false;
    const std::string& id = ids[static_cast<std::size_t>(change.index)];
    const std::vector<core::ParamSpec>& specs = *target.specs;
    for (std::size_t i = 0; i < specs.size(); ++i)
        if (specs[i].id == id) {
            target.scene->setParameter(static_cast<int>(i), sceneParamValue(specs[i], change));
            return true;
        }
    return false;
}

void deliverMapping(mapping::MappingOutput& out, MappingSinks& sinks, const SceneParamTarget& params, MappingTally& tally) noexcept
{
    for (int i = 0; i < out.stageCount; ++i) {
        sinks.stage(out.stage[static_cast<std::size_t>(i)]);
        count(tally.stage);
    }
    for (int i = 0; i < out.midiCount; ++i) {
        const mapping::MidiEvent& e = out.midi[static_cast<std::size_t>(i)];
        const bool wellFormed = e.size >= 1 && e.size <= 3;
        if (wellFormed && sinks.midi(e)) count(tally.midi);
        else count(tally.midiDropped);
    }
    for (int i = 0; i < out.oscCount; ++i) {
        if (sinks.osc(out.osc[static_cast<std::size_t>(i)])) count(tally.osc);
        else count(tally.oscDropped);
    }
    for (int i = 0; i < out.mqttCount; ++i) {
        count(tally.mqtt);
        if (! sinks.mqtt(out.mqtt[static_cast<std::size_t>(i)])) count(tally.mqttDropped);
    }
    for (int k = 0; k < mapping::kMacroCount; ++k)
        if ((out.macroChanged >> k) & 1u) sinks.macro(k, out.macro[static_cast<std::size_t>(k)]);
    for (int i = 0; i < out.paramCount; ++i)
        if (applySceneParam(params, out.params[static_cast<std::size_t>(i)])) count(tally.params);
    if (out.dropped > 0) count(tally.overflow, out.dropped);
    out.clear();
}

} // namespace armadillo::live
