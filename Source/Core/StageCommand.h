#pragma once
// A stage command (docs/STAGE.md): what a performer's panic button, a cue key, an OSC control
// message, a MIDI foot switch or a mapping's "stage" destination asks of what plays. One type for
// every place that makes one (Live/Stage/StageControl.h: OSC and keys; Live/Stage/Stage.h: MIDI; Mapping:
// "stage" destinations), applied in one place, live::Stage::apply.
#include <cstdint>

namespace armadillo::core {

struct StageCommand {
    enum class Kind : std::uint8_t { Panic, Resume, CueNext, CuePrev, CueGoto };
    Kind kind = Kind::Panic;
    int cue = 0;   ///< CueGoto: the cue's index (0-based)
};

} // namespace armadillo::core
