#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Cli/SceneOptions.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Core/Wav.h"
#include "Engine/Engine.h"
#include "Engine/OfflineRenderer.h"
#include <algorithm>
#include <cstdio>
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
                               {"--tactile", "T.csv", "motor levels of every packet: t,m1..m9 (m10..m12 with --back-motors); the last\n"
                                                    "row is the all-off sent at the end"},
                               {"--audio-in", "FILE.wav", "the recording the listener hears, from the first motion row on: scenes that listen\n"
                                                          "(score, audio-touch) follow it, and it is mixed into OUT.wav under the scene's\n"
                                                          "sound; its sample rate is used unless --sample-rate is given"},
                               {"--no-audio-in-mix", "", "with --audio-in: leave the recording out of OUT.wav (the scene's sound alone)"},
                           });
                           o.push_back({"--back-motors", "", "drive the three back motors 10..12 as well"});
                           o.push_back({"--tail", "SECONDS", "audio rendered after the last motion row (default 0)"});
                           o.push_back({"--float", "", "write 32-bit float WAV instead of 16-bit"});
                           return o;
                       }());
        if (!cl.parse(args)) return 0;

        RenderSettings settings;
        EngineConfig& engine = settings.engine;
        readSceneOptions(cl, engine);
        engine.motorCount = cl.has("--back-motors") ? kGridMotors + kBackMotors : kGridMotors;
        settings.tailSeconds = cl.number("--tail", 0.0);
        if (settings.tailSeconds < 0.0 || settings.tailSeconds > 600.0) throw UsageError("--tail must lie in 0..600 s");
        if (cl.has("--no-audio-in-mix") && !cl.has("--audio-in")) throw UsageError("--no-audio-in-mix applies to --audio-in");
        settings.mixAudioIn = !cl.has("--no-audio-in-mix");
        if (cl.has("--audio-in") && cl.value("--audio-in").empty()) throw UsageError("--audio-in needs a WAV file");

        // Every output is checked before any input is read or anything rendered: a missing folder
        // is an error now, not after the WAV was written.
        const std::string out = cl.value("--out"), tactile = cl.value("--tactile");
        checkOutputPath("--out", out);
        if (cl.has("--tactile")) checkOutputPath("--tactile", tactile);
        checkDistinctOutputs({{"--out", out}, {"--tactile", tactile}});

        AudioBuffer recording;
        if (cl.has("--audio-in")) {
            recording = readWav(cl.value("--audio-in"));   // IoError (4) when unreadable, InputError (3) naming the file when not audio
            if (!cl.has("--sample-rate")) engine.sceneConfig.sampleRate = recording.sampleRate;
            settings.audioIn = &recording;
            settings.audioInName = cl.value("--audio-in");
        }
        const CsvTable motion = CsvTable::read(cl.value("--motion"));

        // The audio streams into the WAV's temporary file as it is rendered (memory does not grow
        // with the motion file's span); the WAV is renamed in only when everything succeeded.
        WavStreamWriter wav(out, engine.sceneConfig.sampleRate, 2, cl.has("--float"));
        std::vector<float> interleaved;
        settings.audioSink = [&](const float* left, const float* right, int n) {
            interleaved.resize(2 * static_cast<std::size_t>(n));
            for (int i = 0; i < n; ++i) {
                interleaved[2 * static_cast<std::size_t>(i)] = left[i];
                interleaved[2 * static_cast<std::size_t>(i) + 1] = right[i];
            }
            if (!wav.write(interleaved.data(), static_cast<std::size_t>(n))) wav.finish();   // throws IoError naming the file
        };
        const RenderResult r = renderOffline(motion, settings);
        if (cl.has("--tactile")) writeTactile(tactile, r.tactile, engine.motorCount);
        try {
            wav.finish();
        } catch (const IoError&) {   // the WAV could not be completed: no half of the outputs stays
            if (cl.has("--tactile")) std::remove(tactile.c_str());
            throw;
        }
        if (const std::string why = silenceReason(r, settings); !why.empty())
            std::cerr << "armadillo render: the output is silent: " << why << "\n";
        const double seconds = static_cast<double>(r.frames) / engine.sceneConfig.sampleRate;
        std::cout << "{\"scene\":\"" << engine.scene << "\",\"control_updates\":" << r.controlUpdates
                  << ",\"frames\":" << r.frames << ",\"seconds\":" << seconds
                  << ",\"gestures\":" << r.gestures.size() << ",\"rows_without_orientation\":" << r.invalidRows << "}\n";
        return 0;
    });
}

} // namespace armadillo::cli
