#include "Braille/BrailleScene.h"
#include "Core/Errors.h"
#include "Engine/Engine.h"
#include "Engine/MonitorScene.h"
#include "Formats/ScoreImport.h"
#include "Instruments/Scenes.h"
#include "Tactile/ScoreScene.h"

namespace armadillo {

namespace {
struct Entry {
    const char* name;
    std::unique_ptr<Scene> (*make)();
};
const Entry kScenes[] = {
    {"monitor", makeMonitorScene},
    {"theremin", makeThereminScene},
    {"cymbal", makeCymbalScene},
    {"panel", makePanelScene},
    {"sound-design", makeSoundDesignScene},
    {"compass", makeCompassScene},
    {"braille", makeBrailleScene},
    {"score", makeScoreScene},
    {"audio-touch", makeAudioTouchScene},
    {"layered-keyboard", makeLayeredKeyboardScene},   // issue 28; new scenes go last (choice indices stay)
    {"theremin-duo", makeThereminDuoScene},           // issue 28, two arms
};
} // namespace

const std::vector<std::string>& sceneNames()
{
    static const std::vector<std::string> names = [] {
        std::vector<std::string> v;
        for (const auto& e : kScenes) v.emplace_back(e.name);
        return v;
    }();
    return names;
}

std::unique_ptr<Scene> createScene(const std::string& name)
{
    // `--score` takes MIDI and haptic files too (docs/FORMATS.md): the score scene reads them
    // through the importers of the formats module, which sits above the tactile one.
    setScoreFileReader({&isImportableScorePath, &loadAnyScore});
    for (const auto& e : kScenes) {
        if (name == e.name) return e.make();
    }
    std::string all;
    for (const auto& n : sceneNames()) all += (all.empty() ? "" : ", ") + n;
    throw InputError("", 0, "", "unknown scene '" + name + "' (scenes: " + all + ")");
}

} // namespace armadillo
