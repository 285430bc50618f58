#pragma once
// A scene's parameters as both clocks of the rig set them: the table of every scene's
// parameters (queried once, constant while the rig runs, read lock-free by the control side) and
// the one rule that turns a mapping's `param` destination (docs/MAPPING.md) into the value the
// scene gets — `play --map` (MappingRig) and the plugin's block clock (BlockControl) both call it.
#include "Core/Scene.h"
#include "Mapping/Mapper.h"
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace armadillo::live {

/// Every scene's own parameters (the plugin exposes them as host parameters).
struct SceneParameterTable {
    struct Entry {
        std::string scene;             ///< scene name (INTERFACES.md)
        bool available = false;        ///< false: the scene could not be created (reason says why)
        std::string reason;            ///< why it is unavailable
        std::vector<core::ParamSpec> specs; ///< Scene::parameters(), in index order
        std::vector<bool> exposed;     ///< false for a spec whose id another scene already took
    };
    std::vector<Entry> scenes;         ///< in sceneNames() order
};

/// The value a mapping's change gives the parameter `spec`: a normalised change spans the range
/// (0 → min, 1 → max), an absolute one is in the parameter's unit; clamped to the range and, for
/// a choice, rounded to the nearest choice. Real-time (no allocation).
inline float sceneParamValue(const core::ParamSpec& spec, const mapping::SceneParamChange& change) noexcept
{
    const float lo = std::min(spec.min, spec.max), hi = std::max(spec.min, spec.max);
    float v = change.normalised ? spec.min + change.value * (spec.max - spec.min) : change.value;
    v = std::clamp(v, lo, hi);
    if (! spec.choices.empty()) v = std::round(v);
    return v;
}

} // namespace armadillo::live
