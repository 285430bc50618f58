#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Cli/MapOptions.h"
#include "Cli/SceneOptions.h"
#include "Device/OscIo.h"
#include "Live/MappingRig.h"
#include "Mapping/MidiFile.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Core/Wav.h"
#include "Engine/Engine.h"
#include "Engine/OfflineRenderer.h"
#include <algorithm>
#include <iostream>
#include <memory>
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
                           o.insert(o.begin() + 1, {
                               {"--motion", "FILE", "motion CSV (IMU, quaternion or pose)", true},
                               {"--out", "OUT.wav", "stereo WAV, 16-bit (written whole or not at all); may be left out with --midi-out"},
                               {"--tactile", "T.csv", "motor levels of every packet: t,m1..m9 (m10..m12 with --back-motors)"},
                               {"--audio-in", "FILE.wav", "the recording the listener hears, from the first motion row on: scenes that listen\n"
                                                          "(score, audio-touch) follow it; its sample rate is used unless --sample-rate is given"},
                           });
                           o.push_back({"--back-motors", "", "drive the three back motors 10..12 as well"});
                           o.push_back({"--tail", "SECONDS", "audio rendered after the last motion row (default 0)"});
                           o.push_back({"--float", "", "write 32-bit float WAV instead of 16-bit"});
                           o.push_back({"--map", "PRESET|FILE", kMapHelp});
                           o.push_back({"--forward", "DEG", kForwardHelp});
                           o.push_back({"--midi-out", "OUT.mid", "with --map: the mapped MIDI as a Standard MIDI File (written whole or not at all)"});
                           o.push_back({"--osc-out", "HOST:PORT", "with --map: send the mapping's OSC messages (those naming no target go here;\n"
                                                                  "without --osc-out no OSC is sent)"});
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
        if (cl.has("--audio-in")) {
            if (cl.value("--audio-in").empty()) throw UsageError("--audio-in needs a WAV file");
            recording = readWav(cl.value("--audio-in"));   // InputError names a bad file
            if (!cl.has("--sample-rate")) engine.sceneConfig.sampleRate = recording.sampleRate;
            settings.audioIn = &recording;
        }
        if (!cl.has("--out") && !cl.has("--midi-out")) throw UsageError("missing --out OUT.wav (or --map with --midi-out OUT.mid)");
        if (cl.has("--out") && cl.value("--out").empty()) throw UsageError("--out needs a file name");
        if ((cl.has("--midi-out") || cl.has("--osc-out")) && !cl.has("--map"))
            throw UsageError("--midi-out and --osc-out send what a mapping makes: give --map PRESET|FILE too");
        if (cl.has("--midi-out") && cl.value("--midi-out").empty()) throw UsageError("--midi-out needs a file name");
        if (cl.has("--osc-out")) {
            try {
                device::parseHostPort(cl.value("--osc-out"));
            } catch (const std::invalid_argument& e) {
                throw UsageError(std::string("--osc-out: ") + e.what());
            }
        }
        const auto map = readMapOption(cl, engine);
        const double forward = readForwardOption(cl);
        const CsvTable motion = CsvTable::read(cl.value("--motion"));

        std::unique_ptr<live::MappingRig> rig;
        std::unique_ptr<mapping::MidiFileWriter> midi;
        double lastRow = 0.0;
        if (map) {
            settings.onControl = [&](double t, const ArmState& arm, const GestureEvent* g, std::size_t n, Engine& e) {
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
                if (arm.valid) rig->step(t, arm, g, n, e);
            };
        }
        const RenderResult r = renderOffline(motion, settings);
        if (rig) rig->finish(lastRow);

        if (cl.has("--out")) writeWav(cl.value("--out"), r.audio, cl.has("--float"));
        if (cl.has("--midi-out")) {
            if (!midi) midi = std::make_unique<mapping::MidiFileWriter>(0.0);
            midi->write(cl.value("--midi-out"));
        }
        if (cl.has("--tactile")) writeTactile(cl.value("--tactile"), r.tactile, engine.motorCount);
        std::cout << "{\"scene\":\"" << engine.scene << "\",\"control_updates\":" << r.controlUpdates
                  << ",\"frames\":" << r.audio.frames() << ",\"seconds\":" << r.audio.frames() / r.audio.sampleRate
                  << ",\"gestures\":" << r.gestures.size() << ",\"rows_without_orientation\":" << r.invalidRows;
        if (rig)
            std::cout << ",\"mapping_midi_events\":" << rig->midiEvents() << ",\"mapping_osc_messages\":" << rig->oscMessages()
                      << ",\"mapping_osc_sent\":" << rig->oscSent() << ",\"mapping_dropped\":" << rig->dropped();
        std::cout << "}\n";
        return 0;
    });
}

} // namespace armadillo::cli
