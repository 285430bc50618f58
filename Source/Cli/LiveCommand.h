#pragma once
// The live session that `play` and `read` share (CmdPlay.cpp): the source (device, simulator,
// OSC), the engine and its scene, the outputs, messages over MQTT, the main loop with its status
// lines, and the summary. `play` chooses any scene; `read` is the braille scene with no text of
// its own, showing only messages (docs/MQTT.md) — the same session, so a message is shown by
// both exactly alike.
#include "Cli/CommandLine.h"
#include "Engine/Engine.h"
#include <vector>

namespace armadillo::cli {

struct LiveCommand {
    const char* name;   ///< "play" or "read": the start of every stderr line ("armadillo play: …")
    bool reader;        ///< read: the scene comes from readReaderOptions, no sound, messages required
};

/// Every option of `play` (read takes a few of them by name, with the same help).
std::vector<OptionSpec> playOptionSpecs();

/// Runs the session on options already parsed; returns the exit code (throws the errors
/// guarded() maps to codes).
int runLiveSession(const CommandLine& cl, const LiveCommand& command);

/// read: the braille scene in messages-only mode from --grade, --method, --param (braille.*,
/// not braille.mode), --arm and --profile (CmdRead.cpp). UsageError for a bad value.
void readReaderOptions(const CommandLine& cl, engine::EngineConfig& engine);

} // namespace armadillo::cli
