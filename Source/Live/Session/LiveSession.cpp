#include "Live/Session/LiveSession.h"
#include "Core/AtomicFile.h"
#include "Audio/SequencerOut.h"
#include "Braille/BrailleScene.h"
#include "Live/Sources/SourceRegistry.h"
#include "Live/Outputs/MappingRig.h"
#include "Audio/SoundCard.h"
#include "Core/Errors.h"
#include "Link/Motion.h"
#include "Osc/OscIo.h"
#include "Live/Outputs/SessionWriters.h"
#include "Live/Session/SessionWebView.h"
#include "Fusion/ArmTracker.h"
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace armadillo::live {

namespace {

/// The right (or left) arm's port as `armadillo play` asks for it: a port opened now, or the
/// simulated forearm moving as its motion file says (default: the wandering arm, the left one
/// with the next seed), its board thread one step below the link's priority.
ForearmPortRequest forearmRequest(const LiveConfig& c, bool left)
{
    ForearmPortRequest r;
    r.simulate = left ? c.leftSource == LiveConfig::LeftSource::Simulator : c.source == LiveConfig::Source::Simulator;
    r.port = left ? c.leftPort : c.port;
    r.baud = left ? c.leftBaud : c.baud;
    const std::string& motionFile = left ? c.leftMotionFile : c.motionFile;
    if (r.simulate && !motionFile.empty()) r.motion = std::make_shared<link::FileMotion>(motionFile);
    r.seed = c.engine.sceneConfig.seed + (left ? 1 : 0);
    r.simulatorBaud = c.simulatorBaud;
    r.simulatorPriority = c.link.realtimePriority > 1 ? c.link.realtimePriority - 1 : 0;
    return r;
}

} // namespace

std::string summaryJson(const SessionSummary& s)
{
    if (!s.oscJson.empty()) {   // OSC sources add what their input counted, as one nested object
        SessionSummary plain = s;
        plain.oscJson.clear();
        std::string j = summaryJson(plain);
        j.insert(j.size() - 1, ",\"osc\":{" + s.oscJson + "}");
        return j;
    }
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "{\"packets\":%llu,\"bad_packets\":%llu,\"resyncs\":%llu,\"reconnects\":%llu,\"rate_hz\":%.1f,"
                  "\"gaps\":%llu,\"longest_gap_s\":%.3f}",
                  static_cast<unsigned long long>(s.packets), static_cast<unsigned long long>(s.badPackets),
                  static_cast<unsigned long long>(s.resyncs), static_cast<unsigned long long>(s.reconnects),
                  std::isfinite(s.rateHz) ? s.rateHz : 0.0, static_cast<unsigned long long>(s.gaps),
                  std::isfinite(s.longestGap) ? s.longestGap : 0.0);
    std::string out = buf;
    if (s.v2) {
        std::snprintf(buf, sizeof buf, ",\"v2\":true,\"seq_gaps\":%llu,\"crc_failures\":%llu}",
                      static_cast<unsigned long long>(s.seqGaps), static_cast<unsigned long long>(s.crcFailures));
        out.pop_back();   // the closing brace
        out += buf;
    }
    return out;
}

const std::vector<std::string>& sessionLogHeader()
{
    static const std::vector<std::string> h {"t",      "raw_ax", "raw_ay", "raw_az", "raw_gx", "raw_gy", "raw_gz", "raw_mx",
                                             "raw_my", "raw_mz", "gx",     "gy",     "gz",     "ax",     "ay",     "az",
                                             "mx",     "my",     "mz",     "qw",     "qx",     "qy",     "qz",
                                             "bad_packets", "resyncs", "reconnects", "gaps", "longest_gap_s"};
    return h;
}

LiveSession::LiveSession(const LiveConfig& config) : config_(config)
{
    // In this order: a bad scene, set list, route or mapping is refused before any port is
    // opened; the tactor output last, so a missing device leaves nothing open.
    buildEngine();
    sourceKind_ = config_.source == LiveConfig::Source::Osc ? live::SourceKind::Osc : live::SourceKind::Device;
    openMessagesAndMapping();
    openRightSource();
    openLeftArm();
    openRecordings();
    openAudio();
    if (config_.web.on) {   // bound now: a port that is taken is an error before anything runs
        webView_ = std::make_unique<SessionWebView>(*this);
        web_ = std::make_unique<web::WebServer>(config_.web, *webView_);
    }
}

/// The engine the loop runs (the scene, or the navigation scene of a walk; a monitor under a set
/// list's cues) and, with two arms, the left arm's tracker.
void LiveSession::buildEngine()
{
    const bool twoArms = config_.leftSource != LiveConfig::LeftSource::None;
    if (twoArms) {
        // The loop's engine hears both arms (Engine::control(right, left, …)); with a set list
        // every cue's engine does.
        config_.engine.twoArms = config_.setList.empty();
        leftArm_ = &instrument_.leftArm();   // the instrument's left arm, on from the start
        leftArm_->setOn(true);
    }
    if (!config_.setList.empty()) {   // every cue prepared now; the loop's own engine only tracks the arm
        stage_.replace(std::make_unique<live::CuePlayer>(live::loadSetList(config_.setList), config_.engine.sceneConfig, config_.engine.motorCount,
                                                         twoArms, config_.engine.motorGain));   // the reader's touch profile for every cue
        cues_ = stage_.cues();   // the stage runs it from here on (Live/Stage/Stage.h)
        config_.engine.scene = "monitor";
        config_.engine.parameters.clear();
    }
    {
        auto slot = std::make_unique<live::EngineSlot>();
        if (config_.walk.route) {   // the walk's position source now (IoError: gpsd not reachable, the port taken)
            if (twoArms || cues_) throw core::InputError("", 0, "", "scene '" + config_.engine.scene + "' plays alone: not with a set list or two arms");
            navigation_ = &instrument_.navigation();
            navigation_->open(config_.walk.route, config_.walk.positions, config_.walk.where);
        }
        slot->engine = navigation_ ? std::make_unique<engine::Engine>(config_.engine, navigation::makeNavigationScene(*navigation_->route(), navigation_->link(),
                                                                                                                 config_.walk.options))
                                   : std::make_unique<engine::Engine>(config_.engine); // InputError for an unknown scene
        slot->sceneName = config_.engine.scene;
        engine_.store(slot->engine.get(), std::memory_order_release);
        loop_.replace(std::move(slot));   // nothing runs yet
    }
}

/// Messages, the fixed OSC stream or the mapping with its MIDI, OSC, MQTT and stage sinks.
void LiveSession::openMessagesAndMapping()
{
    if (config_.messages.on) {   // InputError for a bad configuration; nothing connects before start()
        messages_ = &instrument_.messages().open(config_.messages.config, config_.messages.options);   // through the registry
        messageScene_ = dynamic_cast<braille::BrailleSceneControls*>(&loopEngine().scene());
        if (showsMessages() && !messageScene_) throw core::InputError("--messages", 0, "", "messages are read in Arm Braille: use the braille scene");
    }
    if (!config_.oscOut.empty()) {
        osc::HostPort hp;
        try {
            hp = osc::parseHostPort(config_.oscOut);
        } catch (const std::invalid_argument& e) {
            throw core::InputError("--osc-out", 0, "", e.what());
        }
        if (!config_.mapping) oscOut_ = std::make_unique<osc::OscSender>(hp);   // with --map only what the mapping names leaves
    }
    if (config_.mapping) {
        live::MappingRigOptions options;
        options.oscDefault = config_.oscOut;
        options.sourceName = config_.mappingName;
        options.forwardDeg = config_.forwardDeg;
        mapping_ = std::make_unique<live::MappingRig>(*config_.mapping, loopEngine(), options);   // for the scene that plays
        mapping_->setStageSink(&LiveSession::applyStage, this);
        if (messages_) mapping_->setMqttSink(&LiveSession::publishMapped, this);   // the arm as a remote (docs/MQTT.md)
        if (!config_.midiOut.empty()) {
            midiOut_ = std::make_unique<audio::SequencerOut>(config_.midiOut);   // IoError naming the cause (exit 4)
            mapping_->setMidiSink([](void* ctx, const mapping::MidiEvent& e) { static_cast<audio::SequencerOut*>(ctx)->send(e.bytes.data(), e.size); },
                                  midiOut_.get());
        }
    } else if (!config_.midiOut.empty()) {
        throw core::InputError("--midi-out", 0, "", "MIDI out follows a mapping: give --map PRESET|FILE (e.g. --map classic)");
    }
}

/// The right arm's source, through the registry: a port or the simulated forearm read by a
/// device link, or an OSC sender (UDP or SLIP serial).
void LiveSession::openRightSource()
{
    ArmSourceDescription d;
    ArmSourceHandlers h;
    if (config_.source == LiveConfig::Source::Osc) {
        d.kind = config_.oscSerialPort.empty() ? ArmSourceDescription::Kind::OscUdp : ArmSourceDescription::Kind::OscSerial;
        d.oscPort = config_.oscInPort;
        d.oscSerial = osc::OscSerialSource {config_.oscSerialPort, config_.oscSerialBaud};
        d.osc = config_.osc;
        h.onImu = [this](const core::ImuSample& s) { control(s.t, nullptr, &s, nullptr); };
        h.onOrientation = [this](double t, const Eigen::Quaterniond& q) { control(t, nullptr, nullptr, &q); };
    } else {   // a port fails early with its own message (exit 4); later losses reconnect in the link
        d.forearm = forearmRequest(config_, false);
        d.link = config_.link;
        h.onPacket = [this](const link::SensorCounts& counts, double t) { return control(t, &counts, nullptr, nullptr); };
    }
    right_ = &instrument_.source(sourceKind_ == live::SourceKind::Osc ? Instrument::Feed::Osc : Instrument::Feed::Device).open(d, std::move(h));
    link_ = right_->link();
    oscIn_ = right_->osc();
    if (oscIn_ && navigation_ && navigation_->datagramTap()) oscIn_->setDatagramTap(navigation_->datagramTap());   // a phone's gps on the arm's port
}

/// Two arms: the left arm's source (a port, the simulated forearm or an OSC sender) and its log.
void LiveSession::openLeftArm()
{
    if (config_.leftSource == LiveConfig::LeftSource::None) return;
    ArmSourceDescription d;
    ArmSourceHandlers h;
    if (config_.leftSource == LiveConfig::LeftSource::Osc) {
        // An OSC sender as the left arm: its own dialect detection and mount; its samples (or
        // its own orientations) into the left arm's mailbox. It has no motors.
        d.kind = ArmSourceDescription::Kind::OscUdp;
        d.oscPort = config_.leftOscInPort;
        d.osc = config_.leftOsc;
        h.onImu = [this](const core::ImuSample& s) { leftArm_->input().pushImu(s); };
        h.onOrientation = [this](double t, const Eigen::Quaterniond& q) { leftArm_->input().storeOrientation(t, q); };
    } else {   // a port or the simulated left forearm
        // The left arm's packets: calibrated with its own calibration, into its mailbox; answered
        // with the left arm's latest motor levels (its own tactile engine and safety stage).
        d.forearm = forearmRequest(config_, true);
        d.link = config_.link;
        h.onPacket = [this](const link::SensorCounts& counts, double t) {
            if (motorsOff_.load(std::memory_order_acquire)) return core::MotorLevels {};
            leftArm_->input().pushImu(config_.leftCalibration.apply(t, counts));
            return leftLevels_.load();
        };
    }
    left_ = &instrument_.source(Instrument::Feed::Left).open(d, std::move(h));   // IoError when a port is missing or taken
    leftLink_ = left_->link();
    leftOscIn_ = left_->osc();
    if (!config_.armsLog.empty())
        armsLog_ = std::make_unique<StreamingCsvWriter>(config_.armsLog, std::vector<std::string> {"t", "qw", "qx", "qy", "qz", "left_qw", "left_qx", "left_qy", "left_qz"});
}

/// The session log, the tactile CSV and the recording the scene listens to.
void LiveSession::openRecordings()
{
    if (!config_.logOut.empty()) log_ = std::make_unique<StreamingCsvWriter>(config_.logOut, sessionLogHeader());
    if (!config_.tactileOut.empty()) {
        std::vector<std::string> h {"t"};
        for (int m = 1; m <= config_.engine.motorCount; ++m) h.push_back("m" + std::to_string(m));
        tactile_ = std::make_unique<StreamingCsvWriter>(config_.tactileOut, h);
    }
    if (!config_.audioIn.empty() || !config_.audioStems.empty()) {
        recordingIsStems_ = !config_.audioStems.empty();
        const std::string& name = recordingIsStems_ ? config_.audioStems.front() : config_.audioIn;
        if (!cues_ && !loopEngine().listensToAudio())
            throw core::InputError(name, 0, "", "--audio-in: scene '" + config_.engine.scene + "' does not listen to audio (score, audio-touch and layered-keyboard do)");
        if (config_.audioStems.size() > static_cast<std::size_t>(LiveConfig::kMaxAudioInChannels))
            throw core::InputError(name, 0, "", "at most " + std::to_string(LiveConfig::kMaxAudioInChannels) + " stems");
        recording_ = recordingIsStems_ ? core::readWavStems(config_.audioStems) : core::readWav(config_.audioIn); // InputError names a bad file
        if (recording_.channels.empty() || recording_.frames() == 0) throw core::InputError(name, 0, "", "--audio-in: the recording holds no audio");
        if (std::fabs(recording_.sampleRate - config_.engine.sceneConfig.sampleRate) > 0.5)
            throw core::InputError(name, 0, "", "--audio-in: the recording's sample rate (" + std::to_string(static_cast<long>(recording_.sampleRate)) +
                                              " Hz) differs from the engine's (" +
                                              std::to_string(static_cast<long>(config_.engine.sceneConfig.sampleRate)) +
                                              " Hz); give --sample-rate to match it");
        recordingSilence_.assign(8192, 0.0f);
    }
}

/// Where the sound goes (a WAV file or a sound card) and the tactor output.
void LiveSession::openAudio()
{
    if (!config_.audioOut.empty()) {
        wav_ = std::make_unique<StreamingWavWriter>(config_.audioOut, config_.engine.sceneConfig.sampleRate, config_.audioFloat);
    } else if (!config_.soundCard.empty()) {
        try {
            soundCard_ = std::make_unique<audio::SoundCard>(config_.soundCard, config_.engine.sceneConfig.sampleRate);
        } catch (const core::IoError& e) {
            if (!config_.soundCardOptional) throw;
            soundCardWarning_ = e.what();
        }
    }
    // Last, so a bad tactor setting or a missing device leaves nothing open (IoError/InputError).
    if (!config_.tactors.device.empty()) {
        tactors_ = std::make_unique<live::TactorOutput>(config_.tactors);
        // The scene's sound is handed over sample for sample: it needs the scene's audio at the
        // output's rate (no resampling on the way).
        if (tactors_->wantsSound() && !wav_ && !soundCard_)
            throw core::IoError("--tactor-sound: the voice coil takes the scene's sound, and this session has none (no --out, no sound card)");
        if (tactors_->wantsSound() && std::abs(tactors_->sampleRate() - config_.engine.sceneConfig.sampleRate) > 0.5)
            throw core::IoError("--tactor-sound: the tactor output runs at " + std::to_string(static_cast<int>(tactors_->sampleRate())) + " Hz and the scene at "
                                 + std::to_string(static_cast<int>(config_.engine.sceneConfig.sampleRate)) + " Hz: give --sample-rate "
                                 + std::to_string(static_cast<int>(tactors_->sampleRate())));
    }
}

std::string LiveSession::sceneChangeRefusal() const
{
    if (cues_) return "a set list plays: choose one of its cues";
    if (navigation_) return "a walk plays the navigation scene";
    if (mapping_) return "the mapping (--map) is bound to the scene the session began with";
    if (messages_) return "the messages are read in the braille scene";
    if (!recording_.channels.empty()) return "--audio-in feeds the scene the session began with";
    if (!sceneHeld_.empty()) return sceneHeld_;
    if (retiredEngines_.size() >= kMaxSceneChanges)
        return "this session changed its scene " + std::to_string(kMaxSceneChanges) + " times: start it again to change it more";
    return {};
}

std::vector<std::string> LiveSession::sceneChoices(std::string& why)
{
    std::lock_guard<std::mutex> lock(sceneMutex_);
    why = sceneChangeRefusal();
    return why.empty() ? engine::sceneNames() : std::vector<std::string> {};
}

void LiveSession::holdScene(const std::string& why)
{
    std::lock_guard<std::mutex> lock(sceneMutex_);
    sceneHeld_ = why;
}

std::string LiveSession::chooseScene(const std::string& name)
{
    std::lock_guard<std::mutex> lock(sceneMutex_);
    if (std::string why = sceneChangeRefusal(); !why.empty()) return why;
    if (!running_.load(std::memory_order_acquire)) return "the session does not run";
    const std::vector<std::string>& names = engine::sceneNames();
    if (std::find(names.begin(), names.end(), name) == names.end()) return "no scene '" + name + "' (docs/INTERFACES.md lists them)";
    if (auto given = loop_.takeRetired()) retiredEngines_.push_back(std::move(given));   // kept: another thread may still read it
    if (!loop_.canOffer()) return "the previous scene change has not taken effect yet: try again";
    engine::EngineConfig c = config_.engine;
    c.scene = name;
    c.parameters.clear();   // the session's --param settings were the first scene's
    auto slot = std::make_unique<live::EngineSlot>();
    try {
        slot->engine = std::make_unique<engine::Engine>(c);   // InputError for an unknown scene: nothing changes
    } catch (const std::exception& e) {
        return e.what();
    }
    slot->sceneName = name;
    if (!loop_.offer(slot)) return "the previous scene change has not taken effect yet: try again";
    return {};   // the control step takes it at its next step (ControlLoop: the scene starts afresh)
}

LiveSession::~LiveSession()
{
    try {
        stop();
    } catch (...) {
    }
}

core::MotorLevels LiveSession::control(double t, const link::SensorCounts* counts, const core::ImuSample* imu, const Eigen::Quaterniond* q)
{
    if (motorsOff_.load(std::memory_order_acquire)) {
        if (zeroPacketT_.load(std::memory_order_relaxed) < 0.0) zeroPacketT_.store(t, std::memory_order_relaxed);
        zeroPacketsSent_.fetch_add(1, std::memory_order_release);
        if (tactors_) tactors_->push(t, core::MotorLevels {});
        return core::MotorLevels {};
    }
    double dt = lastT_ < 0.0 ? 0.0 : t - lastT_;
    // A source that went quiet (unplug, stall): forget patterns rather than resume mid-gesture.
    if (dt > 0.25) {
        loopEngine().allOff();
        if (cues_) sounding().allOff();
    }
    if (!link_ && dt > 0.0 && sourceGaps_.step(dt)) {
        oscGaps_.store(sourceGaps_.count(), std::memory_order_relaxed);
        oscLongestGap_.store(sourceGaps_.longest(), std::memory_order_relaxed);
    }
    lastT_ = t;
    if (firstT_.load(std::memory_order_relaxed) < 0.0) firstT_.store(t, std::memory_order_relaxed);
    latestT_.store(t, std::memory_order_relaxed);

    // The sample goes through the source's mailbox into the live rig's control step, as in the
    // plugin; here the source's own thread runs the step at once, so a motor packet leaves
    // microseconds after its sensor packet arrived.
    core::ImuSample calibrated;
    live::LiveInput& mailbox = loop_.input(sourceKind_);
    if (counts) {
        calibrated = config_.calibration.apply(t, *counts);
        mailbox.pushImu(calibrated);
    } else if (imu) {
        calibrated = *imu;
        mailbox.pushImu(calibrated);
    } else {
        mailbox.storeOrientation(t, *q);
    }
    // The stage first (Live/Stage/Stage.h): cue requests, panic and resume from every place that makes
    // them (keys, the control port, the mapping), applied at this step as the plugin's block does.
    // A panic that starts silences what the mapping sent: its sounding notes end and CC 120 +
    // CC 123 go out on all 16 channels, and it sends nothing more until resume (Instrument.h).
    if (instrument_.beginStage().silenceMapping && mapping_) mapping_->panic(t);
    live::ControlStep step;
    step.source = sourceKind_;
    step.transport.valid = true;
    step.transport.playing = true;
    step.transport.seconds = t;
    step.transport.bpm = config_.bpm;
    step.transport.ppq = t * config_.bpm / 60.0;
    step.dt = dt;
    step.panicGesture = config_.panicGesture;
    // The instrument's step: the left arm (its samples since the last step through its own
    // tracker, or none with one arm), the stage's cues and panic (a gesture panic is the stage's
    // too, held until resume), and what the step leaves for the rest (the status, the web page,
    // Pure Data): the frame with the levels that went out, and the scene's gestures.
    const Instrument::Stepped stepped = instrument_.step(step, t, true);
    const live::ControlResult& result = stepped.result;
    const core::ArmState* leftArm = stepped.leftArm;
    if (leftArm != nullptr && leftArm->valid) leftPose_.store(leftArm->features.pose);
    if (result.swapped && !cues_) engine_.store(instrument_.runner().running(), std::memory_order_release);   // a scene change took over
    const core::ArmState& arm = result.arm;
    const core::MotorLevels levels = result.levels;
    if (leftArm != nullptr) {
        leftLevels_.store(cues_ ? cues_->leftLevels() : loopEngine().leftLevels());
        if (armsLog_) {
            LogRow row;
            row.count = 9;
            const Eigen::Quaterniond qr = arm.valid ? arm.q : Eigen::Quaterniond::Identity(), ql = leftArm->valid ? leftArm->q : Eigen::Quaterniond::Identity();
            const double v[9] = {t, qr.w(), qr.x(), qr.y(), qr.z(), ql.w(), ql.x(), ql.y(), ql.z()};
            for (int i = 0; i < 9; ++i) row.v[static_cast<std::size_t>(i)] = v[i];
            armsLog_->push(row);
        }
    }
    if (tactors_) tactors_->push(t, levels);   // the same levels as the device's packet, at once

    if (log_) {
        LogRow row;
        row.count = 28;
        row.v[0] = t;
        for (int i = 0; i < 9; ++i) row.v[static_cast<std::size_t>(1 + i)] = counts ? (*counts)[static_cast<std::size_t>(i)] : core::kNaN;
        const Eigen::Vector3d* vs[3] = {&calibrated.gyro, &calibrated.accel, &calibrated.mag};
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < 3; ++i) row.v[static_cast<std::size_t>(10 + 3 * k + i)] = (*vs[k])[i];
        const bool haveQ = arm.valid;
        row.v[19] = haveQ ? arm.q.w() : core::kNaN;
        row.v[20] = haveQ ? arm.q.x() : core::kNaN;
        row.v[21] = haveQ ? arm.q.y() : core::kNaN;
        row.v[22] = haveQ ? arm.q.z() : core::kNaN;
        const SessionSummary link = linkCounters();
        row.v[23] = static_cast<double>(link.badPackets);
        row.v[24] = static_cast<double>(link.resyncs);
        row.v[25] = static_cast<double>(link.reconnects);
        row.v[26] = static_cast<double>(link.gaps);
        row.v[27] = link.longestGap;
        log_->push(row);
    }
    if (tactile_) {
        LogRow row;
        row.count = 1 + config_.engine.motorCount;
        row.v[0] = t;
        for (int m = 0; m < config_.engine.motorCount; ++m) row.v[static_cast<std::size_t>(1 + m)] = levels[static_cast<std::size_t>(m)];
        tactile_->push(row);
    }
    if (oscOut_) {
        if (arm.valid) {
            oscOut_->sendOrientation(arm.q);
            oscOut_->sendPose(arm.features.pose);
        }
        oscOut_->sendGyro(arm.gyro);
        oscOut_->sendMotors(levels, config_.engine.motorCount);
    }
    if (oscOut_)
        for (int i = 0; i < published_.stepGestureCount(); ++i) oscOut_->sendGesture(published_.stepGestures()[i].name);
    if (stepped.silenceMapping && mapping_) mapping_->panic(t);   // the panic gesture at this step
    // In panic only the stage-command mappings run (a mapped resume), nothing else is sent.
    if (mapping_ && result.ran) mapping_->step(instrument_.mappingInput(stepped, t), engine());
    return levels;
}

void LiveSession::applyStage(void* self, const mapping::StageEvent& e) noexcept
{
    auto& s = *static_cast<LiveSession*>(self);
    if (e.command.kind == core::StageCommand::Kind::Panic) s.mappingPanics_.fetch_add(1, std::memory_order_relaxed);
    s.stage_.apply(e.command);   // acts at the next step, as every other stage command does
}

void LiveSession::renderBlock(float* left, float* right, int n) noexcept
{
    renderScene(left, right, n);
    // A voice coil handed the scene's sound (`--tactor-sound`) gets what was just rendered.
    if (tactors_ && tactors_->wantsSound()) tactors_->pushSound(left, right, n);
}

void LiveSession::renderScene(float* left, float* right, int n) noexcept
{
    if (cues_ && recording_.channels.empty()) {
        cues_->renderAudio(left, right, n);
        return;
    }
    engine::Engine* const plays = engine_.load(std::memory_order_acquire);   // a scene change takes effect here at the next block
    if (recording_.channels.empty()) {
        plays->renderAudio(left, right, n);
        return;
    }
    // The recording's next n frames (silence after its end: the input stays connected), heard
    // by the scene first, in stretches that end where the recording ends, then played out under
    // the scene's own sound.
    // A recording is heard as its first two channels (one if mono) and played out as them; stems
    // are heard one channel each and played out as their sum (the mix they came from).
    const std::uint64_t frames = recording_.frames();
    const int channels = recordingIsStems_ ? static_cast<int>(recording_.channels.size()) : (recording_.channels.size() > 1 ? 2 : 1);
    std::array<const float*, LiveConfig::kMaxAudioInChannels> base {}, in {};
    for (int c = 0; c < channels; ++c) base[static_cast<std::size_t>(c)] = recording_.channels[static_cast<std::size_t>(c)].data();
    // Where frame `at` of the session falls in the recording (≥ frames: after its end).
    const bool loop = config_.audioInLoop;
    auto position = [&](std::uint64_t at) noexcept { return loop ? at % frames : at; };
    if (recordingAt_ == 0) {   // the recording itself: followed from its first sample
        if (cues_) cues_->processInput(base.data(), channels, 0);
        else plays->processInput(base.data(), channels, 0);
    }
    for (int done = 0; done < n;) {
        const std::uint64_t at = position(recordingAt_ + static_cast<std::uint64_t>(done));
        const bool inside = at < frames;
        const int len = inside ? static_cast<int>(std::min<std::uint64_t>(static_cast<std::uint64_t>(n - done), frames - at))
                               : std::min(n - done, static_cast<int>(recordingSilence_.size()));
        for (int c = 0; c < channels; ++c) in[static_cast<std::size_t>(c)] = inside ? base[static_cast<std::size_t>(c)] + at : recordingSilence_.data();
        if (cues_) cues_->processInput(in.data(), channels, len);
        else plays->processInput(in.data(), channels, len);
        done += len;
    }
    if (cues_) cues_->renderAudio(left, right, n);
    else plays->renderAudio(left, right, n);
    for (int i = 0; i < n; ++i) {
        const std::uint64_t at = position(recordingAt_ + static_cast<std::uint64_t>(i));
        if (at >= frames) break;
        float l = base[0][at], r = base[static_cast<std::size_t>(channels - 1)][at];
        if (recordingIsStems_) {
            l = 0.0f;
            for (int c = 0; c < channels; ++c) l += base[static_cast<std::size_t>(c)][at];
            r = l;
        }
        left[i] = std::clamp(left[i] + l, -1.0f, 1.0f);
        right[i] = std::clamp(right[i] + r, -1.0f, 1.0f);
    }
    recordingAt_ += static_cast<std::uint64_t>(n);
    recordingPlayed_.store(recordingAt_, std::memory_order_release);
}

double LiveSession::recordingSeconds() const noexcept
{
    return recording_.channels.empty() ? 0.0 : static_cast<double>(recording_.frames()) / recording_.sampleRate;
}

bool LiveSession::recordingEnded() const noexcept
{
    if (recording_.channels.empty() || config_.audioInLoop) return false;
    if (wav_ || (soundCard_ && !soundCard_->failed())) return recordingPlayed_.load(std::memory_order_acquire) >= recording_.frames();
    if (!running_.load() || started_.time_since_epoch().count() == 0) return false;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count() >= recordingSeconds();
}

void LiveSession::audioLoop()
{
    // Renders in real time into the WAV file: the audio clock of a headless session.
    const double sr = config_.engine.sceneConfig.sampleRate;
    constexpr int kBlock = 256;
    std::vector<float> l(kBlock), r(kBlock);
    std::uint64_t rendered = 0;
    auto renderUpTo = [&](std::uint64_t target) {
        while (rendered < target) {
            const int n = static_cast<int>(std::min<std::uint64_t>(kBlock, target - rendered));
            std::fill(l.begin(), l.begin() + n, 0.0f);
            std::fill(r.begin(), r.begin() + n, 0.0f);
            renderBlock(l.data(), r.data(), n);
            wav_->write(l.data(), r.data(), n);
            rendered += static_cast<std::uint64_t>(n);
        }
    };
    while (running_.load(std::memory_order_acquire)) {
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
        renderUpTo(static_cast<std::uint64_t>(elapsed * sr));
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    renderUpTo(static_cast<std::uint64_t>(std::chrono::duration<double>(stopped_ - started_).count() * sr));
}

void LiveSession::start()
{
    if (running_.exchange(true)) return;
    // The tactor output first: a JACK connection that cannot be made throws before anything runs.
    if (tactors_) {
        try {
            tactors_->start();
        } catch (...) {
            running_.store(false);
            throw;
        }
    }
    started_ = std::chrono::steady_clock::now();
    if (right_) right_->start();
    if (left_) left_->start();
    if (navigation_) navigation_->startSource();
    if (messages_) messages_->start();   // a broker that is down is no error: it keeps trying
    if (wav_) audioThread_ = std::thread([this] { audioLoop(); });
    if (soundCard_)
        soundCard_->start([this](float* l, float* r, int n) { renderBlock(l, r, n); },
                          config_.link.realtimePriority);
    if (web_) web_->start();
}

void LiveSession::stop()
{
    if (!running_.load()) return;
    if (web_) web_->stop();   // first: the page reads the session until then
    stopped_ = std::chrono::steady_clock::now();
    // Motors off: answer the next sensor packet with all zeros before the link stops.
    motorsOff_.store(true, std::memory_order_release);
    if (link_) {
        if (link_->stats().inSync) {
            const std::uint64_t before = zeroPacketsSent_.load();
            link_->waitFor([&](const link::LinkStats&) { return zeroPacketsSent_.load() > before; }, 0.2);
        }
        link_->stop();
    }
    if (oscIn_) oscIn_->stop();
    if (leftOscIn_) leftOscIn_->stop();
    if (navigation_) navigation_->stopSource();
    if (leftLink_) {   // the left device's last packet all-off too (motorsOff_ is set)
        if (leftLink_->stats().inSync) leftLink_->waitFor([](const link::LinkStats&) { return true; }, 0.05);
        leftLink_->stop();
    }
    if (right_) right_->stop();   // the simulated forearms stop after their links
    if (left_) left_->stop();
    loopEngine().allOff();
    if (cues_)
        for (int c = 0; c < cues_->cueCount(); ++c) cues_->engine(c).allOff();
    // The tactile file ends with the all-off that was sent: the zero packet answered above (at
    // its packet's time), or the motors' off state at the last packet's time.
    if (tactile_ && published_.steps() > 0) {
        const double zeroT = zeroPacketT_.load();
        LogRow row;
        row.count = 1 + config_.engine.motorCount;
        row.v[0] = zeroT >= 0.0 ? zeroT : latestT_.load();
        tactile_->push(row);
    }
    if (oscOut_) oscOut_->sendMotors(core::MotorLevels {}, config_.engine.motorCount);
    if (mapping_) mapping_->finish(std::max(0.0, lastT_));   // the control thread has stopped: no note is left hanging
    running_.store(false, std::memory_order_release);
    if (messages_) messages_->stop();   // the control thread has stopped: nothing publishes any more
    if (audioThread_.joinable()) audioThread_.join();
    if (soundCard_) soundCard_->stop();
    if (tactors_) {
        tactors_->push(std::max(0.0, latestT_.load()), core::MotorLevels {}); // (the control thread has stopped)
        tactors_->stop();
    }
}

void LiveSession::finish()
{
    stop();
    // Every file is attempted; the first failure is reported.
    std::string error;
    for (StreamingCsvWriter* w : {log_.get(), tactile_.get(), armsLog_.get()}) {
        if (!w) continue;
        try {
            w->finish();
        } catch (const core::IoError& e) {
            if (error.empty()) error = e.what();
        }
    }
    if (wav_) {
        try {
            wav_->finish();
        } catch (const core::IoError& e) {
            if (error.empty()) error = e.what();
        }
    }
    if (!error.empty()) throw core::IoError(error);
}

void LiveSession::discardRecordings() noexcept
{
    for (StreamingCsvWriter* w : {log_.get(), tactile_.get(), armsLog_.get()})
        if (w) w->discard();
    if (wav_) wav_->discard();
}

std::vector<std::string> LiveSession::keptAside() const
{
    std::vector<std::string> lines;
    for (const StreamingCsvWriter* w : {log_.get(), tactile_.get(), armsLog_.get()})
        if (w && !w->keptAs().empty()) lines.push_back(core::keptAsideNote(w->path(), w->keptAs()));
    if (wav_ && !wav_->keptAs().empty()) lines.push_back(core::keptAsideNote(config_.audioOut, wav_->keptAs()));
    return lines;
}

SessionSummary LiveSession::linkCounters() const
{
    SessionSummary s;
    if (link_) {
        const link::LinkStats l = link_->stats();
        s.packets = l.packets;
        s.badPackets = l.badPackets;
        s.resyncs = l.resyncs;
        s.reconnects = l.reconnects;
        s.gaps = l.gaps;
        s.longestGap = l.longestGap;
        s.v2 = l.v2;
        s.seqGaps = l.seqGaps;
        s.crcFailures = l.crcFailures;
        if (l.packets > 1 && l.lastPacketTime > l.firstPacketTime)
            s.rateHz = static_cast<double>(l.packets - 1) / (l.lastPacketTime - l.firstPacketTime);
    } else if (oscIn_) {
        const osc::OscInputStats o = oscIn_->stats();
        s.packets = o.imu + o.orientation;
        s.badPackets = o.bad;
        s.gaps = oscGaps_.load(std::memory_order_relaxed);
        s.longestGap = oscLongestGap_.load(std::memory_order_relaxed);
        const double first = firstT_.load(), last = latestT_.load();
        if (s.packets > 1 && last > first) s.rateHz = static_cast<double>(s.packets - 1) / (last - first);
    }
    return s;
}

SessionSummary LiveSession::summary() const
{
    SessionSummary s = linkCounters();
    if (oscIn_) s.oscJson = oscIn_->statsJson();
    const auto end = running_.load() ? std::chrono::steady_clock::now() : stopped_;
    s.seconds = started_.time_since_epoch().count() ? std::chrono::duration<double>(end - started_).count() : 0.0;
    return s;
}

bool LiveSession::publishMapped(void* self, const mapping::MqttMessage& m)
{
    auto& s = *static_cast<LiveSession*>(self);
    return s.messages_->publishValue(std::string_view(m.topic.data(), m.topicLength), std::string_view(m.payload.data(), m.payloadLength), m.qos,
                                     m.retain, m.rate);
}

std::vector<std::string> LiveSession::presentMessages()
{
    if (!messages_ || !messageScene_) return {};
    std::vector<std::string> lines = messages_->present(*messageScene_);
    std::lock_guard<std::mutex> lock(recentMutex_);
    for (const std::string& line : lines) {
        if (line.find(" on the arm: ") == std::string::npos) continue;
        recent_.push_front(line);
        if (recent_.size() > 20) recent_.pop_back();
    }
    return lines;
}

std::vector<std::string> LiveSession::recentMessages() const
{
    std::lock_guard<std::mutex> lock(recentMutex_);
    return {recent_.begin(), recent_.end()};
}

mqtt::MqttStatus LiveSession::messagesStatus() const { return messages_ ? messages_->status() : mqtt::MqttStatus {}; }

mqtt::InboxStats LiveSession::messagesInbox() const { return messages_ ? messages_->inbox() : mqtt::InboxStats {}; }

void LiveSession::offerMessage(const std::string& text, int priority)
{
    if (messages_) messages_->offerText(text, "osc", priority);
}

std::string LiveSession::messagesJson() const
{
    if (!messages_) return {};
    const mqtt::MqttStatus s = messages_->status();
    const mqtt::InboxStats in = messages_->inbox();
    return ",\"mqtt\":{\"connects\":" + std::to_string(s.connects) + ",\"connection_losses\":" + std::to_string(s.connectionLosses) +
           ",\"published\":" + std::to_string(s.published) + ",\"coalesced\":" + std::to_string(s.coalesced) +
           ",\"outbox_dropped\":" + std::to_string(s.outboxDropped) +
           ",\"received\":" + std::to_string(s.received) + ",\"messages_accepted\":" + std::to_string(in.accepted) +
           ",\"messages_refused\":" + std::to_string(in.refused) + ",\"messages_dropped\":" + std::to_string(in.droppedOldest) +
           ",\"messages_shown\":" + std::to_string(messages_->shown()) + ",\"messages_waiting\":" + std::to_string(in.waiting) + "}";
}

std::vector<std::string> LiveSession::outputLines() const
{
    std::vector<std::string> lines;
    if (soundCard_) {
        const audio::SoundCardInfo& i = soundCard_->info();
        std::ostringstream line;   // (as a stream prints the numbers: "48000 Hz", "21.3333 ms")
        line << "sound on '" << i.device << "' (" << i.sampleRate << " Hz, " << i.format << ", " << 1000.0 * i.bufferFrames / i.sampleRate << " ms buffer)";
        lines.push_back(line.str());
    }
    if (tactors_) lines.push_back("tactors on " + tactors_->describe());
    return lines;
}

std::vector<std::string> LiveSession::outputFailures()
{
    std::vector<std::string> lines;
    if (soundCard_ && soundCard_->failed() && !shownCardFailure_) {
        lines.push_back(soundCard_->lastError() + "; playing on without sound");
        shownCardFailure_ = true;
    }
    if (tactors_ && tactors_->failed() && !shownTactorFailure_) {
        lines.push_back("the tactor output stopped (its JACK server or sound card went away); the device plays on");
        shownTactorFailure_ = true;
    }
    return lines;
}

std::vector<std::string> LiveSession::outputClosingLines() const
{
    std::vector<std::string> lines;
    if (soundCard_ && soundCard_->underruns() > 0)
        lines.push_back("the sound card ran dry " + std::to_string(soundCard_->underruns()) + " time(s) (audible clicks)");
    return lines;
}

std::string LiveSession::outputsJson() const
{
    if (!tactors_) return {};
    return ",\"tactor_frames\":" + std::to_string(tactors_->framesRendered()) + ",\"tactor_dropped\":" + std::to_string(tactors_->recordsDropped()) +
           ",\"tactor_limited\":" + std::to_string(tactors_->limited());
}

link::LatencySummary LiveSession::latency() const { return link_ ? link_->latency() : link::LatencySummary {}; }

int LiveSession::oscInPort() const noexcept { return oscIn_ ? oscIn_->port() : 0; }

bool LiveSession::connected() const noexcept
{
    if (link_) return link_->connected();
    return oscIn_ != nullptr;
}

std::string LiveSession::lastError() const
{
    if (link_) return link_->lastError();
    if (oscIn_) return oscIn_->lastError();
    return "";
}

bool LiveSession::enableSensorTap(bool left)
{
    osc::OscReceiver* osc = left ? leftOscIn_ : oscIn_;
    if (!osc) return false;
    osc->merger().enableSensorTap(true);
    return true;
}

bool LiveSession::popSensorFrame(bool left, osc::SensorFrameSample& sample)
{
    osc::OscReceiver* osc = left ? leftOscIn_ : oscIn_;
    return osc != nullptr && osc->merger().popSensorSample(sample);
}

std::string LiveSession::senderName(bool left) const
{
    const osc::OscReceiver* osc = left ? leftOscIn_ : oscIn_;
    return osc ? osc->deviceName() : std::string();
}

} // namespace armadillo::live
