#include "Cli/MapOptions.h"

namespace armadillo::cli {

std::shared_ptr<const mapping::MappingDocument> readMapOption(const CommandLine& cl, const engine::EngineConfig& engine)
{
    if (!cl.has("--map")) return nullptr;
    const std::string name = cl.value("--map");
    if (name.empty()) throw UsageError("--map needs a preset name or a mapping file");
    return std::make_shared<const mapping::MappingDocument>(mapping::loadMapping(name, engine.sceneConfig.resourceDir));
}

double readForwardOption(const CommandLine& cl)
{
    if (!cl.has("--forward")) return 0.0;
    if (!cl.has("--map")) throw UsageError("--forward is the mapping's forward direction: give --map too");
    const double deg = cl.number("--forward", 0.0);
    if (!(deg >= 0.0 && deg <= 360.0)) throw UsageError("--forward must lie in 0..360 degrees");
    return deg;
}

} // namespace armadillo::cli
