#pragma once
// The plugin/standalone shell over the live instrument (Surge habit: the engine is a library, this
// is glue). It holds three objects of the core: the scenes' parameter table (the parameter layout
// is built from it), the instrument (Live/Session/BlockInstrument.h: sources, control step on the block
// clock, stage, mapping, tactors, navigation, messages, procedures — built and torn down in one
// order) and the self-voicing. What is the host's stays here, each part stating its own threads:
//  - EngineHandover.h  engines built from the parameters on the message thread, handed to the
//                      instrument's control loop lock-free;
//  - HostBlock.h       the host's buffers, MIDI and play head as the block clock takes them;
//  - PluginState.h     saved state and settings, validated on the way in;
//  - TrainingAccess.h  braille training for the Training panel.
// This class adds the AudioProcessor entry points, the message-thread timer (engine updates,
// live orientation → parameters with change gestures, auto-connect) and the status line.
#include "Access/ReaderVoice.h"
#include "Live/Session/BlockInstrument.h"
#include "Plugin/Accessibility.h"
#include "Plugin/EngineHandover.h"
#include "Plugin/HostBlock.h"
#include "Plugin/MidiPort.h"
#include "Plugin/Parameters.h"
#include "Plugin/PluginState.h"
#include "Plugin/TrainingAccess.h"
#include <juce_audio_processors/juce_audio_processors.h>
#include <array>
#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace armadillo::plugin {

class ArmadilloProcessor : public juce::AudioProcessor,
                           public SpokenAnnouncements,
                           private juce::Timer,
                           private juce::ValueTree::Listener {
public:
    static constexpr int kStateVersion = PluginState::kVersion;
    static constexpr double kControlRateHz = live::BlockControl::kControlRateHz;
    static constexpr double kTailSeconds = 5.0;   ///< longest ring-out: cymbal crash (~4 s) + FM tail

    ArmadilloProcessor();
    ~ArmadilloProcessor() override;

    // juce::AudioProcessor (host threads as JUCE documents them; processBlock is the audio thread)
    void prepareToPlay(double sampleRate, int samplesPerBlock) override;
    void releaseResources() override {}
    bool isBusesLayoutSupported(const BusesLayout& layouts) const override;
    void processBlock(juce::AudioBuffer<float>&, juce::MidiBuffer&) override;
    using juce::AudioProcessor::processBlock;
    /// The host's bypass: silence, and no MIDI (the input is not passed through; the mapping's
    /// sounding notes end in the first bypassed block).
    void processBlockBypassed(juce::AudioBuffer<float>&, juce::MidiBuffer&) override;
    using juce::AudioProcessor::processBlockBypassed;
    juce::AudioProcessorEditor* createEditor() override;
    bool hasEditor() const override { return true; }
    const juce::String getName() const override { return "ARMadillo"; }
    bool acceptsMidi() const override { return true; }   // stage messages and MIDI learn; the input is not played
    bool producesMidi() const override { return true; }
    bool isMidiEffect() const override { return false; }
    double getTailLengthSeconds() const override { return kTailSeconds; }
    // Programs: the factory presets (FactoryPresets.h). setCurrentProgram may come from a host's
    // audio thread: it records the request, the message thread applies it (at once when called there).
    int getNumPrograms() override;
    int getCurrentProgram() override { return currentProgram_.load(std::memory_order_relaxed); }
    void setCurrentProgram(int index) override;
    const juce::String getProgramName(int index) override;
    void changeProgramName(int, const juce::String&) override {}
    void getStateInformation(juce::MemoryBlock& destData) override;
    void setStateInformation(const void* data, int sizeInBytes) override;
    /// The app's "Save setup..." / "Load setup...": the whole state as a readable file (message
    /// thread). Return "" or what went wrong; loading reports refused values in the status line.
    juce::String saveSetup(const juce::File& file);
    juce::String loadSetup(const juce::File& file);

    // For the editor (message thread)
    juce::AudioProcessorValueTreeState& parameters() noexcept { return apvts_; }
    juce::ValueTree& settings() noexcept { return settings_; }
    const SceneParameterTable& sceneTable() const noexcept { return sceneTable_; }
    live::ArmFrame latestFrame() const noexcept { return instrument_.control().latestFrame(); }
    SourceKind source() const noexcept { return instrument_.control().source(); }
    int sceneIndex() const noexcept;
    juce::String statusMessage() const;
    void clearStatusMessage();
    core::Pose simulatorPose() const { return instrument_.rig().simulatorPose(); }
    bool simulatorWandering() const { return instrument_.rig().simulatorWandering(); }
    void steerSimulator(const core::Pose& pose);
    void setSimulatorWandering(bool on);
    /// Arm view / keyboard under host automation: user edits of the orientation parameters.
    void setOrientationFromUser(const core::Pose& pose);
    juce::String linkStatus() const { return juce::String(instrument_.rig().linkStatus()); }
    void connectDevice(bool connect);
    bool deviceConnected() const noexcept { return instrument_.rig().deviceConnected(); }
    const procedures::DeviceCalibration& calibration() const noexcept { return instrument_.rig().calibration(); }
    bool beginCalibration(juce::String& why)
    {
        std::string w;
        const bool ok = instrument_.rig().beginCalibration(w);
        why = juce::String(w);
        return ok;
    }
    bool calibrationNext(juce::String& why)
    {
        std::string w;
        const bool ok = instrument_.rig().calibrationNext(w);
        why = juce::String(w);
        return ok;
    }
    void calibrationSkip() { instrument_.rig().calibrationSkip(); }
    void cancelCalibration() { instrument_.rig().cancelCalibration(); }
    /// Writes the applied guided result as calibration JSON and remembers the file in the
    /// settings (the next connection loads it). False with the reason when it cannot be written.
    bool saveCalibration(const juce::File& file, juce::String& message);
    /// Braille training (TrainingAccess.h).
    bool withBrailleTraining(const std::function<void(braille::BrailleSceneControls&, std::uint64_t generation)>& use)
    {
        return training_.with(use);
    }
    bool copyBrailleTrainingLog(std::uint64_t generation, std::string& csv, juce::String& why)
    {
        return training_.copyLog(generation, csv, why);
    }
    std::uint64_t oscMessagesSent() const noexcept { return instrument_.rig().oscMessagesSent(); }
    live::OscInput& oscInput() noexcept { return instrument_.rig().oscInput(); }
    const char* lastGesture() const noexcept { return instrument_.control().lastGesture(); }
    std::uint64_t gestureCount() const noexcept { return instrument_.control().gestureCount(); }
    double controlRateMeasured() const noexcept { return instrument_.rig().controlRateMeasured(); }
    /// The mapping set (message thread; the host's state calls take the same lock).
    struct MappingAccess {
        std::unique_lock<std::mutex> lock;
        live::MappingSession& session;
        live::MappingSession* operator->() const noexcept { return &session; }
    };
    MappingAccess mapping() { return {std::unique_lock<std::mutex>(mappingMutex_), instrument_.mapping()}; }
    /// Self-voicing and the braille display (ReaderVoice.h; message thread). On when the
    /// readerVoice setting is "on", or "auto" in the standalone app while a screen reader or
    /// brltty runs. ARMADILLO_SPEECH / ARMADILLO_BRAILLE name the backends (default auto / brlapi).
    access::ReaderVoice& voice() noexcept { return *voice_; }
    bool voiceOn() const noexcept { return voiceOn_; }
    void speakAnnouncement(const juce::String& text, bool interrupt) const override;
    /// The sensitivity test (Procedures/TouchTest.h; message thread): while it runs, the motors play
    /// its stimuli instead of the scene. endTouchTest(true) keeps a finished test's profile as
    /// the touchProfile setting (applied to every scene, saved in the state).
    procedures::TouchTest& touchTest() noexcept { return instrument_.touchTest(); }
    void beginTouchTest(std::uint64_t seed);
    void endTouchTest(bool keep);
    /// Braille training's answer felt on the arm when the armFeedback setting is on (a deafblind
    /// reader): Access/Feedback.h's "right" / "wrong" sensation in place of the scene's levels,
    /// then, when wrong and `expected` is letters or words, its cells drawn again (passive
    /// drawing, as the CLI's --arm-only), then the "next" cue (through its own TactileEngine and
    /// SafetyStage, with the reader's touch profile as every scene has it). Until it has played
    /// armFeedbackPlaying() is true: the Training
    /// panel holds the next prompt back, and the scene's trial starts again from its first row
    /// once it is over (so rows rolled past under the feedback are shown again).
    /// Not during the sensitivity test or the adaptive training. Message thread.
    void armFeedback(bool right, const std::string& expected = {});
    bool armFeedbackPlaying() const noexcept { return feedbackUntil_ > 0 && instrument_.feedbackPlayer().completed() < feedbackUntil_; }
    /// Adaptive training (Procedures/AdaptiveTraining.h; message thread): while it runs its cells and cues
    /// take the motors in place of the scene, with the reader's touch profile. Its choices come from the settings
    /// (adaptiveChoices(); SettingIds::adaptiveTrials …); the reader profile becomes the
    /// readerProfile setting (the Training panel adds its answers there too).
    procedures::AdaptiveTraining& adaptive() noexcept { return instrument_.adaptive(); }
    procedures::AdaptiveChoices adaptiveChoices() const;
    bool beginAdaptive(const juce::File& readerProfile, juce::String& why);
    void endAdaptive();
    /// The standalone app's MIDI port line ("" in a host), the mapping's OSC and drop counters.
    juce::String mappingStatus() const;

    // The app's status line and welcome (message thread reads; the audio thread only counts).
    /// Samples the given source has delivered so far: the simulator's steps, the device link's
    /// good packets, OSC orientation/IMU messages (0 for host automation, which sends none).
    std::uint64_t sourceSamples(SourceKind kind) const;
    /// The left arm (docs/STAGE.md "Two arms"): whether its OSC sender is in use and listened to,
    /// its port, and the orientation/IMU messages it delivered so far.
    bool leftArmOn() const noexcept { return instrument_.rig().leftArmOn(); }
    int leftArmPort() const { return static_cast<int>(settings_[SettingIds::leftArmOscPort]); }
    std::uint64_t leftArmSamples() const;
    /// Audio blocks processed so far (counts only: a host or sound card that stops calling
    /// processBlock stops it).
    std::uint64_t audioBlocks() const noexcept { return audioBlocks_.load(std::memory_order_relaxed); }
    /// The largest output / input magnitude since the previous call (the call resets it).
    float takeOutputPeak() noexcept { return outputPeak_.exchange(0.0f, std::memory_order_relaxed); }
    float takeInputPeak() noexcept { return inputPeak_.exchange(0.0f, std::memory_order_relaxed); }
    /// Plays a 440 Hz tone at -18 dBFS for `seconds` over the scene's sound (how to check that
    /// the output is heard). The audio thread adds it; without audio callbacks nothing plays.
    void playTestTone(double seconds = 1.0) noexcept;
    bool testTonePlaying() const noexcept { return testToneSamples_.load(std::memory_order_relaxed) > 0; }
    /// Whether the current scene listens to the audio input (score, audio-touch).
    bool sceneListens() const;

    // On stage (docs/STAGE.md, Stage.h). Message thread unless said; the host's state calls too.
    /// Reads a set list file and plays it (cue 0 first): "" or why not (file, line and key
    /// named); the set list used before stays then. The text is kept in the state.
    juce::String loadSetList(const juce::File& file);
    /// The same from a set list's text (`name`: the file, for messages).
    juce::String useSetList(const juce::String& text, const juce::String& name);
    /// Back to the single scene (the Scene box).
    void clearSetList();
    /// Panic, resume and cue steps: any thread (atomics); they act at the next block's start.
    void panic() noexcept { instrument_.stage().panic(); }
    void resume() noexcept { instrument_.stage().resume(); }
    void nextCue() noexcept { instrument_.stage().next(); }
    void previousCue() noexcept { instrument_.stage().previous(); }
    void goToCue(int index) noexcept { instrument_.stage().cue(index); }
    bool panicked() const noexcept { return instrument_.stage().panicked(); }
    /// Message thread: the newest set list's player (null: none), for tests and the UI.
    const live::CuePlayer* cuePlayer() const noexcept { return instrument_.stage().newest(); }
    /// The UDP port the OSC stage commands are heard on (the stageOsc settings), 0 when off.
    int stageOscPort() const { return instrument_.stageSession().oscPort(); }
    std::uint32_t panics() const noexcept { return instrument_.stage().panics(); }
    /// Stage commands the mapping's "stage" destinations fired (any thread; docs/STAGE.md).
    std::uint64_t mappedStageCommands() const noexcept { return instrument_.control().mappedStageCommands(); }
    /// What the performance view shows.
    live::StageSession::Info stageInfo() const { return instrument_.stageSession().info(); }

    /// The VST3's sidechain input buses, after its main input (input buses 1…4, stereo, disabled
    /// until the host routes them): each is a stem of audio-touch with the scene's preset of the
    /// same name in lower case (docs/PLUGIN.md "Stems"; INTERFACES.md "Plugin buses").
    static constexpr std::array<const char*, live::BlockControl::kMaxStems> kStemBuses {"Drums", "Bass", "Other", "Vocals"};
    /// The VST3's Tactors output bus (issue 33, docs/TACTORS.md; INTERFACES.md "Plugin buses"):
    /// output bus 1, 9 channels (or 12 with the back motors), disabled until the host enables
    /// it; channel k carries motor k as the tactor renderer draws it (SettingIds::tactor*).
    static constexpr const char* kTactorBus = "Tactors";

    /// The tactor rig (TactorRig.h; message thread): the Tactors bus and the app's tactor output.
    live::TactorRig& tactorRig() noexcept { return instrument_.tactorRig(); }
    /// The app's tactor output on or off (the tactorOutput setting follows): "" or why not.
    juce::String setTactorOutput(bool on);
    /// Buzzes the motor of tactor channel `channel` (0-based) at level 8 for 0.5 s through the
    /// whole rig (serial device, tactor output, Tactors bus), as `armadillo tactors test` does:
    /// "" or why not (a silent channel, the sensitivity test or the training holding the motors).
    juce::String testTactorChannel(int channel);
    int motorCount() const;

    /// Navigation (NavigationRig.h, issue 34; message thread): a walk along a route, positions
    /// from gpsd or OSC, the navigation scene in place of the chosen one until it stops.
    juce::String startNavigation(const juce::File& route, navigation::NavigationRig::Source source, const juce::String& where);
    void stopNavigation();
    const navigation::NavigationRig& navigation() const noexcept { return instrument_.navigation(); }

    /// Messages on the arm over MQTT (MessagesRig.h, issue 35; message thread): on/off (the
    /// mqttEnabled setting follows; "" or why not), the service while on, and what it did.
    juce::String setMessages(bool on);
    live::MessagesRig& messages() noexcept { return instrument_.messages(); }
    /// The last things the message presenter said ("message 3 from 'arm/inbox' on the arm: ..."),
    /// newest last (at most 50), for the Reader window's message list.
    juce::StringArray messageLog() const { return messageLog_; }

    /// The web page (issue 47; message thread): on or off with the webPort and webBind settings
    /// (the webEnabled setting follows; "" or why not). The page's scene parameters are this
    /// processor's: read from the host's parameters, set as an automation gesture on the message
    /// thread.
    juce::String setWebPage(bool on);
    /// Where to open it ("" while off) and the server's refusals and commands so far, in words.
    juce::String webAddress() const;
    juce::StringArray webLog() const { return webLog_; }

private:
    static BusesProperties busesFor(WrapperType wrapper);
    // Message thread
    void timerCallback() override;
    void valueTreePropertyChanged(juce::ValueTree&, const juce::Identifier&) override;
    EngineRequest currentRequest() const;
    void writeLiveOrientationToParameters();
    void writeMacrosToParameters();
    void applyNetworkSettings();
    void applyLeftArm();
    void applyVoiceSettings();
    live::CueBuild cueBuild(double sampleRate) const;   ///< how every cue's engine is built, from the settings
    /// After a state was restored: the saved set list is used, or cleared with the reason.
    juce::String applySavedSetList();
    void stageTick();   ///< timer: hand-over, and the status line's panic / cue reports
    void applyStageOsc();
    void setStatus(const juce::String& message);
    /// The engine hand-over's messages: "" takes down an earlier engine message (only that).
    void setEngineStatus(const juce::String& message);

    SceneParameterTable sceneTable_;             // before apvts_: the layout is built from it
    juce::AudioProcessorValueTreeState apvts_;
    std::atomic<float>* scene_ = nullptr;
    juce::ValueTree settings_;
    std::atomic<double> sampleRate_ {48000.0};
    std::atomic<std::uint64_t> statesLoaded_ {0};   ///< EngineRequest::session
    mutable std::mutex stemsMutex_;              // prepareToPlay vs the message thread's requests; never audio
    std::vector<std::string> stems_;             // under stemsMutex_: the enabled sidechain buses' stem names

    juce::StringArray messageLog_;
    juce::StringArray webLog_;                   // the web server's lines, newest last (at most 50)
    int webRefreshCountdown_ = 0;                // timer ticks until the page's snapshot is refreshed
    std::mutex webSceneMutex_;                   // webSceneRefusal_: the timer writes, the page's threads read
    std::string webSceneRefusal_;
    // The page's parameter changes reach the message thread through callAsync; this says whether
    // the processor is still there when one runs (both on the message thread).
    std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
    live::BlockWebView::Host webHost();
    HostBlock hostBlock_;                        // the host's buffers as the block clock takes them (audio thread)
    MidiPort midiPort_;                          // the standalone app's ALSA sequencer port (before the instrument: its clock drains it)

    // The live instrument (Live/Session/BlockInstrument.h): its parts built in one order and torn down in
    // the reverse; the destructor stops it first (its idle clock drains midiPort_ and reads the
    // engines below).
    live::BlockInstrument instrument_;
    EngineHandover engines_;                     // builds engines for instrument_.loop()
    TrainingAccess training_;
    int feedbackUntil_ = 0;                      // the sequence whose end gives the motors back to the scene
    bool feedbackRestart_ = false;               // then the braille trial starts again from its first row
    std::mutex mappingMutex_;                    // message thread vs a host's state calls; never audio
    std::unique_ptr<access::ReaderVoice> voice_ = std::make_unique<access::ReaderVoice>();
    bool voiceOn_ = false;
    juce::String voiceOpened_;                   // the readerVoice setting the backends were opened for

    // Live → parameters (message thread)
    bool gestureOpen_ = false;
    std::uint64_t lastWrittenSerial_ = 0;
    /// The mapping's macro destinations → `macro1…8` (message thread): a gesture opens with the
    /// first value and closes after kMacroGestureIdleMs without a new one.
    struct MacroWrite {
        bool open = false;
        float last = -1.0f;
        double changedMs = 0.0;
    };
    static constexpr double kMacroGestureIdleMs = 300.0;
    std::array<MacroWrite, ParamIds::kMacroCount> macroWrites_ {};
    bool autoConnectTried_ = false;              // one attempt per port/setting change

    // Status counters: the audio thread writes, the message thread reads (relaxed atomics only).
    std::atomic<std::uint64_t> audioBlocks_ {0};
    std::atomic<float> outputPeak_ {0.0f}, inputPeak_ {0.0f};
    std::atomic<int> testToneSamples_ {0};     // samples of test tone still to play
    double testTonePhase_ = 0.0;               // audio thread only

    std::atomic<int> currentProgram_ {0};
    std::atomic<int> requestedProgram_ {-1};     // any thread → message thread's timer; a loaded state clears it
    std::atomic<bool> hostRunning_ {false};       // the host has played a block: it takes parameter edits
    void applyRequestedProgram();

    mutable std::mutex statusMutex_;             // message thread and host state calls; never audio
    juce::String status_;
    bool statusFromEngine_ = false;              // status_ came from the engine hand-over

    JUCE_DECLARE_NON_COPYABLE_WITH_LEAK_DETECTOR(ArmadilloProcessor)
};

} // namespace armadillo::plugin
