#pragma once
// What a live tactor output is asked to be (docs/TACTORS.md): the device, the actuators' model,
// the channel map and gains, and JACK's or ALSA's settings. A plain value that front ends fill
// from their options or settings and hand to the live session (LiveConfig::tactors), which builds
// the output (Live/Outputs/TactorOutput.h) from it.
#include "Core/Types.h"
#include "Tactors/TactorRenderer.h"
#include <string>

namespace armadillo::live {

struct TactorOutputConfig {
    std::string device;                    ///< "jack", or an ALSA PCM name ("hw:UMC1820", "plughw:1", "null")
    tactors::TactorParams params {};
    tactors::ChannelMap map = tactors::ChannelMap::identity(core::kGridMotors);
    tactors::TactorGains gains {};
    std::string connect;                   ///< JACK: connect tactor_k to the k-th input port matching this ("" = none)
    std::string clientName = "armadillo";  ///< JACK client name
    double sampleRate = 48000.0;           ///< ALSA: the rate asked of the device (JACK: the server's)
    double latencySeconds = 0.010;         ///< ALSA: buffer asked of the device
    int realtimePriority = 0;              ///< ALSA thread: SCHED_FIFO priority (0 = none)
};

} // namespace armadillo::live
