#include "Plugin/PluginProcessor.h"
#include "Link/TouchProfile.h"
#include "Access/Feedback.h"
#include "Plugin/FactoryPresets.h"
#include "Plugin/PluginEditor.h"
#include "Plugin/TactorBusLayout.h"
#include <algorithm>
#include <iostream>
#include <utility>

namespace armadillo::plugin {

namespace {
live::BlockControl::Cells cellsOf(juce::AudioProcessorValueTreeState& apvts)
{
    live::BlockControl::Cells c;
    c.elevation = apvts.getRawParameterValue(ParamIds::elevation);
    c.azimuth = apvts.getRawParameterValue(ParamIds::azimuth);
    c.roll = apvts.getRawParameterValue(ParamIds::roll);
    c.source = apvts.getRawParameterValue(ParamIds::source);
    return c;
}
} // namespace

/// A main input as effects that listen have (the track the score follows, the music audio-touch
/// turns into touch; played through to the output), in every format. The VST3 has it since the
/// build compiles Debian's JUCE VST3 glue with the fix of its per-block copy of each input bus's
/// channel mapping (cmake/JucePatchedAudioProcessors.cmake; docs/PLUGIN.md, "Audio input"); the
/// fix is in the wrapper's loop over every input bus, so it covers the sidechains too.
///
/// The VST3 alone also declares the stems as sidechain buses (VST3 aux inputs, stereo, disabled
/// by default: a host that routes nothing to them is unaffected). The LV2 does not: JUCE 7.0.5's
/// LV2 hosting crashed with a declared, disabled sidechain (docs/PLUGIN.md), and the standalone
/// app has one sound-card input.
juce::AudioProcessor::BusesProperties ArmadilloProcessor::busesFor(juce::AudioProcessor::WrapperType wrapper)
{
    auto buses = juce::AudioProcessor::BusesProperties()
                     .withInput("Input", juce::AudioChannelSet::stereo(), true)
                     .withOutput("Output", juce::AudioChannelSet::stereo(), true);
    if (wrapper == wrapperType_VST3) {
        for (const char* name : kStemBuses) buses = buses.withInput(name, juce::AudioChannelSet::stereo(), false);
        buses = buses.withOutput(kTactorBus, tactorbus::layoutFor(core::kGridMotors), false);
    }
    return buses;
}

ArmadilloProcessor::ArmadilloProcessor()
    : AudioProcessor(busesFor(juce::PluginHostType::getPluginLoadedAs())),
      sceneTable_(querySceneParameters()),
      apvts_(*this, nullptr, "PARAMETERS", createParameterLayout(sceneTable_)),
      settings_(PluginState::defaultSettings()),
      instrument_(live::BlockInstrument::Host {cellsOf(apvts_), &sceneTable_,
                                                [this] { return static_cast<int>(settings_[SettingIds::midiChannel]); }}),
      engines_(instrument_.loop(), sceneTable_, apvts_, [this](const juce::String& m) { setEngineStatus(m); }),
      training_(engines_)
{
    scene_ = apvts_.getRawParameterValue(ParamIds::scene);
    jassert(scene_ != nullptr);
    settings_.addListener(this);
    engines_.install(currentRequest(), instrument_);
    applyNetworkSettings();
    applyVoiceSettings();
    // The mapping (before the control clock starts): scene parameters for its destinations, the
    // classic preset until a state says otherwise, and in the standalone app an ALSA sequencer
    // port for its MIDI (docs/PLUGIN.md "MIDI out").
    applyLeftArm();
    instrument_.stage().setCueNotes(static_cast<int>(settings_[SettingIds::cueNextNote]), static_cast<int>(settings_[SettingIds::cuePrevNote]));
    instrument_.stage().setPanicGesture(static_cast<bool>(settings_[SettingIds::panicGesture]));
    applyStageOsc();
    instrument_.mapping().setControlStopped(true);   // nothing runs the control step yet: install, not offer
    if (const auto why = instrument_.mapping().fromSaved({}); ! why.empty()) setStatus(why);
    instrument_.mapping().setControlStopped(false);
    if (wrapperType == wrapperType_Standalone) {
        juce::String why;
        if (midiPort_.open("ARMadillo", why)) {
            instrument_.control().setMidiPort(&midiPort_.queue());
            instrument_.rig().setClockHook([this] { midiPort_.drain(); });   // the clock sends the queued MIDI
        } else {
            setStatus(why);   // the editor's status line, and the terminal the app was started from
            std::cerr << "ARMadillo: " << why << std::endl;
        }
    }
    // Only the standalone app lets its idle clock drive the motors (a performer without a sound
    // card); in a host, no processBlock means stopped, bypassed or removed: motors off.
    instrument_.control().setIdleDrivesMotors(wrapperType == wrapperType_Standalone);
    instrument_.start();
    startTimerHz(50);
}

ArmadilloProcessor::~ArmadilloProcessor()
{
    *alive_ = false;   // a parameter change the page queued finds no processor
    stopTimer();
    instrument_.stop();   // the idle clock, the device link (its last packet all-off), every port and thread
    settings_.removeListener(this);
    if (gestureOpen_)
        for (auto* id : {ParamIds::elevation, ParamIds::azimuth, ParamIds::roll})
            if (auto* p = apvts_.getParameter(id)) p->endChangeGesture();
    for (int i = 0; i < ParamIds::kMacroCount; ++i)
        if (macroWrites_[static_cast<std::size_t>(i)].open)
            if (auto* p = apvts_.getParameter(ParamIds::macros[i])) p->endChangeGesture();
}

bool ArmadilloProcessor::isBusesLayoutSupported(const BusesLayout& layouts) const
{
    const auto inputOk = [](const juce::AudioChannelSet& set) {
        return set.isDisabled() || set == juce::AudioChannelSet::mono() || set == juce::AudioChannelSet::stereo();
    };
    if (layouts.getMainOutputChannelSet() != juce::AudioChannelSet::stereo() || layouts.outputBuses.size() > 2) return false;
    // The Tactors bus: disabled, or one channel per motor (9, or 12 with the back motors), in
    // the layouts of TactorBusLayout.h.
    if (layouts.outputBuses.size() == 2) {
        const auto& tactors = layouts.outputBuses.getReference(1);
        if (! tactors.isDisabled() && ! tactorbus::isTactorLayout(tactors)) return false;
    }
    // The main input and every sidechain (stem) bus: enabled (mono or stereo) or disabled.
    return std::all_of(layouts.inputBuses.begin(), layouts.inputBuses.end(), inputOk);
}

int ArmadilloProcessor::sceneIndex() const noexcept
{
    const int n = static_cast<int>(sceneTable_.scenes.size());
    return juce::jlimit(0, std::max(0, n - 1), static_cast<int>(scene_->load(std::memory_order_relaxed)));
}

EngineRequest ArmadilloProcessor::currentRequest() const
{
    EngineRequest r;
    r.scene = sceneIndex();
    r.sampleRate = sampleRate_.load();
    r.left = settings_[SettingIds::armSide].toString() == "left";
    r.backMotors = static_cast<bool>(settings_[SettingIds::backMotors]);
    r.text = settings_[SettingIds::brailleText].toString().toStdString();
    r.score = settings_[SettingIds::score].toString().toStdString();
    r.touchProfile = settings_[SettingIds::touchProfile].toString().toStdString();
    r.twoArms = static_cast<bool>(settings_[SettingIds::leftArmOsc]);   // every scene hears the left arm too
    r.session = statesLoaded_.load(std::memory_order_relaxed);
    r.route = instrument_.navigation().route();       // a walk runs the navigation scene instead
    r.navigation = instrument_.navigation().link();
    const auto& scenes = sceneTable_.scenes;
    if (r.scene >= 0 && r.scene < static_cast<int>(scenes.size()) && scenes[static_cast<std::size_t>(r.scene)].scene == "audio-touch") {
        std::lock_guard<std::mutex> lock(stemsMutex_);
        r.stems = stems_;
    }
    return r;
}

void ArmadilloProcessor::prepareToPlay(double sampleRate, int)
{
    sampleRate_.store(sampleRate > 0.0 ? sampleRate : 48000.0);
    // The main input (where the listened-to audio sits in processBlock's buffer; the layout is
    // fixed until the next prepareToPlay), heard and played through.
    live::BlockControl::Listen listen;
    if (const auto* input = getBus(true, 0); input != nullptr && input->isEnabled() && input->getNumberOfChannels() > 0) {
        listen.first = input->getChannelIndexInProcessBlockBuffer(0);
        listen.count = input->getNumberOfChannels();
        listen.through = listen.count;
    }
    // The sidechain buses the host enabled (VST3 only): audio-touch's stems, in bus order.
    std::vector<std::string> stems;
    for (int b = 1; b < getBusCount(true) && listen.stemCount < live::BlockControl::kMaxStems; ++b) {
        const auto* bus = getBus(true, b);
        if (bus == nullptr || ! bus->isEnabled() || bus->getNumberOfChannels() < 1) continue;
        auto& stem = listen.stems[static_cast<std::size_t>(listen.stemCount++)];
        stem.first = bus->getChannelIndexInProcessBlockBuffer(0);
        stem.count = std::min(bus->getNumberOfChannels(), 2);
        stems.push_back(bus->getName().toLowerCase().toStdString());
    }
    {
        std::lock_guard<std::mutex> lock(stemsMutex_);
        stems_ = std::move(stems);
    }
    // The Tactors bus (VST3 output bus 1) when the host enabled it.
    if (const auto* bus = getBus(false, 1); bus != nullptr && bus->isEnabled() && tactorbus::isTactorLayout(bus->getCurrentLayout())) {
        listen.tactorCount = bus->getNumberOfChannels();
        for (int k = 0; k < listen.tactorCount; ++k)
            listen.tactorChannel[static_cast<std::size_t>(k)] =
                bus->getChannelIndexInProcessBlockBuffer(tactorbus::juceIndexOfTactor(bus->getCurrentLayout(), k));
    }
    instrument_.setListen(listen);
    engines_.install(currentRequest(), instrument_);
    // A set list prepared for another sample rate is built again for this one (audio is stopped).
    std::string cuesWhy;
    auto cues = instrument_.stageSession().rebuild(settings_[SettingIds::setList].toString().toStdString(),
                                      settings_[SettingIds::setListName].toString().toStdString(), cueBuild(sampleRate_.load()), cuesWhy);
    if (! cuesWhy.empty())
        setStatus("The set list cannot be prepared at " + juce::String(sampleRate_.load()) + " Hz: " + juce::String(cuesWhy));
    instrument_.token().take();   // the idle clock holds it for < 1 ms; audio is stopped during prepareToPlay
    if (cues != nullptr) instrument_.stageSession().install(std::move(cues));
    instrument_.control().prepare(sampleRate_.load());
    hostBlock_.prepare();   // MIDI storage for the host's buffer, off the audio thread
    const auto tactorWhy = juce::String(instrument_.tactorRig().prepareBus(PluginState::tactorSettings(settings_), listen.tactorCount, motorCount(), sampleRate_.load()));
    instrument_.token().release();
    if (tactorWhy.isNotEmpty()) setStatus(tactorWhy);
}

void ArmadilloProcessor::processBlock(juce::AudioBuffer<float>& buffer, juce::MidiBuffer& midi)
{
    juce::ScopedNoDenormals noDenormals;
    hostRunning_.store(true, std::memory_order_relaxed);
    const int n = buffer.getNumSamples();
    const auto listen = instrument_.listen();
    float inPeak = 0.0f;
    for (int c = 0; c < listen.count; ++c)
        if (listen.first + c < buffer.getNumChannels()) inPeak = std::max(inPeak, buffer.getMagnitude(listen.first + c, 0, n));
    for (int k = 0; k < listen.stemCount; ++k) {   // the stems (VST3 sidechain buses) count as input too
        const auto& stem = listen.stems[static_cast<std::size_t>(k)];
        for (int c = stem.first; c < std::min(stem.first + stem.count, buffer.getNumChannels()); ++c)
            inPeak = std::max(inPeak, buffer.getMagnitude(c, 0, n));
    }
    hostBlock_.process(instrument_.control(), buffer, midi, getPlayHead(), isNonRealtime(), listen);
    // The test tone (welcome panel): added over the scene's sound, on the main stereo output.
    if (int left = testToneSamples_.load(std::memory_order_relaxed); left > 0) {
        const int count = std::min(left, n);
        const double step = 2.0 * juce::MathConstants<double>::pi * 440.0 / sampleRate_.load(std::memory_order_relaxed);
        for (int i = 0; i < count; ++i) {
            const auto v = static_cast<float>(0.125 * std::sin(testTonePhase_));
            testTonePhase_ = std::fmod(testTonePhase_ + step, 2.0 * juce::MathConstants<double>::pi);
            for (int c = 0; c < std::min(2, buffer.getNumChannels()); ++c) buffer.addSample(c, i, v);
        }
        testToneSamples_.store(left - count, std::memory_order_relaxed);
    }
    float outPeak = 0.0f;
    for (int c = 0; c < std::min(2, buffer.getNumChannels()); ++c) outPeak = std::max(outPeak, buffer.getMagnitude(c, 0, n));
    if (outPeak > outputPeak_.load(std::memory_order_relaxed)) outputPeak_.store(outPeak, std::memory_order_relaxed);
    if (inPeak > inputPeak_.load(std::memory_order_relaxed)) inputPeak_.store(inPeak, std::memory_order_relaxed);
    audioBlocks_.fetch_add(1, std::memory_order_relaxed);
}

void ArmadilloProcessor::playTestTone(double seconds) noexcept
{
    testToneSamples_.store(static_cast<int>(juce::jlimit(0.0, 10.0, seconds) * sampleRate_.load(std::memory_order_relaxed)),
                           std::memory_order_relaxed);
}

std::uint64_t ArmadilloProcessor::sourceSamples(SourceKind kind) const
{
    return instrument_.sourceSamples(kind);
}

bool ArmadilloProcessor::sceneListens() const
{
    const auto& scenes = sceneTable_.scenes;
    const int index = sceneIndex();
    if (index < 0 || index >= static_cast<int>(scenes.size())) return false;
    const auto& name = scenes[static_cast<std::size_t>(index)].scene;
    return name == "score" || name == "audio-touch";
}

void ArmadilloProcessor::processBlockBypassed(juce::AudioBuffer<float>& buffer, juce::MidiBuffer& midi)
{
    hostRunning_.store(true, std::memory_order_relaxed);
    hostBlock_.bypass(instrument_.control(), buffer, midi);
}

// ------------------------------------------------------------------------------------------------
// Message thread

int ArmadilloProcessor::getNumPrograms()
{
    return static_cast<int>(factoryPresets().size());
}

const juce::String ArmadilloProcessor::getProgramName(int index)
{
    const auto& presets = factoryPresets();
    return index >= 0 && index < static_cast<int>(presets.size()) ? juce::String(presets[static_cast<std::size_t>(index)].name)
                                                                   : juce::String();
}

void ArmadilloProcessor::setCurrentProgram(int index)
{
    if (index < 0 || index >= getNumPrograms()) return;
    requestedProgram_.store(index, std::memory_order_release);   // real-time: one atomic store
    if (juce::MessageManager::existsAndIsCurrentThread()) applyRequestedProgram();
}

void ArmadilloProcessor::applyRequestedProgram()
{
    const int index = requestedProgram_.exchange(-1, std::memory_order_acq_rel);
    if (index < 0) return;
    if (applyFactoryPreset(index, apvts_)) currentProgram_.store(index, std::memory_order_relaxed);
}

void ArmadilloProcessor::timerCallback()
{
    applyRequestedProgram();
    stageTick();
    instrument_.tactorRig().tick();
    if (auto* service = instrument_.messages().service()) {   // messages to the braille scene when it runs
        std::vector<std::string> said;
        training_.with([&](braille::BrailleSceneControls& scene, std::uint64_t) { said = service->present(scene); });
        for (const auto& line : said) {
            messageLog_.add(juce::String(line));
            if (line.find(" on the arm: ") != std::string::npos) speakAnnouncement(juce::String(line), false);
        }
        while (messageLog_.size() > 50) messageLog_.remove(0);
    }
    if (auto* web = instrument_.webServer(); web != nullptr && --webRefreshCountdown_ <= 0) {   // 5 times a second
        webRefreshCountdown_ = 10;
        {
            std::lock_guard<std::mutex> lock(webSceneMutex_);   // what the page's scene choice is refused for, if anything
            webSceneRefusal_ = instrument_.stage().newest() != nullptr ? "a set list plays: choose one of its cues"
                               : instrument_.navigation().route()   ? "a walk plays the navigation scene"
                                                                    : "";
        }
        const auto& scenes = sceneTable_.scenes;
        const int index = sceneIndex();
        instrument_.refreshWeb(instrument_.navigation().route() ? std::string("navigation")
                                                                 : index < static_cast<int>(scenes.size()) ? scenes[static_cast<std::size_t>(index)].scene
                                                                                                           : std::string());
        for (const auto& line : web->takeLines()) {
            webLog_.add(juce::String(line));
            if (line.find("panic") != std::string::npos) speakAnnouncement("Web page: " + juce::String(line), false);
        }
        while (webLog_.size() > 50) webLog_.remove(0);
    }
    if (const auto failure = engines_.takeNewFailure(); failure.isNotEmpty()) setEngineStatus(failure);
    training_.collect();   // keeps a braille training log's queue drained while no panel asks for it
    if (feedbackUntil_ > 0 && instrument_.feedbackPlayer().completed() >= feedbackUntil_) {
        feedbackUntil_ = 0;
        if (std::exchange(feedbackRestart_, false))   // the trial from its first row, now felt
            training_.with([](braille::BrailleSceneControls& scene, std::uint64_t) { scene.restartTrainingTrial(); });
        if (instrument_.proceduresIdle())
            instrument_.control().setStimulus(nullptr);   // the scene has the motors again
    }
    engines_.update(currentRequest());
    // Parameter edits go to the host: not before it has played a block. A host still setting the
    // instance up is not ready for them: pluginval caught JUCE's VST3 host crashing in performEdit
    // while it listed the parameters; and with edits from prepareToPlay on, JUCE's VST3 host and
    // the plugin could disagree: under load the simulated arm's pose, written before the host's
    // first block, stayed in the plugin while the host showed the elevation it had set, and the
    // saved state held the arm's (docs/PLUGIN.md "pluginval"). Before the first block there is
    // nothing to record anyway. The standalone app is its own host.
    if (hostRunning_.load(std::memory_order_relaxed) || wrapperType == wrapperType_Standalone) {
        writeLiveOrientationToParameters();
        writeMacrosToParameters();
    }
    {
        std::lock_guard<std::mutex> lock(mappingMutex_);
        instrument_.mapping().timerTick();
    }
    instrument_.rig().drainCalibration();
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
    const auto f = instrument_.control().latestFrame();
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

void ArmadilloProcessor::writeMacrosToParameters()
{
    // The control side leaves each macro's newest value in an atomic (MappingOutputs); this
    // timer (50 Hz) writes it with setValueNotifyingHost inside a change gesture, as a hand on
    // a knob would, so the host records it as automation or routes it on.
    const double now = juce::Time::getMillisecondCounterHiRes();
    for (int i = 0; i < ParamIds::kMacroCount; ++i) {
        auto& w = macroWrites_[static_cast<std::size_t>(i)];
        auto* p = apvts_.getParameter(ParamIds::macros[i]);
        const float v = instrument_.control().mappingOutputs().macro(i);
        if (p == nullptr) continue;
        if (std::isfinite(v) && std::abs(v - w.last) > 1.0e-5f) {
            if (! w.open) p->beginChangeGesture();
            w.open = true;
            w.last = v;
            w.changedMs = now;
            p->setValueNotifyingHost(v);
        } else if (w.open && now - w.changedMs > kMacroGestureIdleMs) {
            p->endChangeGesture();
            w.open = false;
        }
    }
}

void ArmadilloProcessor::setOrientationFromUser(const core::Pose& pose)
{
    if (isLiveSource(source())) return;   // live sources own the orientation parameters
    const float values[3] {static_cast<float>(pose.elevationDeg), static_cast<float>(core::wrapDeg360(pose.azimuthDeg)),
                           static_cast<float>(core::wrapDeg180(pose.rollDeg))};
    const char* ids[3] {ParamIds::elevation, ParamIds::azimuth, ParamIds::roll};
    for (int i = 0; i < 3; ++i) {
        auto* p = apvts_.getParameter(ids[i]);
        p->beginChangeGesture();
        p->setValueNotifyingHost(p->convertTo0to1(values[i]));
        p->endChangeGesture();
    }
}

void ArmadilloProcessor::steerSimulator(const core::Pose& pose)
{
    instrument_.rig().steerSimulator(pose);
    settings_.setProperty(SettingIds::simWandering, false, nullptr);
}

void ArmadilloProcessor::setSimulatorWandering(bool on)
{
    settings_.setProperty(SettingIds::simWandering, on, nullptr);
}

void ArmadilloProcessor::valueTreePropertyChanged(juce::ValueTree&, const juce::Identifier& id)
{
    if (id == SettingIds::simWandering) {
        instrument_.rig().setSimulatorWandering(static_cast<bool>(settings_[SettingIds::simWandering]));
    } else if (id == SettingIds::serialPort || id == SettingIds::connectOnStart) {
        autoConnectTried_ = false;
        if (id == SettingIds::serialPort && deviceConnected()) connectDevice(false);
    } else if (id == SettingIds::midiChannel) {
        std::lock_guard<std::mutex> lock(mappingMutex_);
        if (instrument_.mapping().name() == "classic") instrument_.mapping().usePreset("classic");   // the classic wiring's channel
    } else if (id == SettingIds::leftArmOsc || id == SettingIds::leftArmOscPort) {
        applyLeftArm();
        // A set list's cues are built for one or two arms: switching the left arm rebuilds them
        // (from cue 1, as loading it does).
        if (id == SettingIds::leftArmOsc && settings_[SettingIds::setList].toString().isNotEmpty())
            if (const auto why = useSetList(settings_[SettingIds::setList].toString(), settings_[SettingIds::setListName].toString()); why.isNotEmpty())
                setStatus(why);
    } else if (id == SettingIds::stageOscEnabled || id == SettingIds::stageOscPort || id == SettingIds::stageOscBind || id == SettingIds::stageOscAllow) {
        applyStageOsc();
    } else if (id == SettingIds::cueNextNote || id == SettingIds::cuePrevNote) {
        instrument_.stage().setCueNotes(static_cast<int>(settings_[SettingIds::cueNextNote]), static_cast<int>(settings_[SettingIds::cuePrevNote]));
    } else if (id == SettingIds::panicGesture) {
        instrument_.stage().setPanicGesture(static_cast<bool>(settings_[SettingIds::panicGesture]));
    } else if (id == SettingIds::tactorModel || id == SettingIds::tactorMap || id == SettingIds::tactorGains || id == SettingIds::tactorSound
               || id == SettingIds::backMotors
               || ((id == SettingIds::tactorDevice || id == SettingIds::tactorConnect) && instrument_.tactorRig().outputOpen())) {
        if (const auto why = instrument_.tactorRig().settingsChanged(PluginState::tactorSettings(settings_), motorCount()); ! why.empty()) setStatus(juce::String(why));
    } else if (id == SettingIds::mqttEnabled) {
        if (static_cast<bool>(settings_[SettingIds::mqttEnabled]) != instrument_.messages().running())
            if (const auto why = setMessages(static_cast<bool>(settings_[SettingIds::mqttEnabled])); why.isNotEmpty()) setStatus(why);
    } else if (id == SettingIds::webEnabled) {
        if (static_cast<bool>(settings_[SettingIds::webEnabled]) != (instrument_.webServer() != nullptr))
            if (const auto why = setWebPage(static_cast<bool>(settings_[SettingIds::webEnabled])); why.isNotEmpty()) setStatus(why);
    } else if ((id == SettingIds::webPort || id == SettingIds::webBind) && instrument_.webServer() != nullptr) {
        if (const auto why = setWebPage(true); why.isNotEmpty()) setStatus(why);   // reopened where it is asked to be
    } else if (id == SettingIds::tactorOutput) {
        if (static_cast<bool>(settings_[SettingIds::tactorOutput]) != instrument_.tactorRig().outputOpen())
            if (const auto why = setTactorOutput(static_cast<bool>(settings_[SettingIds::tactorOutput])); why.isNotEmpty()) setStatus(why);
    } else if (id == SettingIds::readerVoice || id == SettingIds::speechRate) {
        applyVoiceSettings();
    } else if (id == SettingIds::oscOutEnabled || id == SettingIds::oscOutHost || id == SettingIds::oscOutPort
               || id == SettingIds::oscInEnabled || id == SettingIds::oscInPort || id == SettingIds::oscInFormat
               || id == SettingIds::oscInMount) {
        applyNetworkSettings();
    }
}

void ArmadilloProcessor::applyVoiceSettings()
{
    const auto mode = settings_[SettingIds::readerVoice].toString();
    voice_->setRate(static_cast<int>(settings_[SettingIds::speechRate]));
    if (mode == voiceOpened_) return;
    voiceOpened_ = mode;
    const bool on = mode == "on"
                    || (mode == "auto" && wrapperType == wrapperType_Standalone
                        && access::ReaderVoice::readerDetected("/proc", access::ReaderVoice::defaultSockets()));
    if (! on) {
        voice_->close();
        voiceOn_ = false;
        return;
    }
    const auto speech = juce::SystemStats::getEnvironmentVariable("ARMADILLO_SPEECH", "auto").toStdString();
    const auto display = juce::SystemStats::getEnvironmentVariable("ARMADILLO_BRAILLE", "brlapi").toStdString();
    const auto problems = voice_->open(speech, display);
    voiceOn_ = voice_->speaking() || voice_->showing();
    // A display or voice that is missing is said on what there is (and in the status line).
    if (! problems.empty()) setStatus("Self-voicing: " + juce::String(problems));
    if (voiceOn_) voice_->say("ARMadillo. Self-voicing on. F3 repeats, F4 stops speech.", true);
}

namespace {
/// The reader's touch profile (the setting) on the training player, as every scene has it; none
/// (all 1) when there is none or it does not parse.
void fitToReader(access::TactilePlayer& player, const juce::ValueTree& settings)
{
    auto gains = tactile::TactileConfig::unitMotorGains();
    if (const auto json = settings[SettingIds::touchProfile].toString(); json.isNotEmpty()) {
        try {
            gains = link::touchProfileGains(link::parseTouchProfile(json.toStdString(), "the touch profile setting"));
        } catch (const std::exception&) {
        }
    }
    player.setMotorGains(gains);
}
} // namespace

procedures::AdaptiveChoices ArmadilloProcessor::adaptiveChoices() const
{
    procedures::AdaptiveChoices c;
    c.trials = static_cast<int>(settings_[SettingIds::adaptiveTrials]);
    c.stages = settings_[SettingIds::adaptiveStages].toString().toStdString();
    c.method = settings_[SettingIds::adaptiveMethod].toString().toStdString();
    c.level = static_cast<int>(settings_[SettingIds::adaptiveLevel]);
    return c;
}

bool ArmadilloProcessor::beginAdaptive(const juce::File& readerProfile, juce::String& why)
{
    if (instrument_.touchTest().state() != procedures::TouchTest::State::Idle) endTouchTest(false);
    std::string reason;
    fitToReader(instrument_.feedbackPlayer(), settings_);   // the cells and cues felt alike on every motor, as in a scene
    instrument_.control().setStimulus(&instrument_.feedbackPlayer());   // before the first trial is queued: its cue plays at once
    if (! instrument_.adaptive().begin(readerProfile.getFullPathName().toStdString(), adaptiveChoices(), reason)) {
        instrument_.control().setStimulus(nullptr);
        why = juce::String(reason);
        return false;
    }
    settings_.setProperty(SettingIds::readerProfile, readerProfile.getFullPathName(), nullptr);
    return true;
}

void ArmadilloProcessor::endAdaptive()
{
    instrument_.adaptive().stop();
    if (instrument_.touchTest().state() == procedures::TouchTest::State::Idle) instrument_.control().setStimulus(nullptr);
}

void ArmadilloProcessor::beginTouchTest(std::uint64_t seed)
{
    if (instrument_.adaptive().state() != procedures::AdaptiveTraining::State::Idle) endAdaptive();
    instrument_.touchTest().begin(seed);
    instrument_.control().setStimulus(&instrument_.touchTest().player());
}

void ArmadilloProcessor::endTouchTest(bool keep)
{
    instrument_.control().setStimulus(nullptr);
    if (keep && instrument_.touchTest().state() == procedures::TouchTest::State::Done) {
        auto profile = instrument_.touchTest().profile();
        profile.arm = settings_[SettingIds::armSide].toString().toStdString();
        settings_.setProperty(SettingIds::touchProfile, juce::String(link::touchProfileToJson(profile)), nullptr);
    }
    instrument_.touchTest().cancel();
}

juce::String ArmadilloProcessor::startNavigation(const juce::File& route, navigation::NavigationRig::Source source, const juce::String& where)
{
    const juce::String why(instrument_.navigation().start(route.getFullPathName().toStdString(), source, where.toStdString()));
    engines_.update(currentRequest());   // the navigation scene is offered now (or the chosen scene again)
    return why;
}

void ArmadilloProcessor::stopNavigation()
{
    instrument_.navigation().stop();
    engines_.update(currentRequest());
}

live::BlockWebView::Host ArmadilloProcessor::webHost()
{
    live::BlockWebView::Host host;
    // The playing scene's exposed parameters, as the host holds them (an atomic read each).
    const auto specsOfScene = [this]() -> const live::SceneParameterTable::Entry* {
        const int index = sceneIndex();
        return index < static_cast<int>(sceneTable_.scenes.size()) ? &sceneTable_.scenes[static_cast<std::size_t>(index)] : nullptr;
    };
    host.parameters = [this, specsOfScene] {
        std::vector<web::ParameterInfo> out;
        if (const auto* entry = specsOfScene())
            for (std::size_t i = 0; i < entry->specs.size(); ++i) {
                if (! entry->exposed[i]) continue;
                const core::ParamSpec& spec = entry->specs[i];
                const auto* value = apvts_.getRawParameterValue(juce::String(spec.id));
                out.push_back({spec.id, spec.name, spec.unit, spec.min, spec.max, value != nullptr ? static_cast<double>(value->load()) : spec.defaultValue,
                               spec.choices});
            }
        return out;
    };
    host.setParameter = [this, specsOfScene](const std::string& id, double value, double& set) {
        const auto* entry = specsOfScene();
        if (entry == nullptr) return false;
        for (std::size_t i = 0; i < entry->specs.size(); ++i) {
            if (! entry->exposed[i] || entry->specs[i].id != id) continue;
            mapping::SceneParamChange change;
            change.value = static_cast<float>(std::clamp(value, -1e9, 1e9));
            change.normalised = false;
            const float v = live::sceneParamValue(entry->specs[i], change);   // clamped, a choice rounded
            set = v;
            // The host's parameter, as a gesture of the page's: on the message thread.
            juce::MessageManager::callAsync([this, alive = alive_, paramId = juce::String(id), v] {
                if (! *alive) return;
                if (auto* p = apvts_.getParameter(paramId)) {
                    p->beginChangeGesture();
                    p->setValueNotifyingHost(p->convertTo0to1(v));
                    p->endChangeGesture();
                }
            });
            return true;
        }
        return false;
    };
    // The scene: the host's `scene` parameter, as a gesture of the page's (message thread).
    const auto choiceRefusal = [this]() -> std::string {   // as the timer last saw it (webSceneRefusal_)
        std::lock_guard<std::mutex> lock(webSceneMutex_);
        return webSceneRefusal_;
    };
    host.sceneChoices = [this, choiceRefusal](std::string& why) {
        why = choiceRefusal();
        std::vector<std::string> names;
        if (why.empty())
            for (const auto& entry : sceneTable_.scenes)
                if (entry.available) names.push_back(entry.scene);
        return names;
    };
    host.chooseScene = [this, choiceRefusal](const std::string& name) -> std::string {
        if (auto why = choiceRefusal(); ! why.empty()) return why;
        const auto& scenes = sceneTable_.scenes;
        for (std::size_t i = 0; i < scenes.size(); ++i) {
            if (scenes[i].scene != name) continue;
            if (! scenes[i].available) return scenes[i].reason;
            juce::MessageManager::callAsync([this, alive = alive_, index = static_cast<float>(i)] {
                if (! *alive) return;
                if (auto* p = apvts_.getParameter(ParamIds::scene)) {
                    p->beginChangeGesture();
                    p->setValueNotifyingHost(p->convertTo0to1(index));
                    p->endChangeGesture();
                }
            });
            return {};
        }
        return "no scene '" + name + "'";
    };
    // The sensitivity test as the Reader window runs it: the measured profile becomes the reader's.
    host.beginTouchTest = [this](std::uint64_t seed) { beginTouchTest(seed); };
    host.endTouchTest = [this](bool keep) { endTouchTest(keep); };
    return host;
}

juce::String ArmadilloProcessor::setWebPage(bool on)
{
    juce::String why;
    if (on) {
        web::WebConfig config;
        config.on = true;
        config.port = static_cast<int>(settings_[SettingIds::webPort]);
        config.bind = settings_[SettingIds::webBind].toString().trim().toStdString();
        if (config.port < 0 || config.port > 65535) why = "Web page: the port must be 0 (a free one) to 65535";
        else if (! config.bind.empty() && ! web::isNumericAddress(config.bind)) why = "Web page: the address must be numeric (such as 0.0.0.0 or 192.168.1.20)";
        else why = juce::String(instrument_.startWeb(config, webHost()));
        webRefreshCountdown_ = 0;
    } else {
        instrument_.stopWeb();
    }
    settings_.setProperty(SettingIds::webEnabled, instrument_.webServer() != nullptr, nullptr);   // off again when it failed
    return why;
}

juce::String ArmadilloProcessor::webAddress() const
{
    auto* web = const_cast<live::BlockInstrument&>(instrument_).webServer();
    return web != nullptr ? juce::String(web->address()) : juce::String();
}

juce::String ArmadilloProcessor::setMessages(bool on)
{
    juce::String why;
    if (on) why = juce::String(instrument_.startMessages(PluginState::messagesSettings(settings_)));
    else instrument_.stopMessages();   // the mapping's mqtt destinations go out through the running service
    settings_.setProperty(SettingIds::mqttEnabled, instrument_.messages().running(), nullptr);   // off again when it failed
    return why;
}

int ArmadilloProcessor::motorCount() const
{
    return static_cast<bool>(settings_[SettingIds::backMotors]) ? core::kGridMotors + core::kBackMotors : core::kGridMotors;
}

juce::String ArmadilloProcessor::setTactorOutput(bool on)
{
    juce::String why;
    if (on && wrapperType != wrapperType_Standalone) why = "Tactors: in a host, route the Tactors output bus instead";
    else if (on) why = juce::String(instrument_.tactorRig().openOutput(PluginState::tactorSettings(settings_), motorCount()));
    else instrument_.tactorRig().closeOutput();
    settings_.setProperty(SettingIds::tactorOutput, instrument_.tactorRig().outputOpen(), nullptr);   // off again when it failed
    return why;
}

juce::String ArmadilloProcessor::testTactorChannel(int channel)
{
    const int motor = instrument_.tactorRig().motorOfChannel(channel, PluginState::tactorSettings(settings_), motorCount());
    if (motor < 0 || motor >= motorCount()) return "Tactor channel " + juce::String(channel + 1) + " is silent in the map";
    if (! instrument_.proceduresIdle())
        return "The sensitivity test or the training has the motors: end it first";
    fitToReader(instrument_.feedbackPlayer(), settings_);
    access::TactileSegment buzz;
    buzz.duration = 0.5;
    buzz.motors = static_cast<std::uint16_t>(1u << motor);
    buzz.level = 8.0f;
    feedbackUntil_ = instrument_.feedbackPlayer().play({buzz}, 0.1);
    feedbackRestart_ = false;
    instrument_.control().setStimulus(&instrument_.feedbackPlayer());
    return {};
}

void ArmadilloProcessor::armFeedback(bool right, const std::string& expected)
{
    if (! static_cast<bool>(settings_[SettingIds::armFeedback])) return;
    if (! instrument_.proceduresIdle()) return;
    fitToReader(instrument_.feedbackPlayer(), settings_);
    // Right / wrong, then (wrong) the right letters or words again, then the "next" cue.
    feedbackUntil_ = instrument_.feedbackPlayer().play(access::feedbackSequence(right, expected, 10.0f), 0.2);
    feedbackRestart_ = true;
    instrument_.control().setStimulus(&instrument_.feedbackPlayer());
}

void ArmadilloProcessor::speakAnnouncement(const juce::String& text, bool interrupt) const
{
    if (voiceOn_) voice_->say(text.toStdString(), interrupt);
}

void ArmadilloProcessor::applyNetworkSettings()
{
    instrument_.rig().configureOsc(static_cast<bool>(settings_[SettingIds::oscOutEnabled]), settings_[SettingIds::oscOutHost].toString().toStdString(),
                              static_cast<int>(settings_[SettingIds::oscOutPort]), static_cast<bool>(settings_[SettingIds::oscInEnabled]),
                              static_cast<int>(settings_[SettingIds::oscInPort]), settings_[SettingIds::oscInFormat].toString().toStdString(),
                              settings_[SettingIds::oscInMount].toString().toStdString());
    std::lock_guard<std::mutex> lock(mappingMutex_);
    instrument_.mapping().setDefaultOscTarget(settings_[SettingIds::oscOutHost].toString().toStdString(), static_cast<int>(settings_[SettingIds::oscOutPort]));
}

void ArmadilloProcessor::applyLeftArm()
{
    // The receiver opens (or closes) here; the engine is rebuilt with twoArms by the timer's
    // request (currentRequest), and the control side fuses the left arm only while it listens.
    const auto why = instrument_.rig().configureLeftArmOsc(static_cast<bool>(settings_[SettingIds::leftArmOsc]),
                                                      static_cast<int>(settings_[SettingIds::leftArmOscPort]));
    if (! why.empty()) setStatus(juce::String(why));
}

std::uint64_t ArmadilloProcessor::leftArmSamples() const
{
    return instrument_.leftArmSamples();
}

juce::String ArmadilloProcessor::mappingStatus() const
{
    juce::String s;
    if (wrapperType == wrapperType_Standalone) s << midiPort_.status() << "\n";
    s << "Mapping OSC sent " << juce::String(static_cast<juce::int64>(instrument_.rig().mappingOscSent())) << ", dropped "
      << juce::String(static_cast<juce::int64>(instrument_.rig().mappingOscDropped() + instrument_.control().mappingOutputs().oscDropped()))
      << "; MIDI events dropped " << juce::String(static_cast<juce::int64>(instrument_.control().midiDropped()));
    return s;
}

void ArmadilloProcessor::connectDevice(bool connect)
{
    if (! connect) {
        instrument_.rig().disconnectDevice();
        return;
    }
    // Connect means "play from the device": the source follows, so the simulator (or OSC) can no
    // longer move the arm while the device stays silent; the status line then says it is silent.
    if (auto* p = apvts_.getParameter(ParamIds::source); p != nullptr && source() != SourceKind::Device)
        p->setValueNotifyingHost(p->convertTo0to1(static_cast<float>(SourceKind::Device)));
    instrument_.rig().connectDevice(settings_[SettingIds::serialPort].toString().toStdString(), static_cast<int>(settings_[SettingIds::baudRate]),
                               settings_[SettingIds::calibrationFile].toString().toStdString());
}

bool ArmadilloProcessor::saveCalibration(const juce::File& file, juce::String& message)
{
    std::string said;
    const bool saved = instrument_.rig().saveCalibration(file.getFullPathName().toStdString(), settings_[SettingIds::serialPort].toString().toStdString(), said);
    message = juce::String(said);
    if (! saved) return false;
    settings_.setProperty(SettingIds::calibrationFile, file.getFullPathName(), nullptr);
    return true;
}

void ArmadilloProcessor::setStatus(const juce::String& message)
{
    std::lock_guard<std::mutex> lock(statusMutex_);
    status_ = message;
    statusFromEngine_ = false;
}

void ArmadilloProcessor::setEngineStatus(const juce::String& message)
{
    std::lock_guard<std::mutex> lock(statusMutex_);
    if (message.isNotEmpty()) {
        status_ = message;
        statusFromEngine_ = true;
    } else if (statusFromEngine_) {
        // The scene (score, text...) that could not start now starts: the banner goes.
        status_.clear();
        statusFromEngine_ = false;
    }
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
// State (PluginState.h)

void ArmadilloProcessor::getStateInformation(juce::MemoryBlock& destData)
{
    std::lock_guard<std::mutex> lock(mappingMutex_);
    PluginState::save(apvts_, settings_, destData, PluginState::mappingNode(instrument_.mapping().toSaved()));
}

juce::String ArmadilloProcessor::saveSetup(const juce::File& file)
{
    juce::MemoryBlock state;
    getStateInformation(state);
    return PluginState::writeSetupFile(state, file);
}

juce::String ArmadilloProcessor::loadSetup(const juce::File& file)
{
    juce::MemoryBlock state;
    if (auto why = PluginState::readSetupFile(file, state); why.isNotEmpty()) return why;
    setStateInformation(state.getData(), static_cast<int>(state.getSize()));
    return {};
}

void ArmadilloProcessor::setStateInformation(const void* data, int sizeInBytes)
{
    // A program asked for before (from a host thread, waiting for the timer) is superseded by
    // the state: applied after it, it would change the scene the state restored.
    requestedProgram_.store(-1, std::memory_order_release);
    juce::ValueTree mapping;
    auto message = PluginState::restore(*this, apvts_, settings_, data, sizeInBytes, &mapping);
    // The session plays as it was saved: a fresh engine (the scene's own state — a reference
    // heading, a glide, a follower's place — and the arm's history), not what this instance
    // played before its state came.
    statesLoaded_.fetch_add(1, std::memory_order_relaxed);
    if (const auto why = applySavedSetList(); why.isNotEmpty()) message = (message + " " + why).trim();
    {
        std::lock_guard<std::mutex> lock(mappingMutex_);
        if (const auto why = instrument_.mapping().fromSaved(PluginState::savedMapping(mapping)); ! why.empty()) message = (message + " " + juce::String(why)).trim();
    }
    setStatus(message);
    // Built here (the host's thread, which may allocate) and offered now, so the first block
    // after the state plays it: a host that bounces right after opening the session renders
    // faster than the timer ticks. Only when a hand-over is still in flight does it wait for
    // the timer's next update. After the state's message: a scene that cannot start says so.
    engines_.update(currentRequest());
}

// ------------------------------------------------------------------------------------------------
// On stage (Stage.h, docs/STAGE.md)

live::CueBuild ArmadilloProcessor::cueBuild(double sampleRate) const
{
    live::CueBuild b;
    b.base.sampleRate = sampleRate > 0.0 ? sampleRate : 48000.0;
    b.base.controlRateHz = kControlRateHz;
    b.base.seed = 1;
    b.base.side = settings_[SettingIds::armSide].toString() == "left" ? core::ArmSide::Left : core::ArmSide::Right;
    b.motors = static_cast<bool>(settings_[SettingIds::backMotors]) ? core::kGridMotors + core::kBackMotors : core::kGridMotors;
    // The reader's touch profile for every cue, as the Scene box's engine gets it (EngineHandover);
    // the settings only keep a profile that parses (PluginState.cpp), so a failure here is moot.
    if (const auto json = settings_[SettingIds::touchProfile].toString(); json.isNotEmpty()) {
        try {
            b.gains = link::touchProfileGains(link::parseTouchProfile(json.toStdString(), "the touch profile setting"));
        } catch (const std::exception&) {
        }
    }
    // With the left arm on, every cue's engine takes it too (as the Scene box's engine does).
    b.twoArms = static_cast<bool>(settings_[SettingIds::leftArmOsc]);
    return b;
}

juce::String ArmadilloProcessor::useSetList(const juce::String& text, const juce::String& name)
{
    std::string summary;
    if (const auto why = instrument_.stageSession().use(text.toStdString(), name.toStdString(), cueBuild(sampleRate_.load()), summary); ! why.empty())
        return juce::String(why);
    settings_.setProperty(SettingIds::setListName, name, nullptr);
    settings_.setProperty(SettingIds::setList, text, nullptr);
    setStatus(juce::String(summary));
    return {};
}

juce::String ArmadilloProcessor::loadSetList(const juce::File& file)
{
    std::string text;
    if (const auto why = live::StageSession::readFile(file.getFullPathName().toStdString(), text); ! why.empty()) return juce::String(why);
    return useSetList(juce::String::fromUTF8(text.data(), static_cast<int>(text.size())), file.getFileName());
}

void ArmadilloProcessor::clearSetList()
{
    instrument_.stageSession().clear();
    settings_.setProperty(SettingIds::setList, "", nullptr);
    settings_.setProperty(SettingIds::setListName, "", nullptr);
}

juce::String ArmadilloProcessor::applySavedSetList()
{
    const auto text = settings_[SettingIds::setList].toString();
    const auto name = settings_[SettingIds::setListName].toString();
    if (text.isEmpty()) {
        if (instrument_.stageSession().loaded()) clearSetList();
        return {};
    }
    const auto why = useSetList(text, name.isNotEmpty() ? name : juce::String("the saved set list"));
    if (why.isEmpty()) return {};
    clearSetList();   // nothing half-used: the single scene plays
    return "The saved set list is not used: " + why;
}

void ArmadilloProcessor::stageTick()
{
    const auto report = instrument_.stageSession().tick();
    for (const auto& refused : report.refused) setStatus(juce::String(refused));   // each sender once
    if (report.panicked) {
        setStatus("PANIC: all sound and every motor off, the notes sent ended (CC 120 and 123 on all channels). "
                  "Resume: R in the performance view, Stage > Resume, or MIDI CC 119.");
        announce(*this, "stage", "Panic: all sound and every motor off.", juce::AccessibilityHandler::AnnouncementPriority::high);
    } else if (report.resumed) {
        setStatus("Resumed.");
        announce(*this, "stage", "Resumed.", juce::AccessibilityHandler::AnnouncementPriority::high);
    }
    if (! report.cue.empty()) {
        if (! instrument_.stage().panicked()) setStatus(juce::String(report.cue));
        announce(*this, "stage", juce::String(report.cue), juce::AccessibilityHandler::AnnouncementPriority::medium);
    }
}

void ArmadilloProcessor::applyStageOsc()
{
    live::StageControlListen listen;   // loopback unless stageOscBind says otherwise (docs/SECURITY.md)
    auto why = live::StageSession::listenFromSettings(settings_[SettingIds::stageOscBind].toString().toStdString(),
                                                      settings_[SettingIds::stageOscAllow].toString().toStdString(), listen);
    if (why.empty())
        why = instrument_.stageSession().setOsc(static_cast<bool>(settings_[SettingIds::stageOscEnabled]), static_cast<int>(settings_[SettingIds::stageOscPort]), listen);
    if (! why.empty()) setStatus("OSC stage commands: " + juce::String(why));
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
