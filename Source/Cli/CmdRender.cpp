#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Engine/Engine.h"
#include "Engine/OfflineRenderer.h"
#include <algorithm>
#include <iostream>

namespace armadillo::cli {

int runRender(const Arguments& args)
{
    return guarded("render", [&] {
        CommandLine cl("render", "--scene SCENE --motion FILE --out OUT.wav [options]",
                       "Runs a scene offline over a motion file with the same engine the app uses, and writes\n"
                       "the audio and (optionally) every motor packet. FILE is an IMU, quaternion or pose CSV,\n"
                       "told apart by its header; IMU files are fused with the SR-UKF first. One control update\n"
                       "per row; the result is the same for the same inputs and --seed.",
                       {
                           {"--scene", "SCENE", "monitor theremin cymbal panel sound-design compass braille score", true},
                           {"--motion", "FILE", "motion CSV (IMU, quaternion or pose)", true},
                           {"--out", "OUT.wav", "stereo WAV, 16-bit (written whole or not at all)", true},
                           {"--tactile", "T.csv", "motor levels of every packet: t,m1..m9 (m10..m12 with --back-motors)"},
                           {"--sample-rate", "HZ", "audio sample rate (default 48000)"},
                           {"--score", "NAME", "score scene: rite-of-spring, polytope, or a score file"},
                           {"--text", "TEXT", "braille scene: the text to read"},
                           {"--seed", "N", "seed of every random choice (default 1)"},
                           {"--arm", "right|left", "arm wearing the device (left mirrors motor columns; default right)"},
                           {"--back-motors", "", "drive the three back motors 10..12 as well"},
                           {"--tail", "SECONDS", "audio rendered after the last motion row (default 0)"},
                           {"--float", "", "write 32-bit float WAV instead of 16-bit"},
                           {"--param", "ID=VALUE", "set one of the scene's own parameters (repeatable), e.g. braille.mode=passive"},
                       });
        if (!cl.parse(args)) return 0;

        RenderSettings settings;
        EngineConfig& engine = settings.engine;
        engine.scene = cl.value("--scene");
        const auto& names = sceneNames();
        if (std::find(names.begin(), names.end(), engine.scene) == names.end())
            throw UsageError("unknown scene '" + engine.scene + "'");
        engine.sceneConfig.sampleRate = static_cast<double>(cl.integer("--sample-rate", 48000, 8000, 384000));
        engine.sceneConfig.seed = static_cast<std::uint64_t>(cl.integer("--seed", 1, 0, 1L << 62));
        engine.sceneConfig.text = cl.value("--text");
        engine.sceneConfig.score = cl.value("--score");
        const std::string arm = cl.value("--arm", "right");
        if (arm != "right" && arm != "left") throw UsageError("--arm must be right or left");
        engine.sceneConfig.side = arm == "left" ? ArmSide::Left : ArmSide::Right;
        engine.motorCount = cl.has("--back-motors") ? kGridMotors + kBackMotors : kGridMotors;
        engine.parameters = cl.values("--param");
        settings.tailSeconds = cl.number("--tail", 0.0);
        if (settings.tailSeconds < 0.0 || settings.tailSeconds > 600.0) throw UsageError("--tail must lie in 0..600 s");
        if (engine.scene == "score" && engine.sceneConfig.score.empty())
            throw UsageError("the score scene needs --score (rite-of-spring, polytope or a file)");
        if (engine.scene == "braille" && engine.sceneConfig.text.empty())
            throw UsageError("the braille scene needs --text");

        const CsvTable motion = CsvTable::read(cl.value("--motion"));
        const RenderResult r = renderOffline(motion, settings);

        writeWav(cl.value("--out"), r.audio, cl.has("--float"));
        if (cl.has("--tactile")) writeTactile(cl.value("--tactile"), r.tactile, engine.motorCount);
        std::cout << "{\"scene\":\"" << engine.scene << "\",\"control_updates\":" << r.controlUpdates
                  << ",\"frames\":" << r.audio.frames() << ",\"seconds\":" << r.audio.frames() / r.audio.sampleRate
                  << ",\"gestures\":" << r.gestures.size() << ",\"rows_without_orientation\":" << r.invalidRows << "}\n";
        return 0;
    });
}

} // namespace armadillo::cli
