#pragma once
// The tactor output's options (issue 33, docs/TACTORS.md), shared by `play`, `tactors test` and
// `render --tactile-wav`: --tactors, --tactor-model, --tactor-map, --tactor-gain, --tactor-connect,
// --tactor-rate and the model's carrier options.
#include "Cli/CommandLine.h"
#include "Live/Outputs/TactorOutputConfig.h"
#include <vector>

namespace armadillo::cli {

/// `withDevice`: --tactors, --tactor-connect and --tactor-rate too (live outputs).
std::vector<OptionSpec> tactorOptionSpecs(bool withDevice);
/// Whether any tactor option other than --tactors was given.
bool anyTactorSetting(const CommandLine& cl);
/// The output's settings for `motors` motors (9 or 12). UsageError for a bad model, map or
/// number; InputError (exit 3) for a gain file out of range; IoError when it cannot be read.
live::TactorOutputConfig tactorConfig(const CommandLine& cl, int motors);

} // namespace armadillo::cli
