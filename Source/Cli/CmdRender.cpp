#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Cli/SceneOptions.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Core/Wav.h"
#include "Engine/Engine.h"
#include "Engine/OfflineRenderer.h"
#include "Formats/ScoreImport.h"
#include <algorithm>
#include <filesystem>
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
                       [] {
                           auto o = sceneOptionSpecs();
                           o.insert(o.begin() + 1, {
                               {"--motion", "FILE", "motion CSV (IMU, quaternion or pose)", true},
                               {"--out", "OUT.wav", "stereo WAV, 16-bit (written whole or not at all)", true},
                               {"--tactile", "T.csv", "motor levels of every packet: t,m1..m9 (m10..m12 with --back-motors)"},
                               {"--audio-in", "FILE.wav", "the recording the listener hears, from the first motion row on: scenes that listen\n"
                                                          "(score, audio-touch) follow it; its sample rate is used unless --sample-rate is given.\n"
                                                          "Given several times, each file is a stem named by its file name (drums.wav, bass.wav ...)"},
                               {"--stem", "NAME=FILE.wav", "audio-touch: a stem felt apart on its own motors (drums, bass, other, vocals;\n"
                                                          "repeatable; docs/INSTRUMENTS.md)"},
                           });
                           o.push_back({"--back-motors", "", "drive the three back motors 10..12 as well"});
                           o.push_back({"--tail", "SECONDS", "audio rendered after the last motion row (default 0)"});
                           o.push_back({"--float", "", "write 32-bit float WAV instead of 16-bit"});
                           o.push_back({"--tactile-wav", "OUT.wav", "the motors as a multichannel WAV (docs/FORMATS.md): channel k = motor k,\n"
                                                                    "a 150 Hz sine at amplitude level/15 (9 channels, 12 with --back-motors)"});
                           return o;
                       }());
        if (!cl.parse(args)) return 0;

        RenderSettings settings;
        EngineConfig& engine = settings.engine;
        readSceneOptions(cl, engine);
        engine.motorCount = cl.has("--back-motors") ? kGridMotors + kBackMotors : kGridMotors;
        settings.tailSeconds = cl.number("--tail", 0.0);
        if (settings.tailSeconds < 0.0 || settings.tailSeconds > 600.0) throw UsageError("--tail must lie in 0..600 s");

        AudioBuffer recording;
        // Stems: --stem NAME=FILE, or several --audio-in files named after their stem.
        std::vector<std::pair<std::string, std::string>> stems;
        for (const std::string& s : cl.values("--stem")) {
            const auto eq = s.find('=');
            if (eq == std::string::npos || eq == 0 || eq + 1 == s.size()) throw UsageError("--stem takes NAME=FILE.wav, not '" + s + "'");
            stems.emplace_back(s.substr(0, eq), s.substr(eq + 1));
        }
        const std::vector<std::string> inputs = cl.values("--audio-in");
        if (inputs.size() > 1)
            for (const std::string& f : inputs) stems.emplace_back(std::filesystem::path(f).stem().string(), f);
        if (!stems.empty() && inputs.size() == 1) throw UsageError("--stem and a single --audio-in: give the mix as stems, or one recording");
        if (!stems.empty()) {
            if (engine.scene != "audio-touch") throw UsageError("stems are felt by the audio-touch scene only (--scene audio-touch)");
            recording.channels.clear();
            for (const auto& [name, path] : stems) {
                const AudioBuffer stem = readWav(path);   // InputError names a bad file
                if (recording.channels.empty()) recording.sampleRate = stem.sampleRate;
                else if (stem.sampleRate != recording.sampleRate) throw InputError(path, 0, "", "the stems must share one sample rate");
                std::vector<float> mono(stem.frames(), 0.0f);
                for (const auto& c : stem.channels)
                    for (std::size_t i = 0; i < mono.size(); ++i) mono[i] += c[i] / static_cast<float>(stem.channels.size());
                recording.channels.push_back(std::move(mono));
                engine.sceneConfig.stems.push_back(name);
            }
            std::size_t longest = 0;
            for (const auto& c : recording.channels) longest = std::max(longest, c.size());
            for (auto& c : recording.channels) c.resize(longest, 0.0f);
            if (!cl.has("--sample-rate")) engine.sceneConfig.sampleRate = recording.sampleRate;
            settings.audioIn = &recording;
        } else if (cl.has("--audio-in")) {
            if (cl.value("--audio-in").empty()) throw UsageError("--audio-in needs a WAV file");
            recording = readWav(cl.value("--audio-in"));   // InputError names a bad file
            if (!cl.has("--sample-rate")) engine.sceneConfig.sampleRate = recording.sampleRate;
            settings.audioIn = &recording;
        }
        const CsvTable motion = CsvTable::read(cl.value("--motion"));
        const RenderResult r = renderOffline(motion, settings);

        writeWav(cl.value("--out"), r.audio, cl.has("--float"));
        if (cl.has("--tactile")) writeTactile(cl.value("--tactile"), r.tactile, engine.motorCount);
        if (cl.has("--tactile-wav")) writeTactileWav(cl.value("--tactile-wav"), r.tactile, engine.motorCount, r.audio.sampleRate, 150.0, cl.has("--float"));
        std::cout << "{\"scene\":\"" << engine.scene << "\",\"control_updates\":" << r.controlUpdates
                  << ",\"frames\":" << r.audio.frames() << ",\"seconds\":" << r.audio.frames() / r.audio.sampleRate
                  << ",\"gestures\":" << r.gestures.size() << ",\"rows_without_orientation\":" << r.invalidRows << "}\n";
        return 0;
    });
}

} // namespace armadillo::cli
