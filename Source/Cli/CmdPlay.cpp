#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Cli/LiveCommand.h"
#include "Cli/LiveOptions.h"
#include "Cli/MapOptions.h"
#include "Cli/MqttOptions.h"
#include "Cli/ReaderIo.h"
#include "Cli/SceneOptions.h"
#include "Cli/TactorOptions.h"
#include "Live/Outputs/MappingRig.h"
#include "Core/Errors.h"
#include "Braille/BrailleScene.h"
#include "Braille/TrainingFeeder.h"
#include "Core/AtomicFile.h"
#include "Core/Wav.h"
#include "Live/Session/LiveSession.h"
#include "Link/Calibration.h"
#include "Live/Sources/SourceReport.h"
#include "Osc/HostPort.h"
#include "Osc/OscDialects.h"
#include "Link/Mount.h"
#include "Procedures/DeviceCalibration.h"
#include "Procedures/MountCalibration.h"
#include "Live/Stage/StageControl.h"
#include "Engine/Engine.h"
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <chrono>
#include <iostream>
#include <memory>
#include <thread>
#include <tuple>
#include <vector>
#include <atomic>
#include <csignal>
#include <poll.h>
#include <unistd.h>

namespace armadillo::cli {

namespace {

/// Braille training through the terminal: prompts out on stderr, answers in from stdin (read
/// without blocking, so the session's loop keeps its pace). braille::TrainingAnswerFeeder hands
/// the answers to the scene one at a time, each once the previous one is scored, so every
/// "right"/"wrong" belongs to its trial (the app's Training panel uses the same feeder).
class TerminalTraining {
public:
    /// `voice` (optional): the prompts and results are also spoken and shown on a braille display.
    TerminalTraining(braille::BrailleSceneControls& scene, ReaderIo* voice) : scene_(scene), voice_(voice) {}

    /// Waits up to `waitMs` for input, then reports a scored answer, shows the next prompt and
    /// hands over the next answer. Returns false once every trial is answered.
    bool step(int waitMs)
    {
        readLines(waitMs);
        for (const braille::TrainingNotice& n : feeder_.poll(scene_)) {
            if (n.kind == braille::TrainingNotice::Kind::Result) {
                std::cerr << "  " << braille::resultText(n) << "\n";
                if (voice_) voice_->note(braille::resultText(n));
            } else if (n.kind == braille::TrainingNotice::Kind::Prompt) {
                // The hold stage is also answered by the arm: a push along the forearm (Braille/ArmPush.h).
                const std::string how = scene_.trainingExpected(n.trial) == "here" ? " (type here, or push the forearm along its axis and back)" : "";
                std::cerr << "braille training " << n.trial + 1 << "/" << n.trialCount << ": " << n.prompt << how << "\n";
                if (voice_) voice_->prompt("trial " + std::to_string(n.trial + 1) + " of " + std::to_string(n.trialCount) + ": " + n.prompt);
            }
        }
        return !feeder_.finished();
    }

    /// stdin has ended and every answer it gave is scored: no more can come.
    bool exhausted() const noexcept { return stdinClosed_ && feeder_.waiting() == 0 && !feeder_.awaitingScore(); }

private:
    void readLines(int waitMs)
    {
        if (stdinClosed_) {
            std::this_thread::sleep_for(std::chrono::milliseconds(waitMs));
            return;
        }
        pollfd p {STDIN_FILENO, POLLIN, 0};
        if (::poll(&p, 1, waitMs) > 0) {
            char buf[512];
            const ssize_t n = ::read(STDIN_FILENO, buf, sizeof buf);
            if (n > 0) {
                pending_.append(buf, static_cast<std::size_t>(n));
            } else if (n == 0 || (errno != EINTR && errno != EAGAIN)) {
                stdinClosed_ = true;
                pending_ += '\n';   // a last answer without a newline still counts
            }
        }
        for (std::size_t nl; (nl = pending_.find('\n')) != std::string::npos;) {
            const std::string line = pending_.substr(0, nl);
            pending_.erase(0, nl + 1);
            // Blank lines are skipped quietly; anything else refused is said, and not sent.
            const auto refusal = feeder_.add(line);
            if (refusal != braille::TrainingAnswerFeeder::Refusal::None && refusal != braille::TrainingAnswerFeeder::Refusal::Empty)
                std::cerr << "  not sent: " << braille::TrainingAnswerFeeder::refusalText(refusal) << "\n";
        }
    }

    braille::BrailleSceneControls& scene_;
    ReaderIo* voice_ = nullptr;
    braille::TrainingAnswerFeeder feeder_;
    std::string pending_;
    bool stdinClosed_ = false;
};

/// SIGUSR1 → the mapping's "set forward" (an atomic store: safe in a signal handler).
std::atomic<mapping::Mapper*>& forwardTarget()
{
    static std::atomic<mapping::Mapper*> target {nullptr};
    return target;
}

void onForwardSignal(int)
{
    if (mapping::Mapper* m = forwardTarget().load()) m->requestForward();
}

/// The guided mount calibration of one OSC sender (`--calibrate-mount` for the right arm,
/// `--calibrate-mount-left` for the left), presenting procedures::MountCalibration (the app's
/// Mount window presents the same): the rig's sensor-frame samples through the poses, each pose
/// taken as soon as it has enough still samples, its lines on stderr, the mount file at the end.
struct GuidedMount {
    procedures::MountCalibration calibration;
    live::LiveSession* session = nullptr;
    bool left = false;
    std::string out, option, arm;   // arm: "" or "left arm " in the messages

    void begin()
    {
        calibration.setAnnouncer([this](const std::string& line) { std::cerr << arm << line << "\n"; });
        calibration.begin({}, procedures::MountCalibration::Advance::WhenReady);   // "mount calibration pose 1 (…): …"
    }
    bool active() const { return calibration.running(); }
    void step()
    {
        if (active()) calibration.drain([this](osc::SensorFrameSample& p) { return active() && session->popSensorFrame(left, p); });
    }
    void finish()
    {
        calibration.setDevice(session->senderName(left));
        std::string why;
        if (!calibration.conclude(why))
            throw core::IoError(option + ": no mount written: " + why + " (stopped at pose '" + link::MountCalibration::poseName(calibration.pose()) + "')");
        calibration.save(out);
        std::cerr << arm << "mount calibration written to " << out << "\n";
    }
};

} // namespace

std::vector<OptionSpec> playOptionSpecs()
{
    auto o = sceneOptionSpecs();
    o.front().required = false;   // --scene or --setlist
    const std::vector<OptionSpec> stage {
        {"--setlist", "FILE", "a set list (docs/STAGE.md) instead of --scene: starts at cue 0; steps with --keys\n"
                              "(n, b, 0..9) and --control-in (/armadillo/cue/next, /armadillo/cue/prev, /armadillo/cue i)"},
        {"--control-in", "PORT", "stage commands as OSC on this UDP port, on 127.0.0.1 unless --control-bind (docs/STAGE.md):\n"
                                 "/armadillo/panic, /armadillo/resume, /armadillo/cue/next, /armadillo/cue/prev, /armadillo/cue i"},
        {"--keys", "", "stage keys on stdin: p or Escape = panic, r = resume, n or Space = next cue,\n"
                       "b = previous cue, 0..9 = cue"},
        {"--panic-gesture", "", "the forearm hanging straight down (elevation <= -75 deg) for 2 s panics"},
    };
    const std::vector<OptionSpec> mapping {
        {"--map", "PRESET|FILE", kMapHelp},
        {"--forward", "DEG", std::string(kForwardHelp) + "; SIGUSR1 (kill -USR1 PID) sets forward to where\n"
                             "the arm points now"},
        {"--midi-out", "NAME", "with --map: open an ALSA sequencer output port NAME (client \"ARMadillo\") and send the\n"
                               "mapped MIDI there as it happens; exit 4 naming the cause when there is no sequencer"},
    };
    const std::vector<OptionSpec> procedures {
        {"--training-log", "LOG.csv", "with --scene braille: the training protocol (thesis §4.4.1) live. Each trial's\n"
                                      "prompt is printed on stderr; type the answers on stdin, one a line (left, right,\n"
                                      "both, here, a letter or a word); right/wrong is said at once; the session ends when\n"
                                      "every trial is answered and the log (docs/BRAILLE.md) is written to LOG.csv"},
        {"--calibrate", "OUT.json", "run the guided calibration (thesis §2.4) on the device while playing; instructions on\n"
                                    "stderr, each step finishes when it has enough data; writes OUT.json (unfinished steps keep\n"
                                    "the starting calibration)"},
    };
    std::vector<OptionSpec> own {stage.front()};   // --setlist, right after --scene
    for (const auto& group : {sourceOptionSpecs(), outputOptionSpecs(), mapping, procedures, leftArmOptionSpecs(),
                              std::vector<OptionSpec>(stage.begin() + 1, stage.begin() + 2), controlListenOptionSpecs(),
                              std::vector<OptionSpec>(stage.begin() + 2, stage.end()), webOptionSpecs()})
        own.insert(own.end(), group.begin(), group.end());
    o.insert(o.begin() + 1, own.begin(), own.end());
    // The motor grid live as audio (docs/TACTORS.md), beside the device.
    const auto tactorOptions = tactorOptionSpecs(true);
    o.insert(o.end(), tactorOptions.begin(), tactorOptions.end());
    o.push_back({"--back-motors", "", "drive the three back motors 10..12 as well: in the tactile CSV, OSC out and the tactor\n"
                                      "output (the thesis's serial packet carries motors 1..9)"});
    for (const auto& specs : {mqttBrokerOptionSpecs(), mqttMessageOptionSpecs()}) o.insert(o.end(), specs.begin(), specs.end());
    o.push_back({"--status-file", "FILE", "once a second, FILE is replaced (whole, never half-written) by one JSON line: the\n"
                                          "summary so far plus seconds and the sensor-to-motor latency (latency_p50_us,\n"
                                          "latency_p99_us, latency_max_us since the start) for a watcher (scripts/soak.sh)"});
    // Speech and a braille display for the training's prompts and the link's state.
    const auto io = readerIoOptionSpecs();
    o.insert(o.end(), io.begin(), io.end());
    return o;
}

namespace {

/// What `play` (or `read`) was asked for: the live configuration and what the front end does
/// around the session (how long, the guided procedures' files, the stage's control port, the
/// reader's voice, messages on the arm).
struct PlayRequest {
    live::LiveConfig config;
    double seconds = -1.0;
    double dataTimeout = 5.0;
    bool leftNeedsData = false;
    std::string mountOut, leftMountOut, calibrateOut, trainingLog;
    int controlPort = -1;
    live::StageControlListen controlListen;   // --control-bind, --control-allow
    std::string statusFile;                   // --status-file
    std::unique_ptr<ReaderIo> voice;
    std::unique_ptr<PlayMessages> messages;   // what the session's messages say on stderr (null: no broker)
};

/// Step 1: the options, group by group (Cli/LiveOptions.h), into a request; every output is
/// checked and every input read before anything is opened.
std::unique_ptr<PlayRequest> readPlayRequest(const CommandLine& cl, const LiveCommand& command)
{
    live::LiveConfig config;
    const SourceChoice source = readSourceOptions(cl, config);   // the source group (Cli/LiveOptions.h)
    const std::string mountOut = source.mountOut;
    engine::EngineConfig& engine = config.engine;
    if (command.reader) {
        readReaderOptions(cl, engine);   // the braille scene, messages only
    } else if (cl.has("--setlist") == cl.has("--scene")) {
        throw UsageError("give --scene SCENE or --setlist FILE (one of them)");
    } else if (cl.has("--setlist")) {
        readSetListOptions(cl, engine, {"--training-log"});
        config.setList = cl.value("--setlist");
        if (config.setList.empty()) throw UsageError("--setlist needs a file");
    } else {
        readSceneOptions(cl, engine);
    }
    engine.motorCount = cl.has("--back-motors") ? core::kGridMotors + core::kBackMotors : core::kGridMotors;

    const double seconds = cl.number("--seconds", -1.0);   // (checked with the outputs group)
    if (cl.has("--midi-out") && !cl.has("--map")) throw UsageError("--midi-out sends what a mapping makes: give --map PRESET|FILE too");
    if (cl.has("--midi-out") && cl.value("--midi-out").empty()) throw UsageError("--midi-out needs a port name");
    config.mappingName = cl.value("--map");
    config.midiOut = cl.value("--midi-out");
    config.forwardDeg = readForwardOption(cl);
    const std::string leftMountOut = readLeftArmOptions(cl, config);   // the left arm group
    // Steadier timing for the link (and the simulated device) where the system allows it.
    config.link.realtimePriority = 20;
    readOutputOptions(cl, config, !command.reader);   // the outputs group (read: the braille scene is silent)
    const double dataTimeout = cl.number("--data-timeout", 5.0);
    if (!(dataTimeout >= 0.0 && dataTimeout <= 3600.0)) throw UsageError("--data-timeout must lie in 0..3600 s");
    const bool leftNeedsData = config.leftSource == live::LiveConfig::LeftSource::Port || config.leftSource == live::LiveConfig::LeftSource::Osc;
    if (cl.has("--data-timeout") && config.source == live::LiveConfig::Source::Simulator && !leftNeedsData)
        throw UsageError("--data-timeout applies to --port and --osc-in (the simulator always sends)");

    const std::string calibrateOut = cl.value("--calibrate");
    if (cl.has("--calibrate") && calibrateOut.empty()) throw UsageError("--calibrate needs an output file");

    const std::string trainingLog = cl.value("--training-log");
    if (cl.has("--training-log")) {
        if (trainingLog.empty()) throw UsageError("--training-log needs a file");
        if (engine.scene != "braille") throw UsageError("--training-log is the braille scene's training: use --scene braille");
        for (const std::string& p : engine.parameters)
            if (p.rfind("braille.mode=", 0) == 0 && p != "braille.mode=training")
                throw UsageError("--training-log runs the training: it cannot go with --param " + p);
        engine.parameters.push_back("braille.mode=training");
    }

    // Every output is checked before any input is read or the source opened: a missing or
    // unwritable folder is an error now (exit 4), not after the reader answered every trial
    // or the session ran for an hour.
    const std::vector<std::pair<std::string, std::string>> outputs {
        {"--out", config.audioOut}, {"--tactile", config.tactileOut}, {"--log", config.logOut},
        {"--calibrate", calibrateOut}, {"--calibrate-mount", mountOut}, {"--calibrate-mount-left", leftMountOut}, {"--training-log", trainingLog},
        {"--arms-log", config.armsLog}, {"--status-file", cl.value("--status-file")}};
    for (const auto& [option, file] : outputs)
        if (cl.has(option)) checkOutputPath(option, file);
    checkDistinctOutputs(outputs);

    // Then the inputs: a file that cannot be read is exit 4, one that is not what it should be 3.
    if (cl.has("--mount")) {
        config.osc.mount = link::mountFromArgument(cl.value("--mount"));
        config.osc.mountGiven = true;
    }
    if (cl.has("--mount-left") || !leftMountOut.empty()) {   // (a calibration sees the sensor's own axes)
        config.leftOsc.mount = leftMountOut.empty() ? link::mountFromArgument(cl.value("--mount-left")) : link::Mount {};
        config.leftOsc.mountGiven = true;
    }
    if (cl.has("--calibration")) config.calibration = link::loadCalibration(cl.value("--calibration"));
    config.mapping = readMapOption(cl, engine);
    if (!config.audioIn.empty() && !cl.has("--sample-rate"))
        engine.sceneConfig.sampleRate = core::engineSampleRate(core::readWav(config.audioIn).sampleRate, config.audioIn);
    if (!config.audioStems.empty() && !cl.has("--sample-rate"))
        engine.sceneConfig.sampleRate = core::engineSampleRate(core::readWav(config.audioStems.front()).sampleRate, config.audioStems.front());

    // Spoken / braille-display copy of what stderr says (stderr itself is unchanged).
    std::unique_ptr<ReaderIo> voice;
    if (cl.has("--speak") || cl.has("--speech") || cl.has("--brlapi") || cl.has("--braille-display")) voice = std::make_unique<ReaderIo>(cl, true);
    else if (cl.has("--rate")) throw UsageError("--rate sets the speech rate: use it with --speak");
    if (cl.has("--keys") && cl.has("--training-log")) throw UsageError("--keys and --training-log both read stdin: choose one");
    config.panicGesture = cl.has("--panic-gesture");
    const int controlPort = cl.has("--control-in") ? static_cast<int>(cl.integer("--control-in", 0, 1, 65535)) : -1;

    if (cl.has("--tactors")) config.tactors = tactorConfig(cl, config.engine.motorCount);
    else if (anyTactorSetting(cl)) throw UsageError("the --tactor-* options set up --tactors DEVICE|jack: give it too");

    // Messages on the arm (docs/MQTT.md): the session owns the service; this says what it does.
    config.messages = readPlayMessages(cl, engine.scene, engine.parameters, engine.sceneConfig.resourceDir);
    if (command.reader && !(config.messages.on && !config.messages.config.topics.empty()))
        throw UsageError("read shows messages only: give a broker and topics (--mqtt HOST[:PORT] --messages TOPIC, or both in --mqtt-config)");
    std::unique_ptr<PlayMessages> messages;
    if (config.messages.on) {
        messages = std::make_unique<PlayMessages>();
        messages->setCommand(command.name);
    }
    readWebOptions(cl, config);   // the instrument as a web page (--web, --web-bind)
    if (cl.has("--web") && cl.has("--calibrate"))
        throw UsageError("--calibrate and --web both present the device calibration: use one (the page has it under 'Device calibration')");
    auto request = std::make_unique<PlayRequest>();
    request->config = std::move(config);
    request->seconds = seconds;
    request->dataTimeout = dataTimeout;
    request->leftNeedsData = leftNeedsData;
    request->mountOut = mountOut;
    request->leftMountOut = leftMountOut;
    request->calibrateOut = calibrateOut;
    request->trainingLog = trainingLog;
    request->controlPort = controlPort;
    request->controlListen = readControlListenOptions(cl);
    request->statusFile = cl.value("--status-file");
    request->voice = std::move(voice);
    request->messages = std::move(messages);
    return request;
}

/// The summary line of step 5 (docs/INTERFACES.md): the link's counters and what each part did.
std::string sessionSummary(live::LiveSession& session, const live::SourceReport& report,
                           live::CuePlayer* cues, std::uint32_t panics)
{
    std::string summary = live::summaryJson(session.summary());
    if (const live::MappingRig* m = session.mapping())
        summary.insert(summary.size() - 1, ",\"mapping_midi_events\":" + std::to_string(m->midiEvents()) + ",\"mapping_osc_messages\":" +
                                               std::to_string(m->oscMessages()) + ",\"mapping_dropped\":" + std::to_string(m->dropped()));
    if (const live::MappingRig* m = session.mapping(); m && m->stageCommands() > 0)   // "stage" destinations fired (docs/STAGE.md)
        summary.insert(summary.size() - 1, ",\"mapping_stage_commands\":" + std::to_string(m->stageCommands()));
    if (const live::MappingRig* m = session.mapping(); m && m->mqttMessages() > 0)   // "mqtt" destinations (docs/MQTT.md)
        summary.insert(summary.size() - 1, ",\"mapping_mqtt_messages\":" + std::to_string(m->mqttMessages()));
    if (panics > 0) {   // only after a panic (docs/STAGE.md)
        summary.insert(summary.size() - 1, ",\"panics\":" + std::to_string(panics));
        if (const live::MappingRig* m = session.mapping())   // note-offs, CC 120 and CC 123 the mapping's MIDI sent
            summary.insert(summary.size() - 1, ",\"panic_midi_events\":" + std::to_string(m->panicMidiEvents()));
    }
    summary.insert(summary.size() - 1, report.leftSummaryJson());
    summary.insert(summary.size() - 1, session.messagesJson());
    if (cues) summary.insert(summary.size() - 1, ",\"cue\":" + std::to_string(cues->current()) + ",\"cue_changes\":" + std::to_string(cues->changes()));
    summary.insert(summary.size() - 1, session.outputsJson());   // the tactor output's own counters (docs/TACTORS.md)
    return summary;
}

/// Steps 2–5 of a live session (`play`, `read`): the session and what the person running it
/// sees and does around it. Built once from the request (step 2: the session, its stage commands,
/// the guided procedures), then start() (the sources run, what they are said), run() (until
/// the time is up, the data never came, the recording ended, the scene failed, the training
/// ended or the user stopped it; one pass every 10 ms) and finish() (the files, the summary).
class LiveRun {
public:
    LiveRun(const CommandLine& cl, const LiveCommand& command, PlayRequest& request)
        : who_("armadillo " + std::string(command.name) + ": "), request_(request), config_(request.config), session_(config_),
          cues_(session_.cuePlayer())
    {
        shownCue_ = cues_ ? cues_->current() : -1;
        openStageCommands(cl);
        openProcedures();
        announceOutputs();
    }
    LiveRun(const LiveRun&) = delete;
    LiveRun& operator=(const LiveRun&) = delete;

    /// Step 3: the sources start; the mapping takes "set forward" from outside (kill -USR1).
    void start()
    {
        if (live::MappingRig* rig = session_.mapping()) forwardTarget().store(&rig->mapper());
        ::signal(SIGUSR1, onForwardSignal);
        session_.start();
        start_ = std::chrono::steady_clock::now();
        report_ = std::make_unique<live::SourceReport>(session_);   // what the sources say, in words (Live/Sources/SourceReport.h)
        for (const std::string& line : report_->startup()) std::cerr << who_ << line << "\n";
        announceWebPage(session_, who_);   // --web: the page's address (Cli/LiveOptions.h)
        // A progress line on a terminal (stderr only, so stdout keeps just the JSON summary), not
        // while a guided procedure prints its own instructions there.
        progress_ = ::isatty(STDERR_FILENO) == 1 && !calibration_ && mountCalibrations_.empty() && !training_;
        lineStart_ = progress_ ? "\r\033[K" : "";   // a message replaces the progress line
    }

    /// Step 4: one pass every 10 ms (or as the training's input comes) until something ends it.
    void run()
    {
        while (!interrupted()) {
            const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
            if (ended(elapsed)) break;
            showProgress(elapsed);
            if (!reportStage()) break;
            reportOutputs(elapsed);
            reportWebPage(session_, who_, lineStart_);
            writeStatus(elapsed);
            stepProcedures();
            if (training_) {
                if (trainingLog_ && elapsed - trainingAt_ >= 1.0) {   // the rows so far, under the log's own name
                    trainingAt_ = elapsed;
                    const std::string csv = brailleScene_->trainingLogCsv();   // (consumer side: its own lock)
                    trainingLog_->append(std::string_view(csv).substr(std::min(trainingWritten_, csv.size())));
                    trainingWritten_ = csv.size();
                }
                if (!stepTraining()) break;
            } else {
                std::this_thread::sleep_for(std::chrono::milliseconds(10));
            }
        }
        if (progress_) std::cerr << "\n";
    }

    /// Step 5: everything stops; the files the session was asked to write, then the summary line.
    int finish()
    {
        if (keys_) keys_->stop();
        if (controlIn_) controlIn_->stop();
        session_.stop();
        if (request_.dataTimeout > 0.0 && noData_.empty()) noData_ = silence(session_.summary().seconds);
        if (!noData_.empty()) {   // nothing was played: no file is written
            session_.discardRecordings();
            std::cout << live::summaryJson(session_.summary()) << "\n" << std::flush;
            throw core::IoError(noData_);
        }
        if (recordingEnded_)
            std::cerr << who_ << "the recording ended after " << session_.recordingSeconds() << " s (--loop plays it again and again)\n";
        const std::string trainingCsv = brailleScene_ ? brailleScene_->trainingLogCsv() : std::string();   // control has stopped
        session_.finish();   // the session's own files first: a failing training log must not lose them
        if (trainingLog_) {
            trainingLog_->append(std::string_view(trainingCsv).substr(std::min(trainingWritten_, trainingCsv.size())));
            trainingLog_->finish();
        }
        for (const std::string& line : session_.outputClosingLines()) std::cerr << who_ << line << "\n";   // a sound card that ran dry
        for (const auto& g : mountCalibrations_) g->finish();
        if (calibration_) {
            if (!calibration_->finished())
                std::cerr << "calibration stopped at step '" << link::CalibrationProcedure::stepName(calibration_->step())
                          << "'; that step and the later ones keep the starting calibration\n";
            link::saveCalibration(request_.calibrateOut, calibration_->result());
        }
        std::string summary = sessionSummary(session_, *report_, cues_, panicTotal());
        if (controlIn_) summary.insert(summary.size() - 1, controlIn_->summaryJson());   // (docs/SECURITY.md)
        std::cout << summary << "\n" << std::flush;
        return session_.engine().failed() ? int(core::kExitFailure) : int(core::kExitOk);
    }

private:
    struct ForwardOff {
        ~ForwardOff() { forwardTarget().store(nullptr); }
    };

    /// Stage commands (OSC control port, keys): panic and resume act on the engine at once
    /// (atomics, any thread); what happened is reported by reportStage().
    void onCommand(const core::StageCommand& c)
    {
        lastCommand_.store(static_cast<int>(c.kind));
        session_.stage().apply(c);   // the one switch (Live/Stage/Stage.h); acts at the next control step
    }

    /// Panics of the stage: commands, keys, the mapping and the gesture alike (a cue change does
    /// not bring the sound back).
    std::uint32_t panicTotal() { return session_.stage().panics(); }

    bool needsData() const { return config_.source != live::LiveConfig::Source::Simulator; }

    /// A port or OSC source (the right arm's, then the left arm's) that sent nothing in
    /// `seconds`, in words with what was heard; "" when every source that needs data sent some.
    std::string silence(double seconds) const
    {
        if (needsData() && session_.summary().packets == 0) return report_->noData(seconds);
        if (request_.leftNeedsData && report_->leftPackets() == 0) return report_->noData(seconds, true);
        return {};
    }

    void openStageCommands(const CommandLine& cl)
    {
        const auto handler = [this](const core::StageCommand& c) { onCommand(c); };
        if (cues_)
            std::cerr << who_ << "set list of " << cues_->cueCount() << " cues; cue 0 '" << cues_->cue(0).name << "' (" << cues_->cue(0).scene << ")\n";
        if (request_.controlPort > 0) {
            controlIn_ = std::make_unique<live::StageControlReceiver>(request_.controlPort, handler, request_.controlListen);   // IoError (exit 4) when taken
            if (!osc::isLoopbackAddress(controlIn_->boundAddress()) && request_.controlListen.allow.empty())
                std::cerr << who_ << "stage control on " << controlIn_->boundAddress() << " port " << controlIn_->port()
                          << " takes commands from anyone who reaches it (--control-allow limits who)\n";
            if (session_.showsMessages())   // /armadillo/message "text" [priority] (docs/MQTT.md)
                controlIn_->setTextHandler([s = &session_](const std::string& text, int priority) { s->offerMessage(text, priority); });
            controlIn_->start();
        }
        if (cl.has("--keys")) {
            keys_ = std::make_unique<live::KeyReader>(STDIN_FILENO, handler);
            keys_->start();
            std::cerr << who_ << "keys: p = panic, r = resume" << (cues_ ? ", n = next cue, b = previous cue, 0..9 = cue" : "") << "\n";
        }
    }

    /// The training, the messages, the device calibration and the mount calibrations.
    void openProcedures()
    {
        PlayMessages* messages = request_.messages.get();
        if (!request_.trainingLog.empty()) {
            brailleScene_ = dynamic_cast<braille::BrailleSceneControls*>(&session_.engine().scene());
            if (!brailleScene_) throw UsageError("--training-log needs the braille scene");
            session_.holdScene("the training (--training-log) reads in the braille scene");
            training_ = std::make_unique<TerminalTraining>(*brailleScene_, request_.voice.get());
            trainingLog_ = std::make_unique<core::RecordingFile>(request_.trainingLog);   // grows as answered (docs/SECURITY.md)
            if (!trainingLog_->keptAs().empty()) std::cerr << who_ << core::keptAsideNote(request_.trainingLog, trainingLog_->keptAs()) << "\n";
        }
        if (messages && request_.voice) messages->setMirror([v = request_.voice.get()](const std::string& line) { v->note(line); });   // --speak, --brlapi
        // --calibrate: the device calibration (procedures::DeviceCalibration, as `armadillo
        // calibrate` and the app's Calibration window present it), each step taken when it has enough data.
        if (!request_.calibrateOut.empty()) {
            calibration_ = std::make_unique<procedures::DeviceCalibration>();
            calibration_->begin(config_.calibration);
            sayCalibrationStep();
        }
    }

    void sayCalibrationStep() const
    {
        std::cerr << (calibration_->finished() ? std::string("calibration complete")
                                               : "calibration step " + std::to_string(calibration_->stepNumber()) + " (" +
                                                     link::CalibrationProcedure::stepName(calibration_->step()) + "): " + calibration_->instruction())
                  << "\n";
    }

    /// The sound card and the tactors, as opened; then the mount calibrations begin.
    void announceOutputs()
    {
        for (const std::string& line : session_.keptAside()) std::cerr << who_ << line << "\n";   // never half-replaced
        for (const std::string& line : session_.outputLines()) std::cerr << who_ << line << "\n";   // the sound card, the tactors
        if (!session_.soundCardWarning().empty())
            std::cerr << who_ << "no sound: " << session_.soundCardWarning() << " (--out FILE records the audio instead; --no-audio silences this message)\n";
        for (const auto& [out, left, option, arm] : {std::tuple {request_.mountOut, false, "--calibrate-mount", ""},
                                                     std::tuple {request_.leftMountOut, true, "--calibrate-mount-left", "left arm "}}) {
            if (out.empty() || !session_.enableSensorTap(left)) continue;
            mountCalibrations_.push_back(std::make_unique<GuidedMount>());
            GuidedMount& g = *mountCalibrations_.back();
            g.session = &session_;
            g.left = left;
            g.out = out;
            g.option = option;
            g.arm = arm;
            g.begin();
        }
    }

    /// The time is up, or a port or OSC source sent nothing within --data-timeout (said, with
    /// what was heard; exit 4), or the recording ended.
    bool ended(double elapsed)
    {
        if (request_.seconds > 0.0 && elapsed >= request_.seconds) return true;
        if (request_.dataTimeout > 0.0 && elapsed >= request_.dataTimeout) {
            noData_ = silence(request_.dataTimeout);
            if (!noData_.empty()) return true;
        }
        if (session_.recordingEnded()) {
            recordingEnded_ = true;
            return true;
        }
        return false;
    }

    void showProgress(double elapsed)
    {
        if (!progress_ || elapsed - shownAt_ < 0.5) return;
        shownAt_ = elapsed;
        const live::SessionSummary now = session_.summary();
        const double seconds = request_.seconds;
        char line[160];
        std::snprintf(line, sizeof line, "\r\033[K%7.1f s%s  packets %llu  bad %llu  resyncs %llu  reconnects %llu  link %s", elapsed,
                      seconds > 0.0 ? (" of " + std::to_string(static_cast<long>(std::ceil(seconds)))).c_str() : "",
                      static_cast<unsigned long long>(now.packets), static_cast<unsigned long long>(now.badPackets),
                      static_cast<unsigned long long>(now.resyncs), static_cast<unsigned long long>(now.reconnects),
                      session_.connected() ? (now.packets > 0 ? "up" : "waiting for data") : "down, reconnecting");
        std::cerr << line << std::flush;
    }

    /// Cues, panics and a failed scene, as they happen. False: the scene failed (stop).
    bool reportStage()
    {
        engine::Engine& engine = session_.engine();
        if (cues_ && cues_->current() != shownCue_) {
            shownCue_ = cues_->current();
            const live::Cue& q = cues_->cue(shownCue_);
            std::cerr << lineStart_ << who_ << "cue " << shownCue_ << " '" << q.name << "' (" << q.scene << ")\n";
        }
        const bool panicked = session_.stage().panicked();
        if (const std::uint32_t n = panicTotal(); n != shownPanics_ || panicked != shownPanicked_) {
            const int k = lastCommand_.exchange(-1);
            const std::uint32_t mapped = session_.mappingPanics();   // a mapping's "stage": "panic"
            const bool byMapping = mapped != shownMappingPanics_;
            shownMappingPanics_ = mapped;
            const std::uint64_t fromPage = session_.webServer() ? session_.webServer()->counters().stageCommands : 0;   // --web
            const bool byPage = fromPage != shownPageCommands_;
            shownPageCommands_ = fromPage;
            if (n != shownPanics_)
                std::cerr << lineStart_ << who_ << "PANIC ("
                          << (k == static_cast<int>(core::StageCommand::Kind::Panic) ? "command" : byMapping ? "mapping" : byPage ? "web page" : "gesture")
                          << "): all sound and every motor off; resume with r or /armadillo/resume\n";
            else if (!panicked)
                std::cerr << lineStart_ << who_ << "resumed: scene '" << engine.config().scene << "' again\n";
            shownPanics_ = n;
            shownPanicked_ = panicked;
        }
        if (engine.failed()) {   // the scene threw: its motors are off; stop and say so
            std::cerr << who_ << "the scene failed and was stopped (motors off): " << engine.failure() << "\n";
            return false;
        }
        return true;
    }

    /// The device going away (once; the link keeps reconnecting), what the sources report, and
    /// a sound card or tactor output that stopped.
    void reportOutputs(double elapsed)
    {
        const std::string e = session_.lastError();
        if (!e.empty() && e != shownError_) {
            std::cerr << lineStart_ << who_ << e << "\n";
            if (request_.voice) request_.voice->status(e);
        }
        shownError_ = e;
        for (const std::string& line : report_->poll(elapsed)) std::cerr << lineStart_ << who_ << line << "\n";
        for (const auto& g : mountCalibrations_) g->step();
        if (request_.messages) request_.messages->poll(session_, std::cerr, lineStart_);
        if (controlIn_) for (const std::string& line : controlIn_->takeRefusals()) std::cerr << lineStart_ << who_ << line << "\n";
        for (const std::string& line : session_.outputFailures()) std::cerr << lineStart_ << who_ << line << "\n";   // once each
    }

    /// --status-file: the summary so far and the latency, once a second, replaced whole.
    void writeStatus(double elapsed)
    {
        if (request_.statusFile.empty() || elapsed - statusAt_ < 1.0) return;
        statusAt_ = elapsed;
        std::string status = sessionSummary(session_, *report_, cues_, panicTotal());
        if (controlIn_) status.insert(status.size() - 1, controlIn_->summaryJson());
        const link::LatencySummary l = session_.latency();
        char more[160];
        std::snprintf(more, sizeof more, ",\"seconds\":%.1f,\"latency_p50_us\":%.0f,\"latency_p99_us\":%.0f,\"latency_max_us\":%.0f", elapsed,
                      l.p50Us, l.p99Us, l.maxUs);
        status.insert(status.size() - 1, more);
        try {
            core::writeFileAtomically(request_.statusFile, status + "\n");
        } catch (const core::IoError& e) {   // said once; the session plays on
            if (!statusFailed_) std::cerr << lineStart_ << who_ << e.what() << "\n";
            statusFailed_ = true;
        }
    }

    void stepProcedures()
    {
        if (calibration_ && calibration_->running()) {
            link::RawPacket p;
            while (session_.rawPackets()->pop(p)) calibration_->offer(p.t, p.counts);
            calibration_->drain();
            if (std::string why; calibration_->ready() && calibration_->next(why)) sayCalibrationStep();
        }
    }

    /// One step of the terminal training (waits up to 10 ms for input). False: it ended.
    bool stepTraining()
    {
        ReaderIo* voice = request_.voice.get();
        if (!training_->step(10)) {
            std::cerr << "braille training complete: " << brailleScene_->trainingCorrect() << " of " << brailleScene_->trainingTrialCount() << " right\n";
            if (voice)
                voice->status("braille training complete: " + std::to_string(brailleScene_->trainingCorrect()) + " of " +
                              std::to_string(brailleScene_->trainingTrialCount()) + " right");
            return false;
        }
        if (training_->exhausted()) {
            std::cerr << "braille training: no more answers (stdin ended) with " << brailleScene_->trainingTrialCount() - brailleScene_->trainingTrial()
                      << " of " << brailleScene_->trainingTrialCount() << " trials unanswered; " << brailleScene_->trainingCorrect() << " right so far\n";
            return false;
        }
        return true;
    }

    const std::string who_;   // what stderr's lines start with
    PlayRequest& request_;
    live::LiveConfig& config_;
    live::LiveSession session_;
    live::CuePlayer* cues_ = nullptr;
    std::atomic<int> lastCommand_ {-1};
    std::unique_ptr<live::StageControlReceiver> controlIn_;
    std::unique_ptr<live::KeyReader> keys_;
    std::unique_ptr<TerminalTraining> training_;
    std::unique_ptr<core::RecordingFile> trainingLog_;   // --training-log
    std::size_t trainingWritten_ = 0;
    double trainingAt_ = -1.0;
    braille::BrailleSceneControls* brailleScene_ = nullptr;
    std::unique_ptr<procedures::DeviceCalibration> calibration_;
    std::vector<std::unique_ptr<GuidedMount>> mountCalibrations_;   // the right arm's, the left arm's
    ForwardOff forwardOff_;
    std::unique_ptr<live::SourceReport> report_;
    std::chrono::steady_clock::time_point start_;
    bool progress_ = false;
    const char* lineStart_ = "";
    double shownAt_ = -1.0, statusAt_ = -1.0;
    bool statusFailed_ = false;
    int shownCue_ = -1;
    std::uint32_t shownPanics_ = 0, shownMappingPanics_ = 0;
    std::uint64_t shownPageCommands_ = 0;   // stage commands the web page sent, as last seen
    bool shownPanicked_ = false;
    std::string shownError_, noData_;
    bool recordingEnded_ = false;
};

} // namespace

int runLiveSession(const CommandLine& cl, const LiveCommand& command)
{
    const std::unique_ptr<PlayRequest> request = readPlayRequest(cl, command);   // step 1
    installInterruptHandlers();
    LiveRun run(cl, command, *request);   // step 2
    run.start();                           // step 3
    run.run();                             // step 4
    return run.finish();                   // step 5
}

int runPlay(const Arguments& args)
{
    return guarded("play", [&] {
        CommandLine cl(
            "play", "--scene SCENE (--port NAME | --simulate [--motion FILE] | --osc-in PORT) [options]",
            "The live engine, headless: sensor packets from a serial device (thesis protocol), the built-in\n"
            "simulated forearm or OSC (/armadillo/imu, /armadillo/orientation, or a phone app or NGIMU: see\n"
            "docs/SENSORS.md) go through calibration,\n"
            "fusion and the scene; each sensor packet is answered with its motor packet at once. Runs for\n"
            "--seconds or until SIGINT/SIGTERM, turns every motor off, then prints one JSON line:\n"
            "{\"packets\":…,\"bad_packets\":…,\"resyncs\":…,\"reconnects\":…,\"rate_hz\":…}.\n"
            "Audio goes to --out, or else to the sound card (ALSA 'default', or --audio-device); on a machine\n"
            "without one the session runs silently and says so once (--no-audio: silence, no message).\n"
            "A lost serial port is reopened on its own (backoff up to 0.25 s); a port missing at start is\n"
            "an error (exit 4), and so is a port or OSC source that sends no sensor data (--data-timeout).\n"
            "Every output's folder is checked before the session starts; on failure no output is written.",
            playOptionSpecs());
        if (!cl.parse(args)) return 0;
        return runLiveSession(cl, {"play", false});
    });
}

} // namespace armadillo::cli
