#pragma once
// The live sources' mailbox now lives in the core live rig (Source/Live/LiveInput.h); the plugin's
// names stay valid.
#include "Live/LiveInput.h"

namespace armadillo::plugin {
using live::LiveImu;
using live::LiveInput;
using live::LiveOrientation;
using live::toImuSample;
using live::toLiveImu;
} // namespace armadillo::plugin
