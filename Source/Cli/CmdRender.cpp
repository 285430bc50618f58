#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Cli/SceneOptions.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Core/Wav.h"
#include "Engine/Engine.h"
#include "Engine/OfflineRenderer.h"
#include "Instruments/LayeredKeyboard.h"
#include "Live/SetList.h"
#include "Core/AtomicFile.h"
#include <stdexcept>
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
                       [] {
                           auto o = sceneOptionSpecs();
                           o.front().required = false;   // --scene or --setlist
                           o.insert(o.begin() + 1, {
                               {"--setlist", "FILE", "a set list (docs/STAGE.md) instead of --scene: starts at cue 0"},
                               {"--cue-at", "T:INDEX", "with --setlist: go to cue INDEX at T s (repeatable), cross-faded"},
                               {"--motion-left", "FILE", "two arms: the left arm's motion CSV (same clock as --motion); scenes see both\n"
                                                         "(theremin-duo is made for two); the left arm's motors are mirrored"},
                               {"--tactile-left", "T.csv", "with --motion-left: the left arm's motor packets"},
                               {"--arms-log", "A.csv", "with --motion-left: t,qw,qx,qy,qz,left_qw,left_qx,left_qy,left_qz per control update"},
                               {"--motion", "FILE", "motion CSV (IMU, quaternion or pose)", true},
                               {"--out", "OUT.wav", "stereo WAV, 16-bit (written whole or not at all)", true},
                               {"--tactile", "T.csv", "motor levels of every packet: t,m1..m9 (m10..m12 with --back-motors)"},
                               {"--audio-in", "FILE.wav", "the recording the listener hears, from the first motion row on: scenes that listen\n"
                                                          "(score, audio-touch, layered-keyboard) follow it; its sample rate is used unless --sample-rate is given"},
                           });
                           o.push_back({"--back-motors", "", "drive the three back motors 10..12 as well"});
                           o.push_back({"--tail", "SECONDS", "audio rendered after the last motion row (default 0)"});
                           o.push_back({"--float", "", "write 32-bit float WAV instead of 16-bit"});
                           return o;
                       }());
        if (!cl.parse(args)) return 0;

        RenderSettings settings;
        EngineConfig& engine = settings.engine;
        const bool setlist = cl.has("--setlist");
        if (setlist == cl.has("--scene")) throw UsageError("give --scene SCENE or --setlist FILE (one of them)");
        if (cl.has("--cue-at") && !setlist) throw UsageError("--cue-at applies to --setlist");
        if (setlist) {
            for (const char* o : {"--param", "--score", "--text", "--audio"})
                if (cl.has(o)) throw UsageError(std::string(o) + " goes into the set list's cues, not on the command line");
            engine.scene = "monitor";   // (each cue names its own)
            engine.sceneConfig.sampleRate = static_cast<double>(cl.integer("--sample-rate", 48000, 8000, 384000));
            engine.sceneConfig.seed = static_cast<std::uint64_t>(cl.integer("--seed", 1, 0, 1L << 62));
            const std::string arm = cl.value("--arm", "right");
            if (arm != "right" && arm != "left") throw UsageError("--arm must be right or left");
            engine.sceneConfig.side = arm == "left" ? ArmSide::Left : ArmSide::Right;
        } else {
            readSceneOptions(cl, engine);
        }
        engine.motorCount = cl.has("--back-motors") ? kGridMotors + kBackMotors : kGridMotors;
        settings.tailSeconds = cl.number("--tail", 0.0);
        if (settings.tailSeconds < 0.0 || settings.tailSeconds > 600.0) throw UsageError("--tail must lie in 0..600 s");

        AudioBuffer recording;
        if (cl.has("--audio-in")) {
            if (cl.value("--audio-in").empty()) throw UsageError("--audio-in needs a WAV file");
            recording = readWav(cl.value("--audio-in"));   // InputError names a bad file
            if (!cl.has("--sample-rate")) engine.sceneConfig.sampleRate = recording.sampleRate;
            settings.audioIn = &recording;
        }
        const CsvTable motion = CsvTable::read(cl.value("--motion"));
        for (const char* o : {"--tactile-left", "--arms-log"})
            if (cl.has(o) && !cl.has("--motion-left")) throw UsageError(std::string(o) + " applies to --motion-left");
        CsvTable leftMotion;
        if (cl.has("--motion-left")) {
            if (setlist) throw UsageError("--motion-left with --setlist is not supported yet");
            leftMotion = CsvTable::read(cl.value("--motion-left"));
            settings.leftMotion = &leftMotion;
            engine.twoArms = true;
        }
        RenderResult r;
        if (setlist) {
            const live::SetList list = live::loadSetList(cl.value("--setlist"));   // InputError names file, line, key
            std::vector<live::CueChange> changes;
            for (const std::string& c : cl.values("--cue-at")) {
                try {
                    changes.push_back(live::parseCueChange(c));
                } catch (const std::invalid_argument& e) {
                    throw UsageError(std::string("--cue-at: ") + e.what());
                }
            }
            if (settings.audioIn) throw UsageError("--audio-in with --setlist is not supported yet");
            r = live::renderSetList(motion, list, settings, changes);
            engine.scene = "setlist";
        } else {
            r = renderOffline(motion, settings);
        }

        // The notes a listening scene captured (layered-keyboard), named, in capture order.
        for (const GestureEvent& g : r.gestures)
            if (std::string_view(g.name) == "captured-note")
                std::cerr << "render: captured " << noteName(static_cast<int>(g.value)) << " at t = " << g.t << " s\n";
        writeWav(cl.value("--out"), r.audio, cl.has("--float"));
        if (cl.has("--tactile")) writeTactile(cl.value("--tactile"), r.tactile, engine.motorCount);
        if (cl.has("--tactile-left")) writeTactile(cl.value("--tactile-left"), r.leftTactile, engine.motorCount);
        if (cl.has("--arms-log")) {
            std::string text = "t,qw,qx,qy,qz,left_qw,left_qx,left_qy,left_qz\n";
            for (std::size_t i = 0; i < r.rightOrientation.size(); ++i) {
                const auto& a = r.rightOrientation[i].q;
                const auto& b = r.leftOrientation[i].q;
                for (const double v : {r.rightOrientation[i].t, a.w(), a.x(), a.y(), a.z(), b.w(), b.x(), b.y(), b.z()}) {
                    appendNumber(text, v, 9);
                    text += ',';
                }
                text.back() = '\n';
            }
            writeFileAtomically(cl.value("--arms-log"), text);
        }
        std::cout << "{\"scene\":\"" << engine.scene << "\",\"control_updates\":" << r.controlUpdates
                  << ",\"frames\":" << r.audio.frames() << ",\"seconds\":" << r.audio.frames() / r.audio.sampleRate
                  << ",\"gestures\":" << r.gestures.size() << ",\"rows_without_orientation\":" << r.invalidRows << "}\n";
        return 0;
    });
}

} // namespace armadillo::cli
