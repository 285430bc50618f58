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
void readSceneOptions(const CommandLine& cl, engine::EngineConfig& engine);
/// `--profile FILE` alone into engine.motorGain (readSceneOptions reads it too; a set list's cues
/// take it from here). UsageError without a file, InputError for a bad profile.
void readProfileOption(const CommandLine& cl, engine::EngineConfig& engine);
/// With --setlist (play, render): the options every cue shares (--sample-rate, --seed, --arm,
/// --profile; the engine itself only tracks: "monitor"); UsageError for a cue's own option
/// (--param, --score, --text, --audio and `cueOnly`) given on the command line.
void readSetListOptions(const CommandLine& cl, engine::EngineConfig& engine, const std::vector<const char*>& cueOnly = {});

/// The stems audio-touch feels apart (docs/INSTRUMENTS.md "Stems felt apart"), as `render` and
/// `play` take them: `--stem NAME=FILE` (repeatable), or several `--audio-in` files, each named by
/// its file name (drums.wav → drums). Returns the files in order and appends their names to
/// `engine.sceneConfig.stems`; empty when there are none (one --audio-in is a recording, not a
/// stem). UsageError for a malformed --stem, --stem with a single --audio-in, or stems for a
/// scene other than audio-touch.
std::vector<std::string> readStemOptions(const CommandLine& cl, engine::EngineConfig& engine);

} // namespace armadillo::cli
