#include "Plugin/PluginProcessor.h"
#include "Plugin/PluginEditor.h"
#include "Braille/BrailleScene.h"
#include <cmath>
#include <cstring>
#include <limits>

namespace armadillo::plugin {

// ------------------------------------------------------------------------------------------------
int MidiMap::noteFor(const char* gesture) noexcept
{
    struct Entry { const char* name; int note; };
    static constexpr Entry table[] {{"roll", kNoteRoll}, {"punch", kNotePunch}, {"strike", kNoteStrike}};
    if (gesture != nullptr)
        for (const auto& e : table)
            if (std::strcmp(e.name, gesture) == 0) return e.note;
    return kNoteOther;
}

class ArmadilloProcessor::ControlClock : public juce::HighResolutionTimer {
public:
    explicit ControlClock(ArmadilloProcessor& owner) : owner_(owner) {}
    ~ControlClock() override { stopTimer(); }
    void hiResTimerCallback() override
    {
        const double now = juce::Time::getMillisecondCounterHiRes();
        const double dt = last_ < 0.0 ? 0.005 : (now - last_) * 1.0e-3;
        last_ = now;
        owner_.clockTick(dt);
    }

private:
    ArmadilloProcessor& owner_;
    double last_ = -1.0;
};

// ------------------------------------------------------------------------------------------------
ArmadilloProcessor::ArmadilloProcessor()
    : AudioProcessor(BusesProperties().withOutput("Output", juce::AudioChannelSet::stereo(), true)),
      sceneTable_(querySceneParameters()),
      apvts_(*this, nullptr, "PARAMETERS", createParameterLayout(sceneTable_)),
      settings_(defaultSettings())
{
    elevation_ = apvts_.getRawParameterValue(ParamIds::elevation);
    azimuth_ = apvts_.getRawParameterValue(ParamIds::azimuth);
    roll_ = apvts_.getRawParameterValue(ParamIds::roll);
    source_ = apvts_.getRawParameterValue(ParamIds::source);
    scene_ = apvts_.getRawParameterValue(ParamIds::scene);
    jassert(elevation_ && azimuth_ && roll_ && source_ && scene_);

    settings_.addListener(this);
    {
        std::lock_guard<std::mutex> lock(builderMutex_);
        builtRequest_ = currentRequest();
        loop_.replace(buildEngine(builtRequest_));   // nothing else runs yet
    }
    applyNetworkSettings();
    device_ = std::make_unique<DeviceConnection>(loop_.input(SourceKind::Device), [this] { return frame_.load().motors; });
    clock_ = std::make_unique<ControlClock>(*this);
    clock_->startTimer(5);   // 200 Hz
    startTimerHz(50);
}

ArmadilloProcessor::~ArmadilloProcessor()
{
    stopTimer();
    device_.reset();         // link thread stopped: no more motor packets
    clock_.reset();          // waits for a running callback
    settings_.removeListener(this);
    if (gestureOpen_)
        for (auto* id : {ParamIds::elevation, ParamIds::azimuth, ParamIds::roll})
            if (auto* p = apvts_.getParameter(id)) p->endChangeGesture();
}

bool ArmadilloProcessor::isBusesLayoutSupported(const BusesLayout& layouts) const
{
    return layouts.getMainOutputChannelSet() == juce::AudioChannelSet::stereo() && layouts.getMainInputChannels() == 0;
}

SourceKind ArmadilloProcessor::source() const noexcept
{
    return static_cast<SourceKind>(juce::jlimit(0, 3, static_cast<int>(source_->load(std::memory_order_relaxed))));
}

int ArmadilloProcessor::sceneIndex() const noexcept
{
    const int n = static_cast<int>(sceneTable_.scenes.size());
    return juce::jlimit(0, std::max(0, n - 1), static_cast<int>(scene_->load(std::memory_order_relaxed)));
}

// ------------------------------------------------------------------------------------------------
// Engines

ArmadilloProcessor::EngineRequest ArmadilloProcessor::currentRequest() const
{
    EngineRequest r;
    r.scene = sceneIndex();
    r.sampleRate = sampleRate_.load();
    r.left = settings_[SettingIds::armSide].toString() == "left";
    r.backMotors = static_cast<bool>(settings_[SettingIds::backMotors]);
    r.text = settings_[SettingIds::brailleText].toString().toStdString();
    r.score = settings_[SettingIds::score].toString().toStdString();
    return r;
}

std::unique_ptr<live::EngineSlot> ArmadilloProcessor::buildEngine(const EngineRequest& request)
{
    auto slot = std::make_unique<live::EngineSlot>();
    slot->generation = ++engineGeneration_;
    EngineConfig config;
    const auto& names = sceneNames();
    config.scene = names.empty() ? std::string("monitor") : names[static_cast<std::size_t>(request.scene) % names.size()];
    config.motorCount = request.backMotors ? kGridMotors + kBackMotors : kGridMotors;
    config.sceneConfig.sampleRate = request.sampleRate;
    config.sceneConfig.controlRateHz = kControlRateHz;
    config.sceneConfig.seed = 1;
    config.sceneConfig.side = request.left ? ArmSide::Left : ArmSide::Right;
    config.sceneConfig.text = request.text;
    config.sceneConfig.score = request.score;
    config.sceneConfig.resourceDir = ARMADILLO_RESOURCE_DIR;
    try {
        slot->engine = std::make_unique<Engine>(config);
    } catch (const std::exception& e) {
        setStatus("Scene \"" + juce::String(config.scene) + "\" cannot start (" + juce::String(e.what())
                  + "); running \"monitor\" instead.");
        config.scene = "monitor";
        try {
            slot->engine = std::make_unique<Engine>(config);
        } catch (const std::exception& e2) {
            setStatus("The engine cannot start: " + juce::String(e2.what()));
            return slot;
        }
    }
    slot->sceneName = config.scene;
    for (const auto& entry : sceneTable_.scenes) {
        if (entry.scene != config.scene) continue;
        for (std::size_t i = 0; i < entry.specs.size(); ++i)
            slot->params.push_back(entry.exposed[i] ? apvts_.getRawParameterValue(juce::String(entry.specs[i].id))
                                                    : nullptr);
    }
    slot->sent.assign(slot->params.size(), std::numeric_limits<float>::quiet_NaN());
    return slot;
}

void ArmadilloProcessor::applyPendingEngine()
{
    std::lock_guard<std::mutex> lock(builderMutex_);
    loop_.collect();   // the engine the control side gave up is deleted here, never on the audio thread
    const auto request = currentRequest();
    if (request == builtRequest_) return;
    // Only one hand-over in flight, and the retired engine must be gone before the next one.
    if (! loop_.canOffer()) return;
    auto slot = buildEngine(request);
    if (loop_.offer(slot)) builtRequest_ = request;
}

bool ArmadilloProcessor::tryTakeToken() noexcept
{
    bool expected = false;
    return token_.compare_exchange_strong(expected, true, std::memory_order_acquire);
}

void ArmadilloProcessor::releaseToken() noexcept
{
    token_.store(false, std::memory_order_release);
}

void ArmadilloProcessor::prepareToPlay(double sampleRate, int)
{
    sampleRate_.store(sampleRate > 0.0 ? sampleRate : 48000.0);
    std::lock_guard<std::mutex> lock(builderMutex_);
    const auto request = currentRequest();
    auto slot = buildEngine(request);
    while (! tryTakeToken()) std::this_thread::yield();   // the clock holds it for < 1 ms
    loop_.replace(std::move(slot));   // the control side is not running: we hold the token
    builtRequest_ = request;
    samplesToTick_ = 0;
    noteOffs_ = {};
    midiStorage_.ensureSize(kMidiStorageBytes);   // off the audio thread; processBlock hands it over
    midiStorageGiven_ = false;
    releaseToken();
}

bool ArmadilloProcessor::withBrailleTraining(
    const std::function<void(braille::BrailleSceneControls&, std::uint64_t)>& use)
{
    // Engines are deleted only under builderMutex_ (applyPendingEngine, prepareToPlay), and the
    // loop's newest engine is either the active one or the pending one, never the retired one.
    std::lock_guard<std::mutex> lock(builderMutex_);
    auto* newest = loop_.newest();
    if (newest == nullptr || newest->engine == nullptr) return false;
    auto* controls = dynamic_cast<braille::BrailleSceneControls*>(&newest->engine->scene());
    if (controls == nullptr) return false;
    use(*controls, newest->generation);
    return true;
}

bool ArmadilloProcessor::copyBrailleTrainingLog(std::uint64_t generation, std::string& csv, juce::String& why)
{
    // builderMutex_ keeps the engine alive (the audio thread never takes it). The control side
    // only queues fixed-size log records; trainingLogCsv() turns them into text here, so no
    // control token is held and the audio thread never waits for this copy.
    std::lock_guard<std::mutex> lock(builderMutex_);
    auto* newest = loop_.newest();
    if (newest == nullptr || newest->engine == nullptr || newest->generation != generation) {
        why = "The braille scene was restarted since (scene, text or audio settings changed); its training log is gone.";
        return false;
    }
    auto* controls = dynamic_cast<braille::BrailleSceneControls*>(&newest->engine->scene());
    if (controls == nullptr) {
        why = "The braille scene is not running.";
        return false;
    }
    try {
        csv = controls->trainingLogCsv();
    } catch (const std::exception& e) {
        why = "Cannot copy the training log: " + juce::String(e.what());
        return false;
    }
    return true;
}

void ArmadilloProcessor::reportEngineFailure()
{
    // Message thread: a scene that threw during a control update was stopped by the Engine (motors
    // off, silence); say so once per engine, with what it threw. Also keeps a braille training
    // log's queue drained while no panel asks for it.
    std::lock_guard<std::mutex> lock(builderMutex_);
    auto* newest = loop_.newest();
    if (newest == nullptr || newest->engine == nullptr) return;
    if (auto* controls = dynamic_cast<braille::BrailleSceneControls*>(&newest->engine->scene())) controls->collectTrainingLog();
    if (newest->engine->failed() && reportedFailure_ != newest->generation) {
        reportedFailure_ = newest->generation;
        setStatus("The scene \"" + juce::String(newest->sceneName) + "\" failed during a control update and was stopped (motors off): "
                  + juce::String(newest->engine->failure()) + ". Choose the scene again to restart it.");
    }
}

// ------------------------------------------------------------------------------------------------
// Control loop

void ArmadilloProcessor::controlTick(double dt, const Transport& transport, juce::MidiBuffer* midi,
                                     int sampleOffset) noexcept
{
    live::ControlStep step;
    step.source = source();
    step.automation = Pose {elevation_->load(std::memory_order_relaxed), azimuth_->load(std::memory_order_relaxed),
                            roll_->load(std::memory_order_relaxed)};
    step.transport = transport;
    step.dt = dt;
    const live::ControlResult result = loop_.tick(step);   // swap-in, parameters, fusion, Engine::control
    if (! result.ran) return;
    Engine& engine = *loop_.active()->engine;
    controlClock_ += dt;
    const ArmState& arm = result.arm;
    const MotorLevels& levels = result.levels;

    ArmFrame f;
    f.t = controlClock_;
    f.valid = arm.valid;
    f.q[0] = arm.q.w();
    f.q[1] = arm.q.x();
    f.q[2] = arm.q.y();
    f.q[3] = arm.q.z();
    f.pose[0] = arm.features.pose.elevationDeg;
    f.pose[1] = arm.features.pose.azimuthDeg;
    f.pose[2] = arm.features.pose.rollDeg;
    for (int i = 0; i < 3; ++i) f.gyro[i] = arm.gyro[i];
    f.motors = levels;
    f.motorCount = engine.config().motorCount;
    f.serial = ++frameSerial_;
    frame_.store(f);
    ticks_.fetch_add(1, std::memory_order_relaxed);

    GestureEvent g;
    while (engine.popGesture(g)) {
        gesturesOut_.push(g);
        lastGesture_.store(g.name, std::memory_order_relaxed);
        gestureCount_.fetch_add(1, std::memory_order_relaxed);
        if (midi != nullptr) emitNote(*midi, MidiMap::noteFor(g.name), g.value, sampleOffset);
    }

    if (midi != nullptr && arm.valid) {
        const double values[3] {(f.pose[0] + 90.0) / 180.0, f.pose[1] / 360.0, (f.pose[2] + 180.0) / 360.0};
        const int ccs[3] {MidiMap::kCcElevation, MidiMap::kCcAzimuth, MidiMap::kCcRoll};
        const int channel = juce::jlimit(1, 16, midiChannel_.load(std::memory_order_relaxed));
        for (int i = 0; i < 3; ++i) {
            const int v = juce::jlimit(0, 127, static_cast<int>(std::lround(values[i] * 127.0)));
            if (v != lastCc_[i]) {
                midi->addEvent(juce::MidiMessage::controllerEvent(channel, ccs[i], v), sampleOffset);
                lastCc_[i] = v;
            }
        }
    }
}

void ArmadilloProcessor::emitNote(juce::MidiBuffer& midi, int note, float value, int sampleOffset) noexcept
{
    const int channel = juce::jlimit(1, 16, midiChannel_.load(std::memory_order_relaxed));
    const auto velocity = static_cast<juce::uint8>(juce::jlimit(1, 127, static_cast<int>(std::lround(std::fabs(value) * 127.0f))));
    for (auto& off : noteOffs_) {
        if (off.note == note) {   // retrigger: close the sounding note first
            midi.addEvent(juce::MidiMessage::noteOff(channel, note), sampleOffset);
            off.note = -1;
        }
    }
    midi.addEvent(juce::MidiMessage::noteOn(channel, note, velocity), sampleOffset);
    const int length = std::max(1, static_cast<int>(MidiMap::kNoteLengthS * sampleRate_.load(std::memory_order_relaxed)));
    for (auto& off : noteOffs_) {
        if (off.note < 0) {
            off.note = note;
            off.samplesLeft = sampleOffset + length;
            return;
        }
    }
}

void ArmadilloProcessor::flushNoteOffs(juce::MidiBuffer& midi, int blockSamples) noexcept
{
    const int channel = juce::jlimit(1, 16, midiChannel_.load(std::memory_order_relaxed));
    for (auto& off : noteOffs_) {
        if (off.note < 0) continue;
        if (off.samplesLeft < blockSamples) {
            midi.addEvent(juce::MidiMessage::noteOff(channel, off.note), std::max(0, off.samplesLeft));
            off.note = -1;
        } else {
            off.samplesLeft -= blockSamples;
        }
    }
}

void ArmadilloProcessor::processBlock(juce::AudioBuffer<float>& buffer, juce::MidiBuffer& midi)
{
    juce::ScopedNoDenormals noDenormals;
    const int n = buffer.getNumSamples();
    buffer.clear();
    // No MIDI input is used; the buffer carries our gestures out. The host's buffer may be sized
    // for a few events only, and a roll that emits several would grow it here: the first block
    // hands it storage sized in prepareToPlay (swapWith moves pointers, and clear() keeps the
    // storage), so adding events never allocates while the host reuses its buffer, as JUCE's
    // wrappers do.
    if (! midiStorageGiven_) {
        midi.swapWith(midiStorage_);
        midiStorageGiven_ = true;
    }
    midi.clear();
    lastAudioMs_.store(juce::Time::getMillisecondCounterHiRes(), std::memory_order_relaxed);
    if (buffer.getNumChannels() < 2 || n <= 0) return;
    if (! tryTakeToken()) return;   // the idle clock is finishing an update: one silent block

    const double sr = sampleRate_.load(std::memory_order_relaxed);
    Transport transport;
    if (auto* head = getPlayHead()) {
        if (const auto pos = head->getPosition()) {
            transport.valid = pos->getTimeInSeconds().hasValue() || pos->getPpqPosition().hasValue();
            transport.playing = pos->getIsPlaying();
            transport.looping = pos->getIsLooping();
            transport.seconds = pos->getTimeInSeconds().orFallback(0.0);
            transport.ppq = pos->getPpqPosition().orFallback(0.0);
            transport.bpm = pos->getBpm().orFallback(120.0);
        }
    }

    const int samplesPerTick = std::max(1, static_cast<int>(std::lround(sr / kControlRateHz)));
    float* left = buffer.getWritePointer(0);
    float* right = buffer.getWritePointer(1);
    int pos = 0;
    while (pos < n) {
        if (samplesToTick_ <= 0) {
            Transport t = transport;
            if (t.valid && t.playing) {
                const double ahead = pos / sr;
                t.seconds += ahead;
                t.ppq += ahead * t.bpm / 60.0;
            }
            controlTick(samplesPerTick / sr, t, &midi, pos);
            samplesToTick_ = samplesPerTick;
        }
        const int len = std::min(n - pos, samplesToTick_);
        loop_.render(left + pos, right + pos, len);
        pos += len;
        samplesToTick_ -= len;
    }
    flushNoteOffs(midi, n);
    releaseToken();
}

// ------------------------------------------------------------------------------------------------
// Control clock thread

void ArmadilloProcessor::clockTick(double dt)
{
    dt = juce::jlimit(0.0, 0.1, dt);
    if (source() == SourceKind::Simulator) {
        Eigen::Quaterniond q;
        double t = 0.0;
        {
            std::lock_guard<std::mutex> lock(simMutex_);
            q = simulator_.advance(dt);
            t = simulator_.time();
        }
        loop_.input(SourceKind::Simulator).storeOrientation(t, q);
    }

    const double now = juce::Time::getMillisecondCounterHiRes();
    if (now - lastAudioMs_.load(std::memory_order_relaxed) > 100.0 && tryTakeToken()) {
        // A late timer (loaded machine) catches up with several updates so the control rate
        // stays at 200 Hz on average, as it does under an audio callback.
        const int updates = juce::jlimit(1, 4, static_cast<int>(std::lround(dt * kControlRateHz)));
        for (int i = 0; i < updates; ++i) controlTick(dt / updates, Transport {}, nullptr, 0);
        releaseToken();
    }

    const auto f = frame_.load();
    if (f.serial != lastSentSerial_) {
        lastSentSerial_ = f.serial;
        oscOut_.sendFrame(f);
    }
    GestureEvent g;
    while (gesturesOut_.pop(g)) oscOut_.sendGesture(g.name);

    if (now - rateWindowStartMs_ >= 1000.0) {
        const auto ticks = ticks_.load(std::memory_order_relaxed);
        if (rateWindowStartMs_ > 0.0)
            measuredRate_.store((ticks - rateWindowTicks_) * 1000.0 / (now - rateWindowStartMs_), std::memory_order_relaxed);
        rateWindowTicks_ = ticks;
        rateWindowStartMs_ = now;
    }
}

// ------------------------------------------------------------------------------------------------
// Message thread

void ArmadilloProcessor::timerCallback()
{
    reportEngineFailure();
    applyPendingEngine();
    writeLiveOrientationToParameters();
    device_->calibrationSession().drain();   // raw packets queued by the link thread → the guided calibration
    // The performer's standalone app (or a session) reopens its saved port by itself, once.
    if (! autoConnectTried_ && static_cast<bool>(settings_[SettingIds::connectOnStart]) && source() == SourceKind::Device
        && ! deviceConnected() && settings_[SettingIds::serialPort].toString().isNotEmpty()) {
        autoConnectTried_ = true;
        connectDevice(true);
    }
}

void ArmadilloProcessor::writeLiveOrientationToParameters()
{
    juce::RangedAudioParameter* params[3] {apvts_.getParameter(ParamIds::elevation), apvts_.getParameter(ParamIds::azimuth),
                                           apvts_.getParameter(ParamIds::roll)};
    if (! isLiveSource(source())) {
        if (gestureOpen_)
            for (auto* p : params) p->endChangeGesture();
        gestureOpen_ = false;
        return;
    }
    const auto f = frame_.load();
    if (! f.valid || f.serial == lastWrittenSerial_) return;
    lastWrittenSerial_ = f.serial;
    // One long gesture while a live source plays the arm: hosts record it like a held knob.
    if (! gestureOpen_)
        for (auto* p : params) p->beginChangeGesture();
    gestureOpen_ = true;
    for (int i = 0; i < 3; ++i) {
        const float value = static_cast<float>(f.pose[i]);
        if (std::abs(params[i]->convertFrom0to1(params[i]->getValue()) - value) > 0.01f)
            params[i]->setValueNotifyingHost(params[i]->convertTo0to1(value));
    }
}

void ArmadilloProcessor::setOrientationFromUser(const Pose& pose)
{
    if (isLiveSource(source())) return;   // live sources own the orientation parameters
    const float values[3] {static_cast<float>(pose.elevationDeg), static_cast<float>(wrapDeg360(pose.azimuthDeg)),
                           static_cast<float>(wrapDeg180(pose.rollDeg))};
    const char* ids[3] {ParamIds::elevation, ParamIds::azimuth, ParamIds::roll};
    for (int i = 0; i < 3; ++i) {
        auto* p = apvts_.getParameter(ids[i]);
        p->beginChangeGesture();
        p->setValueNotifyingHost(p->convertTo0to1(values[i]));
        p->endChangeGesture();
    }
}

Pose ArmadilloProcessor::simulatorPose() const
{
    std::lock_guard<std::mutex> lock(simMutex_);
    return simulator_.pose();
}

bool ArmadilloProcessor::simulatorWandering() const
{
    std::lock_guard<std::mutex> lock(simMutex_);
    return simulator_.wandering();
}

void ArmadilloProcessor::steerSimulator(const Pose& pose)
{
    {
        std::lock_guard<std::mutex> lock(simMutex_);
        simulator_.steerTo(pose);
    }
    settings_.setProperty(SettingIds::simWandering, false, nullptr);
}

void ArmadilloProcessor::setSimulatorWandering(bool on)
{
    settings_.setProperty(SettingIds::simWandering, on, nullptr);
}

void ArmadilloProcessor::valueTreePropertyChanged(juce::ValueTree&, const juce::Identifier& id)
{
    if (id == SettingIds::simWandering) {
        std::lock_guard<std::mutex> lock(simMutex_);
        simulator_.setWandering(static_cast<bool>(settings_[SettingIds::simWandering]));
    } else if (id == SettingIds::serialPort || id == SettingIds::connectOnStart) {
        autoConnectTried_ = false;
        if (id == SettingIds::serialPort && deviceConnected()) connectDevice(false);
    } else if (id == SettingIds::midiChannel) {
        midiChannel_.store(juce::jlimit(1, 16, static_cast<int>(settings_[SettingIds::midiChannel])));
    } else if (id == SettingIds::oscOutEnabled || id == SettingIds::oscOutHost || id == SettingIds::oscOutPort
               || id == SettingIds::oscInEnabled || id == SettingIds::oscInPort || id == SettingIds::oscInFormat
               || id == SettingIds::oscInMount) {
        applyNetworkSettings();
    }
}

void ArmadilloProcessor::applyNetworkSettings()
{
    std::string why;
    juce::String message;
    if (! oscOut_.configure(static_cast<bool>(settings_[SettingIds::oscOutEnabled]),
                            settings_[SettingIds::oscOutHost].toString().toStdString(),
                            static_cast<int>(settings_[SettingIds::oscOutPort]), why))
        message << "OSC out: " << juce::String(why) << ". ";
    if (! oscIn_.configure(static_cast<bool>(settings_[SettingIds::oscInEnabled]),
                           static_cast<int>(settings_[SettingIds::oscInPort]), settings_[SettingIds::oscInFormat].toString().toStdString(),
                           settings_[SettingIds::oscInMount].toString().toStdString(), why))
        message << "OSC in: " << juce::String(why) << ".";
    std::lock_guard<std::mutex> lock(statusMutex_);
    networkStatus_ = message.trim();
}

void ArmadilloProcessor::connectDevice(bool connect)
{
    if (! connect) {
        const bool calibrating = device_->calibrationSession().running();
        device_->disconnect();   // cancels a running calibration: its packets stop
        deviceMessage_ = calibrating ? "Not connected; the calibration was cancelled." : "Not connected.";
        return;
    }
    std::string message;
    device_->connect(settings_[SettingIds::serialPort].toString().toStdString(),
                     static_cast<int>(settings_[SettingIds::baudRate]),
                     settings_[SettingIds::calibrationFile].toString().toStdString(), message);
    deviceMessage_ = juce::String(message);
}

bool ArmadilloProcessor::beginCalibration(juce::String& why)
{
    if (! deviceConnected()) {
        why = "Connect a device (or the simulated forearm) first: the calibration measures its raw sensor counts.";
        return false;
    }
    device_->calibrationSession().begin(device_->calibration());
    why.clear();
    return true;
}

bool ArmadilloProcessor::calibrationNext(juce::String& why)
{
    std::string reason;
    const bool ok = device_->calibrationSession().next(reason);
    why = juce::String(reason);
    if (ok && device_->calibrationSession().finished()) applyGuidedCalibration();
    return ok;
}

void ArmadilloProcessor::calibrationSkip()
{
    device_->calibrationSession().skip();
    if (device_->calibrationSession().finished()) applyGuidedCalibration();
}

void ArmadilloProcessor::cancelCalibration()
{
    device_->calibrationSession().cancel();
}

void ArmadilloProcessor::applyGuidedCalibration()
{
    if (! deviceConnected()) return;   // the link went away: nothing to apply it to (disconnect cancels anyway)
    device::Calibration c = device_->calibrationSession().result();
    device_->applyCalibration(c, "guided calibration, not saved");
    deviceMessage_ = "Guided calibration applied (not saved).";
}

bool ArmadilloProcessor::saveCalibration(const juce::File& file, juce::String& message)
{
    const auto& session = device_->calibrationSession();
    if (! session.finished()) {
        message = "There is no finished calibration to save.";
        return false;
    }
    device::Calibration c = session.result();
    c.device = settings_[SettingIds::serialPort].toString().toStdString();
    c.date = juce::Time::getCurrentTime().toISO8601(true).toStdString();
    try {
        device::saveCalibration(file.getFullPathName().toStdString(), c);
    } catch (const std::exception& e) {
        message = "Calibration not saved: " + juce::String(e.what());
        return false;
    }
    settings_.setProperty(SettingIds::calibrationFile, file.getFullPathName(), nullptr);
    if (deviceConnected()) {
        device_->applyCalibration(c, "calibration " + file.getFullPathName().toStdString());
        deviceMessage_ = "Guided calibration applied and saved as " + file.getFileName() + ".";
    }
    message = "Saved as " + file.getFileName() + "; the next connection loads it.";
    return true;
}

juce::String ArmadilloProcessor::linkStatus() const
{
    juce::String s = deviceMessage_;
    if (deviceConnected()) s << "\n" << juce::String(device_->status());
    const auto in = oscIn_.stats();
    s << "\nControl rate " << juce::String(controlRateMeasured(), 1) << " Hz; OSC sent "
      << juce::String(static_cast<juce::int64>(oscOut_.messagesSent())) << ", received "
      << juce::String(static_cast<juce::int64>(in.imu + in.orientation)) << " (bad " << juce::String(static_cast<juce::int64>(in.bad)) << ")";
    s << "\n" << juce::String(oscIn_.statusText());   // sender format, device, mount, refusals by kind
    std::lock_guard<std::mutex> lock(statusMutex_);
    if (networkStatus_.isNotEmpty()) s << "\n" << networkStatus_;
    return s.trim();
}

void ArmadilloProcessor::setStatus(const juce::String& message)
{
    std::lock_guard<std::mutex> lock(statusMutex_);
    status_ = message;
}

juce::String ArmadilloProcessor::statusMessage() const
{
    std::lock_guard<std::mutex> lock(statusMutex_);
    return status_;
}

void ArmadilloProcessor::clearStatusMessage()
{
    setStatus({});
}

// ------------------------------------------------------------------------------------------------
// State

juce::ValueTree ArmadilloProcessor::defaultSettings()
{
    juce::ValueTree s(SettingIds::root);
    s.setProperty(SettingIds::oscOutEnabled, false, nullptr);
    s.setProperty(SettingIds::oscOutHost, "127.0.0.1", nullptr);
    s.setProperty(SettingIds::oscOutPort, 9000, nullptr);
    s.setProperty(SettingIds::oscInEnabled, false, nullptr);
    s.setProperty(SettingIds::oscInPort, 9001, nullptr);
    s.setProperty(SettingIds::oscInFormat, "", nullptr);
    s.setProperty(SettingIds::oscInMount, "", nullptr);
    s.setProperty(SettingIds::serialPort, "", nullptr);
    s.setProperty(SettingIds::baudRate, 57600, nullptr);
    s.setProperty(SettingIds::calibrationFile, "", nullptr);
    s.setProperty(SettingIds::armSide, "right", nullptr);
    s.setProperty(SettingIds::backMotors, false, nullptr);
    s.setProperty(SettingIds::brailleText, "armadillo", nullptr);
    s.setProperty(SettingIds::score, "rite-of-spring", nullptr);
    s.setProperty(SettingIds::midiChannel, 1, nullptr);
    s.setProperty(SettingIds::editorWidth, 1040, nullptr);
    s.setProperty(SettingIds::editorHeight, 700, nullptr);
    s.setProperty(SettingIds::simWandering, true, nullptr);
    s.setProperty(SettingIds::connectOnStart, false, nullptr);
    return s;
}

void ArmadilloProcessor::installSettings(const juce::ValueTree& loaded)
{
    // Start from the defaults and take only known properties of the right kind and range, so a
    // hand-edited or damaged state cannot put nonsense into the sockets or the engine.
    const auto defaults = defaultSettings();
    for (int i = 0; i < defaults.getNumProperties(); ++i) {
        const auto id = defaults.getPropertyName(i);
        const auto& fallback = defaults[id];
        juce::var value = fallback;
        if (loaded.isValid() && loaded.hasProperty(id)) {
            const auto& v = loaded[id];
            if (fallback.isBool()) value = static_cast<bool>(v);
            else if (fallback.isInt()) value = static_cast<int>(v);
            else value = v.toString().substring(0, 4096);
        }
        settings_.setProperty(id, value, nullptr);
    }
    auto clampInt = [this](const juce::Identifier& id, int lo, int hi, int fallback) {
        const int v = static_cast<int>(settings_[id]);
        settings_.setProperty(id, v < lo || v > hi ? fallback : v, nullptr);
    };
    clampInt(SettingIds::oscOutPort, 1, 65535, 9000);
    clampInt(SettingIds::oscInPort, 1, 65535, 9001);
    clampInt(SettingIds::baudRate, 1200, 4000000, 57600);
    clampInt(SettingIds::midiChannel, 1, 16, 1);
    clampInt(SettingIds::editorWidth, 400, 8000, 1040);
    clampInt(SettingIds::editorHeight, 300, 8000, 700);
    if (settings_[SettingIds::armSide].toString() != "left") settings_.setProperty(SettingIds::armSide, "right", nullptr);
    const auto score = settings_[SettingIds::score].toString();
    if (score.isEmpty()) settings_.setProperty(SettingIds::score, "rite-of-spring", nullptr);
}

void ArmadilloProcessor::resetToDefaults()
{
    for (auto* p : getParameters())
        if (auto* ranged = dynamic_cast<juce::RangedAudioParameter*>(p))
            ranged->setValueNotifyingHost(ranged->getDefaultValue());
    installSettings({});
}

void ArmadilloProcessor::getStateInformation(juce::MemoryBlock& destData)
{
    juce::ValueTree root("ARMADILLO");
    root.setProperty("version", kStateVersion, nullptr);
    root.setProperty("pluginVersion", ARMADILLO_VERSION_STRING, nullptr);
    root.appendChild(apvts_.copyState(), nullptr);
    root.appendChild(settings_.createCopy(), nullptr);
    if (auto xml = root.createXml()) copyXmlToBinary(*xml, destData);
}

void ArmadilloProcessor::setStateInformation(const void* data, int sizeInBytes)
{
    std::unique_ptr<juce::XmlElement> xml;
    if (data != nullptr && sizeInBytes > 0) xml = getXmlFromBinary(data, sizeInBytes);
    const auto root = xml != nullptr ? juce::ValueTree::fromXml(*xml) : juce::ValueTree();
    juce::String problem;
    if (! root.isValid() || ! root.hasType("ARMADILLO"))
        problem = "The saved state is not an ARMadillo state (damaged or from another plugin)";
    else if (static_cast<int>(root["version"]) < 1 || static_cast<int>(root["version"]) > kStateVersion)
        problem = "The saved state has format version " + root["version"].toString() + ", this build reads up to "
                  + juce::String(kStateVersion);
    if (problem.isNotEmpty()) {
        resetToDefaults();
        setStatus(problem + "; defaults loaded.");
        return;
    }

    const auto saved = root.getChildWithName(apvts_.state.getType());
    int rejected = 0;
    for (auto* p : getParameters()) {
        auto* ranged = dynamic_cast<juce::RangedAudioParameter*>(p);
        if (ranged == nullptr) continue;
        const auto node = saved.getChildWithProperty("id", ranged->getParameterID());
        const double v = node.isValid() ? static_cast<double>(node["value"]) : std::numeric_limits<double>::quiet_NaN();
        if (node.isValid() && ! std::isfinite(v)) ++rejected;
        const auto& range = ranged->getNormalisableRange();
        const float value = std::isfinite(v) ? juce::jlimit(range.start, range.end, static_cast<float>(v))
                                             : range.convertFrom0to1(ranged->getDefaultValue());
        ranged->setValueNotifyingHost(ranged->convertTo0to1(value));
    }
    installSettings(root.getChildWithName(SettingIds::root));
    setStatus(rejected > 0 ? juce::String(rejected) + " saved parameter values were not numbers; defaults used for them."
                           : juce::String());
}

juce::AudioProcessorEditor* ArmadilloProcessor::createEditor()
{
    return new ArmadilloEditor(*this);
}

} // namespace armadillo::plugin

juce::AudioProcessor* JUCE_CALLTYPE createPluginFilter()
{
    return new armadillo::plugin::ArmadilloProcessor();
}
