#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Cli/MapOptions.h"
#include "Cli/SceneOptions.h"
#include "Cli/TactorOptions.h"
#include "Osc/HostPort.h"
#include "Link/Mount.h"
#include "Live/MappingRig.h"
#include "Mapping/MidiFile.h"
#include "Core/Csv.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include "Core/Wav.h"
#include "Engine/Engine.h"
#include "Engine/OfflineRenderer.h"
#include "Formats/ScoreImport.h"
#include "Instruments/LayeredKeyboard.h"
#include "Live/SetList.h"
#include "Core/AtomicFile.h"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>

namespace armadillo::cli {

int runRender(const Arguments& args)
{
    return guarded("render", [&] {
        CommandLine cl("render", "--scene SCENE --motion FILE (--out OUT.wav | --map M --midi-out OUT.mid) [options]",
                       "Runs a scene offline over a motion file with the same engine the app uses, and writes\n"
                       "the audio and (optionally) every motor packet. FILE is an IMU, quaternion or pose CSV,\n"
                       "told apart by its header; IMU files are fused with the SR-UKF first. One control update\n"
                       "per row; the result is the same for the same inputs and --seed. With --map the mapping runs\n"
                       "at every row: --midi-out writes its MIDI as a Standard MIDI File (format 1, 960 ticks per\n"
                       "quarter at 120 bpm: one tick is 0.52 ms, so every event lies within 0.27 ms of its row),\n"
                       "--osc-out sends its OSC messages (at render speed).",
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
                               {"--mount", "FILE|PRESET", "how the sensor that recorded --motion (an IMU or quaternion file) was strapped on:\n"
                                                          "a mount file (play --calibrate-mount) or a preset (identity, phone-screen-up, ngimu ...)"},
                               {"--mount-left", "FILE|PRESET", "the same for --motion-left"},
                               {"--motion", "FILE", "motion CSV (IMU, quaternion or pose)", true},
                               {"--out", "OUT.wav", "stereo WAV, 16-bit (written whole or not at all); may be left out with --midi-out"},
                               {"--tactile", "T.csv", "motor levels of every packet: t,m1..m9 (m10..m12 with --back-motors); the last\n"
                                                    "row is the all-off sent at the end"},
                               {"--audio-in", "FILE.wav", "the recording the listener hears, from the first motion row on: scenes that listen\n"
                                                          "(score, audio-touch, layered-keyboard) follow it, and it is mixed into OUT.wav under the scene's\n"
                                                          "sound; its sample rate is used unless --sample-rate is given.\n"
                                                          "Given several times, each file is a stem named by its file name (drums.wav, bass.wav ...)"},
                               {"--midi-in", "PIECE.mid", "with --audio-in: the instrument's MIDI notes on the recording's clock (a Standard MIDI\n"
                                                          "File, t = 0 at its first sample): layered-keyboard takes its notes from them (docs/STAGE.md)"},
                               {"--no-audio-in-mix", "", "with --audio-in: leave the recording out of OUT.wav (the scene's sound alone)"},
                               {"--stem", "NAME=FILE.wav", "audio-touch: a stem felt apart on its own motors (drums, bass, other, vocals;\n"
                                                          "repeatable; docs/INSTRUMENTS.md)"},
                           });
                           o.push_back({"--back-motors", "", "drive the three back motors 10..12 as well"});
                           o.push_back({"--tail", "SECONDS", "audio rendered after the last motion row (default 0)"});
                           o.push_back({"--float", "", "write 32-bit float WAV instead of 16-bit"});
                           o.push_back({"--map", "PRESET|FILE", kMapHelp});
                           o.push_back({"--forward", "DEG", kForwardHelp});
                           o.push_back({"--midi-out", "OUT.mid", "with --map: the mapped MIDI as a Standard MIDI File (written whole or not at all)"});
                           o.push_back({"--osc-out", "HOST:PORT", "with --map: send the mapping's OSC messages (those naming no target go here;\n"
                                                                  "without --osc-out no OSC is sent)"});
                           o.push_back({"--tactile-wav", "OUT.wav", "the motors as a multichannel WAV (docs/FORMATS.md): channel k = motor k,\n"
                                                                    "a 150 Hz sine at amplitude level/15 (9 channels, 12 with --back-motors)"});
                           for (const OptionSpec& t : tactorOptionSpecs(false)) {   // the --tactile-wav's actuators (docs/TACTORS.md)
                               o.push_back(t);
                               o.back().help = "with --tactile-wav: " + o.back().help;
                           }
                           o.push_back({"--tactile-ahap", "OUT.ahap", "the motors as an Apple AHAP file: one actuator, level = 15 x HapticIntensity\n"
                                                                      "(docs/FORMATS.md; sharpness is not written)"});
                           o.push_back({"--tactile-haptic", "OUT.haptic", "the motors as a Meta Haptics Studio .haptic file: one actuator,\n"
                                                                          "level = 15 x amplitude (docs/FORMATS.md)"});
                           o.push_back({"--tactile-tact", "OUT.tact", "the motors as a bHaptics .tact forearm (ForearmR) effect (docs/FORMATS.md)"});
                           o.push_back({"--tactile-hjif", "OUT.hjif", "the motors as an MPEG haptics (ISO/IEC 23090-31) .hjif file: one channel per motor,\n"
                                                                      "amplitude = level/15 (docs/FORMATS.md)"});
                           o.push_back({"--actuator-motors", "SET", "with --tactile-ahap/--tactile-haptic: the motors the one actuator carries\n"
                                                                    "(the loudest of them at each packet; default all of the render's motors)"});
                           return o;
                       }());
        if (!cl.parse(args)) return 0;

        engine::RenderSettings settings;
        engine::EngineConfig& engine = settings.engine;
        const bool setlist = cl.has("--setlist");
        if (setlist == cl.has("--scene")) throw UsageError("give --scene SCENE or --setlist FILE (one of them)");
        if (cl.has("--cue-at") && !setlist) throw UsageError("--cue-at applies to --setlist");
        if (setlist) {
            readSetListOptions(cl, engine);   // the options every cue shares (Cli/SceneOptions.h)
        } else {
            readSceneOptions(cl, engine);
        }
        engine.motorCount = cl.has("--back-motors") ? core::kGridMotors + core::kBackMotors : core::kGridMotors;
        // The tactile WAV's actuators: the tactor renderer's model, map and gains (docs/TACTORS.md);
        // without any of them, the voice-coil model at 150 Hz, one channel per motor (docs/FORMATS.md).
        if (anyTactorSetting(cl) && !cl.has("--tactile-wav")) throw UsageError("the --tactor-* options shape --tactile-wav: give it too");
        live::TactorOutputConfig tactorWav;
        if (anyTactorSetting(cl)) {
            tactorWav = tactorConfig(cl, engine.motorCount);   // UsageError / InputError before the render starts
            tactors::validate(tactorWav.params, engine.sceneConfig.sampleRate, "--tactor-model");
        } else {
            tactorWav.params.model = tactors::TactorModel::VoiceCoil;
            tactorWav.params.voiceCoilHz = 150.0;
            tactorWav.map = tactors::ChannelMap::identity(engine.motorCount);
        }
        settings.tailSeconds = cl.number("--tail", 0.0);
        if (settings.tailSeconds < 0.0 || settings.tailSeconds > 600.0) throw UsageError("--tail must lie in 0..600 s");
        if (cl.has("--no-audio-in-mix") && !cl.has("--audio-in")) throw UsageError("--no-audio-in-mix applies to --audio-in");
        settings.mixAudioIn = !cl.has("--no-audio-in-mix");
        if (cl.has("--audio-in") && cl.value("--audio-in").empty()) throw UsageError("--audio-in needs a WAV file");

        // Every output is checked before any input is read or anything rendered: a missing folder
        // is an error now, not after the WAV was written.
        if (!cl.has("--out") && !cl.has("--midi-out")) throw UsageError("missing --out OUT.wav (or --map with --midi-out OUT.mid)");
        if (cl.has("--out") && cl.value("--out").empty()) throw UsageError("--out needs a file name");
        if ((cl.has("--midi-out") || cl.has("--osc-out")) && !cl.has("--map"))
            throw UsageError("--midi-out and --osc-out send what a mapping makes: give --map PRESET|FILE too");
        if (cl.has("--midi-out") && cl.value("--midi-out").empty()) throw UsageError("--midi-out needs a file name");
        if (cl.has("--osc-out")) {
            try {
                osc::parseHostPort(cl.value("--osc-out"));
            } catch (const std::invalid_argument& e) {
                throw UsageError(std::string("--osc-out: ") + e.what());
            }
        }
        const std::string out = cl.value("--out"), tactile = cl.value("--tactile"), midiOut = cl.value("--midi-out"),
                          tactileWav = cl.value("--tactile-wav"), tactileAhap = cl.value("--tactile-ahap"),
                          tactileHaptic = cl.value("--tactile-haptic"), tactileTact = cl.value("--tactile-tact"),
                          tactileHjif = cl.value("--tactile-hjif");
        if (cl.has("--out")) checkOutputPath("--out", out);
        if (cl.has("--tactile")) checkOutputPath("--tactile", tactile);
        if (cl.has("--midi-out")) checkOutputPath("--midi-out", midiOut);
        if (cl.has("--tactile-wav")) checkOutputPath("--tactile-wav", tactileWav);
        if (cl.has("--tactile-ahap")) checkOutputPath("--tactile-ahap", tactileAhap);
        if (cl.has("--tactile-haptic")) checkOutputPath("--tactile-haptic", tactileHaptic);
        if (cl.has("--tactile-tact")) checkOutputPath("--tactile-tact", tactileTact);
        if (cl.has("--tactile-hjif")) checkOutputPath("--tactile-hjif", tactileHjif);
        const std::string tactileLeft = cl.value("--tactile-left"), armsLog = cl.value("--arms-log");
        if (cl.has("--tactile-left")) checkOutputPath("--tactile-left", tactileLeft);
        if (cl.has("--arms-log")) checkOutputPath("--arms-log", armsLog);
        checkDistinctOutputs({{"--out", out}, {"--tactile", tactile}, {"--midi-out", midiOut}, {"--tactile-wav", tactileWav},
                              {"--tactile-ahap", tactileAhap}, {"--tactile-haptic", tactileHaptic}, {"--tactile-tact", tactileTact},
                              {"--tactile-hjif", tactileHjif}, {"--tactile-left", tactileLeft}, {"--arms-log", armsLog}});
        std::uint16_t actuator = static_cast<std::uint16_t>((1u << engine.motorCount) - 1u);
        if (cl.has("--actuator-motors")) {
            if (!cl.has("--tactile-ahap") && !cl.has("--tactile-haptic")) throw UsageError("--actuator-motors applies to --tactile-ahap and --tactile-haptic");
            actuator = 0;
            if (!tactile::parseMotorSet(cl.value("--actuator-motors"), actuator) || actuator == 0)
                throw UsageError("--actuator-motors: '" + cl.value("--actuator-motors") + "' is not a motor set (1-9, elbow, 1,3 ...)");
            if (actuator >> engine.motorCount) throw UsageError("--actuator-motors names a back motor (10..12): add --back-motors");
        }

        core::AudioBuffer recording;
        // Stems: --stem NAME=FILE, or several --audio-in files named after their stem.
        const std::vector<std::string> paths = readStemOptions(cl, engine);
        if (!paths.empty()) {
            recording = core::readWavStems(paths); // InputError names a bad file or a sample-rate mismatch
            settings.audioInName = paths.front();
            if (!cl.has("--sample-rate")) engine.sceneConfig.sampleRate = core::engineSampleRate(recording.sampleRate, paths.front());
            settings.audioIn = &recording;
        } else if (cl.has("--audio-in")) {
            recording = core::readWav(cl.value("--audio-in")); // IoError (4) when unreadable, InputError (3) naming the file when not audio
            if (!cl.has("--sample-rate")) engine.sceneConfig.sampleRate = core::engineSampleRate(recording.sampleRate, cl.value("--audio-in"));
            settings.audioIn = &recording;
            settings.audioInName = cl.value("--audio-in");
        }
        std::vector<engine::TimedMidiNote> midiIn; // --midi-in: every note-on and note-off, in time order
        if (cl.has("--midi-in")) {
            if (!settings.audioIn) throw UsageError("--midi-in needs --audio-in (the notes' sound is sampled from the recording)");
            const formats::MidiFile piece = formats::readMidiFile(cl.value("--midi-in")); // InputError (3) naming the file and byte
            for (const formats::MidiNote& n : piece.notes) {
                midiIn.push_back({piece.secondsAt(n.start), n.key, n.velocity, n.channel});
                midiIn.push_back({piece.secondsAt(n.end), n.key, 0, n.channel});
            }
            std::stable_sort(midiIn.begin(), midiIn.end(), [](const engine::TimedMidiNote& a, const engine::TimedMidiNote& b) { return a.t < b.t; });
            settings.midiIn = &midiIn;
            settings.midiInName = cl.value("--midi-in");
        }
        const auto map = readMapOption(cl, engine);
        const double forward = readForwardOption(cl);
        if (cl.has("--mount-left") && !cl.has("--motion-left")) throw UsageError("--mount-left applies to --motion-left");
        if (cl.has("--mount")) settings.mount = link::mountFromArgument(cl.value("--mount")).rotation;   // IoError / InputError naming the file
        if (cl.has("--mount-left")) settings.leftMount = link::mountFromArgument(cl.value("--mount-left")).rotation;
        const core::CsvTable motion = core::CsvTable::read(cl.value("--motion"));
        for (const char* o : {"--tactile-left", "--arms-log"})
            if (cl.has(o) && !cl.has("--motion-left")) throw UsageError(std::string(o) + " applies to --motion-left");
        core::CsvTable leftMotion;
        if (cl.has("--motion-left")) {
            leftMotion = core::CsvTable::read(cl.value("--motion-left"));
            settings.leftMotion = &leftMotion;
            engine.twoArms = true;
        }

        std::unique_ptr<live::MappingRig> rig;
        std::unique_ptr<mapping::MidiFileWriter> midi;
        double lastRow = 0.0;
        if (map) {
            settings.onControl = [&](double t, const core::ArmState& arm, const core::ArmState* leftArm, const engine::GestureEvent* g, std::size_t n, engine::Engine& e) {
                if (!rig) {   // the engine exists only inside the render: the mapping is built for its scene
                    live::MappingRigOptions options;
                    options.oscDefault = cl.value("--osc-out");
                    options.sendOsc = cl.has("--osc-out");
                    options.sourceName = cl.value("--map");
                    options.forwardDeg = forward;
                    rig = std::make_unique<live::MappingRig>(*map, e, options);
                    midi = std::make_unique<mapping::MidiFileWriter>(t);
                    rig->setMidiSink([](void* ctx, const mapping::MidiEvent& ev) { static_cast<mapping::MidiFileWriter*>(ctx)->add(ev); }, midi.get());
                }
                lastRow = t;
                if (arm.valid) rig->step(t, arm, leftArm, g, n, e);
            };
        }

        // The audio streams into the WAV's temporary file as it is rendered (memory does not grow
        // with the motion file's span); the WAV is renamed in only when everything succeeded.
        std::optional<core::WavStreamWriter> wav;
        if (cl.has("--out")) wav.emplace(out, engine.sceneConfig.sampleRate, 2, cl.has("--float"));
        std::vector<float> interleaved;
        // --tactor-sound: the scene's sound, mono, is the voice coil's carrier in --tactile-wav.
        std::vector<float> tactorSound;
        const bool keepSound = cl.has("--tactile-wav") && tactorWav.params.voiceCoilSound;
        settings.audioSink = [&](const float* left, const float* right, int n) {
            if (keepSound)
                for (int i = 0; i < n; ++i) tactorSound.push_back(0.5f * (left[i] + right[i]));
            if (!wav) return;   // --midi-out alone: the audio is rendered (scenes stay the same) but not kept
            interleaved.resize(2 * static_cast<std::size_t>(n));
            for (int i = 0; i < n; ++i) {
                interleaved[2 * static_cast<std::size_t>(i)] = left[i];
                interleaved[2 * static_cast<std::size_t>(i) + 1] = right[i];
            }
            if (!wav->write(interleaved.data(), static_cast<std::size_t>(n))) wav->finish();   // throws IoError naming the file
        };
        engine::RenderResult r;
        if (setlist) {
            if (map) throw UsageError("--map with --setlist is not supported yet");
            const live::SetList list = live::loadSetList(cl.value("--setlist"));   // InputError names file, line, key
            std::vector<live::CueChange> changes;
            for (const std::string& c : cl.values("--cue-at")) {
                try {
                    changes.push_back(live::parseCueChange(c));
                } catch (const std::invalid_argument& e) {
                    throw UsageError(std::string("--cue-at: ") + e.what());
                }
            }
            r = live::renderSetList(motion, list, settings, changes);   // streamed through settings.audioSink as a scene is
            engine.scene = "setlist";
        } else {
            r = renderOffline(motion, settings);
        }
        // The notes a listening scene captured (layered-keyboard), named, in capture order.
        for (const engine::GestureEvent& g : r.gestures)
            if (std::string_view(g.name) == "captured-note")
                std::cerr << "render: captured " << instruments::noteName(static_cast<int>(g.value)) << " at t = " << g.t << " s\n";
        if (rig) rig->finish(lastRow);
        if (cl.has("--midi-out")) {
            if (!midi) midi = std::make_unique<mapping::MidiFileWriter>(0.0);
            midi->write(midiOut);
        }
        if (cl.has("--tactile")) writeTactile(tactile, r.tactile, engine.motorCount);
        if (cl.has("--tactile-left")) writeTactile(cl.value("--tactile-left"), r.leftTactile, engine.motorCount);
        if (cl.has("--arms-log")) {
            std::string text = "t,qw,qx,qy,qz,left_qw,left_qx,left_qy,left_qz\n";
            for (std::size_t i = 0; i < r.rightOrientation.size(); ++i) {
                const auto& a = r.rightOrientation[i].q;
                const auto& b = r.leftOrientation[i].q;
                for (const double v : {r.rightOrientation[i].t, a.w(), a.x(), a.y(), a.z(), b.w(), b.x(), b.y(), b.z()}) {
                    core::appendNumber(text, v, 9);
                    text += ',';
                }
                text.back() = '\n';
            }
            core::writeFileAtomically(cl.value("--arms-log"), text);
        }
        if (cl.has("--tactile-wav"))
            formats::writeTactileWav(tactileWav, r.tactile, tactorWav.params, tactorWav.map, tactorWav.gains, engine.sceneConfig.sampleRate, cl.has("--float"),
                            keepSound ? &tactorSound : nullptr);
        const std::string project = std::filesystem::path(cl.value("--motion")).stem().string();
        if (cl.has("--tactile-ahap")) core::writeFileAtomically(tactileAhap, formats::exportAhap(r.tactile, actuator, project));
        if (cl.has("--tactile-haptic")) core::writeFileAtomically(tactileHaptic, formats::exportMetaHaptic(r.tactile, actuator, project));
        if (cl.has("--tactile-tact")) core::writeFileAtomically(tactileTact, formats::exportTact(r.tactile, project));
        if (cl.has("--tactile-hjif")) core::writeFileAtomically(tactileHjif, formats::exportHjif(r.tactile, engine.motorCount, project));
        if (wav) {
            try {
                wav->finish();
            } catch (const core::IoError&) { // the WAV could not be completed: no part of the outputs stays
                for (const std::string* f : {&tactile, &midiOut, &tactileWav, &tactileAhap, &tactileHaptic, &tactileTact, &tactileLeft, &armsLog})
                    if (!f->empty()) std::remove(f->c_str());
                throw;
            }
            if (const std::string why = silenceReason(r, settings); !why.empty())
                std::cerr << "armadillo render: the output is silent: " << why << "\n";
        }
        const double seconds = static_cast<double>(r.frames) / engine.sceneConfig.sampleRate;
        std::cout << "{\"scene\":\"" << engine.scene << "\",\"control_updates\":" << r.controlUpdates
                  << ",\"frames\":" << r.frames << ",\"seconds\":" << seconds
                  << ",\"gestures\":" << r.gestures.size() << ",\"rows_without_orientation\":" << r.invalidRows;
        if (rig)
            std::cout << ",\"mapping_midi_events\":" << rig->midiEvents() << ",\"mapping_osc_messages\":" << rig->oscMessages()
                      << ",\"mapping_osc_sent\":" << rig->oscSent() << ",\"mapping_dropped\":" << rig->dropped();
        std::cout << "}\n";
        return 0;
    });
}

} // namespace armadillo::cli
