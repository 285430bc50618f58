#pragma once
// `--map PRESET|FILE` and the MIDI/OSC outputs a mapping drives, shared by `render` and `play`
// (docs/MAPPING.md, INTERFACES.md).
#include "Cli/CommandLine.h"
#include "Engine/Engine.h"
#include "Mapping/MappingSpec.h"
#include <memory>
#include <string>

namespace armadillo::cli {

inline const char* const kMapHelp =
    "the mapping matrix: a preset (classic, scenerotator, scenerotator-osc, mpe, homeassistant; `armadillo\n"
    "resources` lists them) or a mapping file (JSON, docs/MAPPING.md). With --map only what the\n"
    "mapping names is sent";

/// The mapping --map names (nullptr without --map): InputError (exit 3) for a bad file, IoError
/// (exit 4) for one that cannot be read or a preset that does not exist.
std::shared_ptr<const mapping::MappingDocument> readMapOption(const CommandLine& cl, const engine::EngineConfig& engine);

inline const char* const kForwardHelp =
    "with --map: the forward direction (azimuth, degrees) yaw and forward-relative azimuths are\n"
    "measured from (default 0: north)";
/// --forward DEG (0…360; UsageError otherwise), 0 without it.
double readForwardOption(const CommandLine& cl);

} // namespace armadillo::cli
