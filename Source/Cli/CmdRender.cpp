#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Cli/MapOptions.h"
#include "Cli/SceneOptions.h"
#include "Cli/TactorOptions.h"
#include "Osc/HostPort.h"
#include "Link/Mount.h"
#include "Live/Outputs/MappingRig.h"
#include "Mapping/MidiFile.h"
#include "Core/Csv.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include "Core/Wav.h"
#include "Engine/Engine.h"
#include "Engine/RenderSettings.h"
#include "Formats/ScoreImport.h"
#include "Instruments/LayeredKeyboard.h"
#include "Live/Session/RowClock.h"
#include "Live/Stage/SetList.h"
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

namespace {

std::vector<OptionSpec> renderOptionSpecs()
{
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
}

/// The scene (or the set list's shared options), the motors, and the tactile WAV's actuators:
/// the tactor renderer's model, map and gains (docs/TACTORS.md); without any of them, the
/// voice-coil model at 150 Hz, one channel per motor (docs/FORMATS.md).
live::TactorOutputConfig readRenderScene(const CommandLine& cl, engine::RenderSettings& settings)
{
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
    return tactorWav;
}

/// Every file the render writes, checked before any input is read or anything rendered: a
/// missing folder is an error now, not after the WAV was written.
struct RenderOutputs {
    std::string out, tactile, midiOut, tactileWav, tactileAhap, tactileHaptic, tactileTact, tactileHjif, tactileLeft, armsLog;
    std::uint16_t actuator = 0;   ///< the motors the AHAP's or .haptic's one actuator carries
    /// Every output named, for removing them all when the WAV fails.
    std::vector<const std::string*> all() const
    {
        return {&tactile, &midiOut, &tactileWav, &tactileAhap, &tactileHaptic, &tactileTact, &tactileHjif, &tactileLeft, &armsLog};
    }
};

RenderOutputs checkRenderOutputs(const CommandLine& cl, int motorCount)
{
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
    RenderOutputs o;
    const std::vector<std::pair<const char*, std::string*>> files {
        {"--out", &o.out}, {"--tactile", &o.tactile}, {"--midi-out", &o.midiOut}, {"--tactile-wav", &o.tactileWav},
        {"--tactile-ahap", &o.tactileAhap}, {"--tactile-haptic", &o.tactileHaptic}, {"--tactile-tact", &o.tactileTact}, {"--tactile-hjif", &o.tactileHjif},
        {"--tactile-left", &o.tactileLeft}, {"--arms-log", &o.armsLog}};
    std::vector<std::pair<std::string, std::string>> named;
    for (const auto& [option, file] : files) {
        *file = cl.value(option);
        if (cl.has(option)) checkOutputPath(option, *file);
        named.push_back({option, *file});
    }
    checkDistinctOutputs(named);
    o.actuator = static_cast<std::uint16_t>((1u << motorCount) - 1u);
    if (cl.has("--actuator-motors")) {
        if (!cl.has("--tactile-ahap") && !cl.has("--tactile-haptic")) throw UsageError("--actuator-motors applies to --tactile-ahap and --tactile-haptic");
        o.actuator = 0;
        if (!tactile::parseMotorSet(cl.value("--actuator-motors"), o.actuator) || o.actuator == 0)
            throw UsageError("--actuator-motors: '" + cl.value("--actuator-motors") + "' is not a motor set (1-9, elbow, 1,3 ...)");
        if (o.actuator >> motorCount) throw UsageError("--actuator-motors names a back motor (10..12): add --back-motors");
    }
    return o;
}

/// What the render hears and reads: the recording (or stems), the MIDI notes, the mounts, the
/// mapping, the motion files. `recording`, `midiIn` and `leftMotion` are the caller's (settings
/// point into them).
core::CsvTable readRenderInputs(const CommandLine& cl, engine::RenderSettings& settings, core::AudioBuffer& recording,
                                std::vector<engine::TimedMidiNote>& midiIn, core::CsvTable& leftMotion,
                                std::shared_ptr<const mapping::MappingDocument>& map, double& forward)
{
    engine::EngineConfig& engine = settings.engine;
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
    if (cl.has("--midi-in")) {   // every note-on and note-off, in time order
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
    map = readMapOption(cl, engine);
    forward = readForwardOption(cl);
    if (cl.has("--mount-left") && !cl.has("--motion-left")) throw UsageError("--mount-left applies to --motion-left");
    if (cl.has("--mount")) settings.mount = link::mountFromArgument(cl.value("--mount")).rotation;   // IoError / InputError naming the file
    if (cl.has("--mount-left")) settings.leftMount = link::mountFromArgument(cl.value("--mount-left")).rotation;
    core::CsvTable motion = core::CsvTable::read(cl.value("--motion"));
    for (const char* o : {"--tactile-left", "--arms-log"})
        if (cl.has(o) && !cl.has("--motion-left")) throw UsageError(std::string(o) + " applies to --motion-left");
    if (cl.has("--motion-left")) {
        leftMotion = core::CsvTable::read(cl.value("--motion-left"));
        settings.leftMotion = &leftMotion;
        engine.twoArms = true;
    }
    return motion;
}

/// The mapping run at every row (--map): built for the render's scene at its first row; its
/// MIDI kept for --midi-out, its OSC sent to --osc-out.
struct RenderMapping {
    std::unique_ptr<live::MappingRig> rig;
    std::unique_ptr<mapping::MidiFileWriter> midi;
    double lastRow = 0.0;

    void attach(const CommandLine& cl, engine::RenderSettings& settings, std::shared_ptr<const mapping::MappingDocument> map, double forward)
    {
        settings.onStep = [this, &cl, map, forward](const mapping::MappingInput& in, engine::Engine& e) {
            if (!rig) {   // the engine exists only inside the render: the mapping is built for its scene
                live::MappingRigOptions options;
                options.oscDefault = cl.value("--osc-out");
                options.sendOsc = cl.has("--osc-out");
                options.sourceName = cl.value("--map");
                options.forwardDeg = forward;
                rig = std::make_unique<live::MappingRig>(*map, e, options);
                midi = std::make_unique<mapping::MidiFileWriter>(in.t);
                rig->setMidiSink([](void* ctx, const mapping::MidiEvent& ev) { static_cast<mapping::MidiFileWriter*>(ctx)->add(ev); }, midi.get());
            }
            lastRow = in.t;
            if (in.arm[0]->valid) rig->step(in, e);
        };
    }
};

/// The audio streams into the WAV's temporary file as it is rendered (memory does not grow with
/// the motion file's span); the WAV is renamed in only when everything succeeded. --tactor-sound:
/// the scene's sound, mono, is kept as the voice coil's carrier in --tactile-wav.
struct RenderAudio {
    std::optional<core::WavStreamWriter> wav;
    std::vector<float> interleaved, tactorSound;
    bool keepSound = false;

    void attach(engine::RenderSettings& settings)
    {
        settings.audioSink = [this](const float* left, const float* right, int n) {
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
    }
};

engine::RenderResult renderSetListFile(const CommandLine& cl, const core::CsvTable& motion, const engine::RenderSettings& settings)
{
    const live::SetList list = live::loadSetList(cl.value("--setlist"));   // InputError names file, line, key
    std::vector<live::CueChange> changes;
    for (const std::string& c : cl.values("--cue-at")) {
        try {
            changes.push_back(live::parseCueChange(c));
        } catch (const std::invalid_argument& e) {
            throw UsageError(std::string("--cue-at: ") + e.what());
        }
    }
    return live::renderOffline(motion, settings, list, changes);   // streamed through settings.audioSink as a scene is
}

void writeArmsLog(const std::string& path, const engine::RenderResult& r)
{
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
    core::writeFileAtomically(path, text);
}

/// The motors' files: the tactile CSVs, the arms log, the tactile WAV and the haptic exports.
void writeTactileFiles(const CommandLine& cl, const RenderOutputs& o, const engine::RenderResult& r, const engine::EngineConfig& engine,
                       const live::TactorOutputConfig& tactorWav, const RenderAudio& audio)
{
    if (cl.has("--tactile")) writeTactile(o.tactile, r.tactile, engine.motorCount);
    if (cl.has("--tactile-left")) writeTactile(o.tactileLeft, r.leftTactile, engine.motorCount);
    if (cl.has("--arms-log")) writeArmsLog(o.armsLog, r);
    if (cl.has("--tactile-wav"))
        formats::writeTactileWav(o.tactileWav, r.tactile, tactorWav.params, tactorWav.map, tactorWav.gains, engine.sceneConfig.sampleRate, cl.has("--float"),
                                 audio.keepSound ? &audio.tactorSound : nullptr);
    const std::string project = std::filesystem::path(cl.value("--motion")).stem().string();
    if (cl.has("--tactile-ahap")) core::writeFileAtomically(o.tactileAhap, formats::exportAhap(r.tactile, o.actuator, project));
    if (cl.has("--tactile-haptic")) core::writeFileAtomically(o.tactileHaptic, formats::exportMetaHaptic(r.tactile, o.actuator, project));
    if (cl.has("--tactile-tact")) core::writeFileAtomically(o.tactileTact, formats::exportTact(r.tactile, project));
    if (cl.has("--tactile-hjif")) core::writeFileAtomically(o.tactileHjif, formats::exportHjif(r.tactile, engine.motorCount, project));
}

void printRenderSummary(const engine::EngineConfig& engine, const engine::RenderResult& r, const live::MappingRig* rig)
{
    const double seconds = static_cast<double>(r.frames) / engine.sceneConfig.sampleRate;
    std::cout << "{\"scene\":\"" << engine.scene << "\",\"control_updates\":" << r.controlUpdates
              << ",\"frames\":" << r.frames << ",\"seconds\":" << seconds
              << ",\"gestures\":" << r.gestures.size() << ",\"rows_without_orientation\":" << r.invalidRows;
    if (rig)
        std::cout << ",\"mapping_midi_events\":" << rig->midiEvents() << ",\"mapping_osc_messages\":" << rig->oscMessages()
                  << ",\"mapping_osc_sent\":" << rig->oscSent() << ",\"mapping_dropped\":" << rig->dropped();
    std::cout << "}\n";
}

} // namespace

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
                       renderOptionSpecs());
        if (!cl.parse(args)) return 0;

        engine::RenderSettings settings;
        engine::EngineConfig& engine = settings.engine;
        const live::TactorOutputConfig tactorWav = readRenderScene(cl, settings);
        const RenderOutputs outputs = checkRenderOutputs(cl, engine.motorCount);
        core::AudioBuffer recording;
        std::vector<engine::TimedMidiNote> midiIn;
        core::CsvTable leftMotion;
        std::shared_ptr<const mapping::MappingDocument> map;
        double forward = 0.0;
        const core::CsvTable motion = readRenderInputs(cl, settings, recording, midiIn, leftMotion, map, forward);
        RenderMapping mapping;
        if (map) mapping.attach(cl, settings, map, forward);
        RenderAudio audio;
        if (cl.has("--out")) audio.wav.emplace(outputs.out, engine.sceneConfig.sampleRate, 2, cl.has("--float"));
        audio.keepSound = cl.has("--tactile-wav") && tactorWav.params.voiceCoilSound;
        audio.attach(settings);

        engine::RenderResult r;
        if (cl.has("--setlist")) {
            if (map) throw UsageError("--map with --setlist is not supported yet");
            r = renderSetListFile(cl, motion, settings);
            engine.scene = "setlist";
        } else {
            r = live::renderOffline(motion, settings);
        }
        // The notes a listening scene captured (layered-keyboard), named, in capture order.
        for (const engine::GestureEvent& g : r.gestures)
            if (std::string_view(g.name) == "captured-note")
                std::cerr << "render: captured " << instruments::noteName(static_cast<int>(g.value)) << " at t = " << g.t << " s\n";
        if (mapping.rig) mapping.rig->finish(mapping.lastRow);
        if (cl.has("--midi-out")) {
            if (!mapping.midi) mapping.midi = std::make_unique<mapping::MidiFileWriter>(0.0);
            mapping.midi->write(outputs.midiOut);
        }
        writeTactileFiles(cl, outputs, r, engine, tactorWav, audio);
        if (audio.wav) {
            try {
                audio.wav->finish();
            } catch (const core::IoError&) { // the WAV could not be completed: no part of the outputs stays
                for (const std::string* f : outputs.all())
                    if (!f->empty()) std::remove(f->c_str());
                throw;
            }
            if (const std::string why = silenceReason(r, settings); !why.empty())
                std::cerr << "armadillo render: the output is silent: " << why << "\n";
        }
        printRenderSummary(engine, r, mapping.rig.get());
        return 0;
    });
}

} // namespace armadillo::cli
