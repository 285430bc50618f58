#include "Cli/SceneOptions.h"
#include "Link/TouchProfile.h"
#include <algorithm>
#include <filesystem>

namespace armadillo::cli {

std::string sceneList()
{
    std::string list;
    for (const std::string& n : engine::sceneNames()) list += (list.empty() ? "" : " ") + n;
    return list;
}

std::vector<OptionSpec> sceneOptionSpecs()
{
    return {
        {"--scene", "SCENE", sceneList(), true},
        {"--sample-rate", "HZ", "audio sample rate (default 48000)"},
        {"--score", "NAME", "score scene: rite-of-spring, polytope, a score of yours (armadillo resources), a .score file,\n"
                             "or a file to import as it plays: .mid .wav .ahap .haptic .tact .hjif (docs/FORMATS.md)"},
        {"--text", "TEXT", "braille scene: the text to read (@FILE reads a text or .brf file)"},
        {"--seed", "N", "seed of every random choice (default 1)"},
        {"--audio", "FILE.wav", "cymbal: a recording to cut crash fragments from (mixed with the built-in bank)"},
        {"--arm", "right|left", "arm wearing the device (left mirrors motor columns; default right)"},
        {"--param", "ID=VALUE", "set one of the scene's own parameters (repeatable), e.g. braille.mode=passive"},
        {"--profile", "PROFILE.json", "the reader's touch profile (armadillo touch-profile): each motor's levels scaled so\n"
                                      "all are felt alike, before the safety stage"},
    };
}

void readProfileOption(const CommandLine& cl, engine::EngineConfig& engine)
{
    if (!cl.has("--profile")) return;
    if (cl.value("--profile").empty()) throw UsageError("--profile needs a touch profile file");
    engine.motorGain = link::touchProfileGains(link::loadTouchProfile(cl.value("--profile")));   // InputError: exit 3
}

void readSceneOptions(const CommandLine& cl, engine::EngineConfig& engine)
{
    engine.scene = cl.value("--scene");
    const auto& names = engine::sceneNames();
    if (std::find(names.begin(), names.end(), engine.scene) == names.end())
        throw UsageError("unknown scene '" + engine.scene + "' (scenes: " + sceneList() + ")");
    engine.sceneConfig.sampleRate = static_cast<double>(cl.integer("--sample-rate", 48000, 8000, 384000));
    engine.sceneConfig.seed = static_cast<std::uint64_t>(cl.integer("--seed", 1, 0, 1L << 62));
    engine.sceneConfig.text = cl.value("--text");
    engine.sceneConfig.score = cl.value("--score");
    engine.sceneConfig.audioFile = cl.value("--audio");
    if (!engine.sceneConfig.audioFile.empty() && engine.scene != "cymbal")
        throw UsageError("--audio is for the cymbal scene");
    const std::string arm = cl.value("--arm", "right");
    if (arm != "right" && arm != "left") throw UsageError("--arm must be right or left");
    engine.sceneConfig.side = arm == "left" ? core::ArmSide::Left : core::ArmSide::Right;
    engine.parameters = cl.values("--param");
    // A setting the scene does not have, or a value it does not take, is bad usage (exit 2),
    // refused before any file is read or written.
    for (const std::string& p : engine.parameters)
        if (const std::string problem = engine::sceneParameterProblem(engine.scene, p); !problem.empty())
            throw UsageError("--param " + p + ": " + problem);
    readProfileOption(cl, engine);
    if (engine.scene == "score" && engine.sceneConfig.score.empty())
        throw UsageError("the score scene needs --score (rite-of-spring, polytope or a file)");
    // Training (play --training-log) brings its own material, and so do messages (play --messages,
    // docs/MQTT.md: the scene's own text is then its demonstration word); reading needs a text.
    const bool messages = cl.has("--messages") || cl.has("--urgent") || cl.has("--mqtt-config");
    if (engine.scene == "braille" && engine.sceneConfig.text.empty() && !cl.has("--training-log") && !messages)
        throw UsageError("the braille scene needs --text");
}

std::vector<std::string> readStemOptions(const CommandLine& cl, engine::EngineConfig& engine)
{
    std::vector<std::pair<std::string, std::string>> stems;
    for (const std::string& s : cl.values("--stem")) {
        const auto eq = s.find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == s.size()) throw UsageError("--stem takes NAME=FILE.wav, not '" + s + "'");
        stems.emplace_back(s.substr(0, eq), s.substr(eq + 1));
    }
    const std::vector<std::string> inputs = cl.values("--audio-in");
    if (inputs.size() > 1)
        for (const std::string& f : inputs) {
            if (f.empty()) throw UsageError("--audio-in needs a WAV file");
            stems.emplace_back(std::filesystem::path(f).stem().string(), f);
        }
    if (!stems.empty() && inputs.size() == 1) throw UsageError("--stem and a single --audio-in: give the mix as stems, or one recording");
    if (stems.empty()) return {};
    if (engine.scene != "audio-touch") throw UsageError("stems are felt by the audio-touch scene only (--scene audio-touch)");
    std::vector<std::string> paths;
    for (const auto& [name, path] : stems) {
        paths.push_back(path);
        engine.sceneConfig.stems.push_back(name);
    }
    return paths;
}

void readSetListOptions(const CommandLine& cl, engine::EngineConfig& engine, const std::vector<const char*>& cueOnly)
{
    std::vector<const char*> own {"--param", "--score", "--text", "--audio"};
    own.insert(own.end(), cueOnly.begin(), cueOnly.end());
    for (const char* o : own)
        if (cl.has(o)) throw UsageError(std::string(o) + " goes into the set list's cues, not on the command line");
    engine.scene = "monitor";   // (each cue names its own)
    engine.sceneConfig.sampleRate = static_cast<double>(cl.integer("--sample-rate", 48000, 8000, 384000));
    engine.sceneConfig.seed = static_cast<std::uint64_t>(cl.integer("--seed", 1, 0, 1L << 62));
    const std::string arm = cl.value("--arm", "right");
    if (arm != "right" && arm != "left") throw UsageError("--arm must be right or left");
    engine.sceneConfig.side = arm == "left" ? core::ArmSide::Left : core::ArmSide::Right;
    readProfileOption(cl, engine);   // every cue feels the reader's touch profile
}

} // namespace armadillo::cli
