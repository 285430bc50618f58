#pragma once
// The scene options `render` and `play` share (--scene, --seed, --text, --param, …), parsed once
// so both commands accept and check them identically.
#include "Cli/CommandLine.h"
#include "Engine/Engine.h"
#include <vector>

namespace armadillo::cli {

/// Every scene name, space-separated, in the order of sceneNames() (help texts).
std::string sceneList();
/// Option specs for choosing and configuring a scene.
std::vector<OptionSpec> sceneOptionSpecs();
/// Fills `engine` from the parsed options; throws UsageError for bad values.
void readSceneOptions(const CommandLine& cl, EngineConfig& engine);

} // namespace armadillo::cli
