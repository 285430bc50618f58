#include "Cli/MapOptions.h"

namespace armadillo::cli {

std::shared_ptr<const mapping::MappingDocument> readMapOption(const CommandLine& cl, const EngineConfig& engine)
{
    if (!cl.has("--map")) return nullptr;
    const std::string name = cl.value("--map");
    if (name.empty()) throw UsageError("--map needs a preset name or a mapping file");
    return std::make_shared<const mapping::MappingDocument>(mapping::loadMapping(name, engine.sceneConfig.resourceDir));
}

} // namespace armadillo::cli
