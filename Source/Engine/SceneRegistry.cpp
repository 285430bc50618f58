#include "Braille/BrailleScene.h"
#include "Core/Errors.h"
#include "Engine/Engine.h"
#include "Engine/MonitorScene.h"
#include "Formats/ScoreImport.h"
#include "Instruments/Scenes.h"
#include "Tactile/ScoreScene.h"

namespace armadillo::engine {

namespace {
struct Entry {
    const char* name;
    std::unique_ptr<core::Scene> (*make)();
};
const Entry kScenes[] = {
    {"monitor", makeMonitorScene},
    {"theremin", instruments::makeThereminScene},
    {"cymbal", instruments::makeCymbalScene},
    {"panel", instruments::makePanelScene},
    {"sound-design", instruments::makeSoundDesignScene},
    {"compass", instruments::makeCompassScene},
    {"braille", braille::makeBrailleScene},
    {"score", tactile::makeScoreScene},
    {"audio-touch", instruments::makeAudioTouchScene},
    {"layered-keyboard", instruments::makeLayeredKeyboardScene}, // issue 28; new scenes go last (choice indices stay)
    {"theremin-duo", instruments::makeThereminDuoScene}, // issue 28, two arms
};
/// Scenes a front end drives by writing into them (hostedSceneNames()); not the plugin's choice.
const Entry kHostedScenes[] = {
    {"patch", instruments::makePatchScene}, // issue 46: the grid's targets from a patch
};
} // namespace

const std::vector<std::string>& hostedSceneNames()
{
    static const std::vector<std::string> names = [] {
        std::vector<std::string> v;
        for (const auto& e : kHostedScenes) v.emplace_back(e.name);
        return v;
    }();
    return names;
}

const std::vector<std::string>& sceneNames()
{
    static const std::vector<std::string> names = [] {
        std::vector<std::string> v;
        for (const auto& e : kScenes) v.emplace_back(e.name);
        return v;
    }();
    return names;
}

std::unique_ptr<core::Scene> createScene(const std::string& name)
{
    // `--score` takes MIDI and haptic files too (docs/FORMATS.md): the score scene reads them
    // through the importers of the formats module, which sits above the tactile one.
    tactile::setScoreFileReader({&formats::isImportableScorePath, &formats::loadAnyScore});
    for (const auto& e : kScenes) {
        if (name == e.name) return e.make();
    }
    for (const auto& e : kHostedScenes) {
        if (name == e.name) return e.make();
    }
    std::string all;
    for (const auto& n : sceneNames()) all += (all.empty() ? "" : ", ") + n;
    throw core::InputError("", 0, "", "unknown scene '" + name + "' (scenes: " + all + ")");
}

} // namespace armadillo::engine
