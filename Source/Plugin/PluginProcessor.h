#pragma once
// The plugin/standalone shell over armadillo::Engine (Surge habit: the engine is a library, this is
// glue). Threads:
//  - audio thread: processBlock runs the control loop at a steady ~200 Hz derived from the block
//    timeline (ArmTracker → Engine::control) and renders the scene's audio between updates;
//  - control clock (a 200 Hz high-resolution timer): advances the simulator, sends OSC, and runs
//    the control loop itself only while no audio callbacks arrive (standalone without a sound
//    card, a host that stopped processing), so the tactile display never freezes;
//  - message thread: builds engines for scene changes, writes live orientation into the
//    parameters with change gestures, owns settings, ports and sockets.
// The audio thread and the clock never run the control loop at the same time: whoever runs it
// holds a try-only atomic token (nobody waits for it). The control step itself (engine hand-over,
// source choice, bounded fusion, Engine::control) is the core's live::ControlLoop, the same one
// Tests/Live/RealtimeLoopTests.cpp holds to the real-time rules; this class adds MIDI, the
// published frame, OSC and the idle clock around it.
#include "Engine/Engine.h"
#include "Live/ControlLoop.h"
#include "Plugin/DeviceConnection.h"
#include "Plugin/LiveInput.h"
#include "Plugin/OscLink.h"
#include "Plugin/Parameters.h"
#include "Plugin/PortRegistry.h"
#include "Plugin/WanderingMotion.h"
#include <juce_audio_processors/juce_audio_processors.h>
#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

namespace armadillo::braille {
class BrailleSceneControls;
}

namespace armadillo::plugin {

/// Names of the persistent settings (the "SETTINGS" child of the saved state).
namespace SettingIds {
inline const juce::Identifier root {"SETTINGS"};
inline const juce::Identifier oscOutEnabled {"oscOutEnabled"};
inline const juce::Identifier oscOutHost {"oscOutHost"};
inline const juce::Identifier oscOutPort {"oscOutPort"};
inline const juce::Identifier oscInEnabled {"oscInEnabled"};
inline const juce::Identifier oscInPort {"oscInPort"};
inline const juce::Identifier oscInFormat {"oscInFormat"};   ///< "" = detect; else docs/SENSORS.md names
inline const juce::Identifier oscInMount {"oscInMount"};     ///< "" = the format's usual mount; a preset or mount file
inline const juce::Identifier serialPort {"serialPort"};
inline const juce::Identifier baudRate {"baudRate"};
inline const juce::Identifier calibrationFile {"calibrationFile"};
inline const juce::Identifier armSide {"armSide"};           ///< "right" | "left"
inline const juce::Identifier backMotors {"backMotors"};     ///< bool: 12 motors instead of 9
inline const juce::Identifier brailleText {"brailleText"};
inline const juce::Identifier score {"score"};               ///< "rite-of-spring" | "polytope"
inline const juce::Identifier midiChannel {"midiChannel"};   ///< 1..16
inline const juce::Identifier editorWidth {"editorWidth"};
inline const juce::Identifier editorHeight {"editorHeight"};
inline const juce::Identifier simWandering {"simWandering"};
inline const juce::Identifier connectOnStart {"connectOnStart"}; ///< bool: open the saved port when source = device
} // namespace SettingIds

/// MIDI out of gestures and pose (documented in docs/PLUGIN.md).
namespace MidiMap {
inline constexpr int kNoteRoll = 60, kNotePunch = 62, kNoteStrike = 64, kNoteOther = 67;
inline constexpr int kCcElevation = 16, kCcAzimuth = 17, kCcRoll = 18;
inline constexpr double kNoteLengthS = 0.05;
int noteFor(const char* gesture) noexcept;
} // namespace MidiMap

class ArmadilloProcessor : public juce::AudioProcessor,
                           private juce::Timer,
                           private juce::ValueTree::Listener {
public:
    static constexpr int kStateVersion = 1;
    static constexpr double kControlRateHz = 200.0;   ///< thesis: the 2005 system ran at ~200 updates/s

    ArmadilloProcessor();
    ~ArmadilloProcessor() override;

    // juce::AudioProcessor
    void prepareToPlay(double sampleRate, int samplesPerBlock) override;
    void releaseResources() override {}
    bool isBusesLayoutSupported(const BusesLayout& layouts) const override;
    void processBlock(juce::AudioBuffer<float>&, juce::MidiBuffer&) override;
    using juce::AudioProcessor::processBlock;
    juce::AudioProcessorEditor* createEditor() override;
    bool hasEditor() const override { return true; }
    const juce::String getName() const override { return "ARMadillo"; }
    bool acceptsMidi() const override { return false; }
    bool producesMidi() const override { return true; }
    bool isMidiEffect() const override { return false; }
    double getTailLengthSeconds() const override { return kTailSeconds; }
    int getNumPrograms() override { return 1; }
    int getCurrentProgram() override { return 0; }
    void setCurrentProgram(int) override {}
    const juce::String getProgramName(int) override { return "Default"; }
    void changeProgramName(int, const juce::String&) override {}
    void getStateInformation(juce::MemoryBlock& destData) override;
    void setStateInformation(const void* data, int sizeInBytes) override;

    // For the editor (message thread)
    juce::AudioProcessorValueTreeState& parameters() noexcept { return apvts_; }
    juce::ValueTree& settings() noexcept { return settings_; }
    const SceneParameterTable& sceneTable() const noexcept { return sceneTable_; }
    ArmFrame latestFrame() const noexcept { return frame_.load(); }
    SourceKind source() const noexcept;
    int sceneIndex() const noexcept;
    juce::String statusMessage() const;
    void clearStatusMessage();
    Pose simulatorPose() const;
    bool simulatorWandering() const;
    void steerSimulator(const Pose& pose);
    void setSimulatorWandering(bool on);
    /// Arm view / keyboard under host automation: user edits of the orientation parameters.
    void setOrientationFromUser(const Pose& pose);
    juce::String linkStatus() const;
    void connectDevice(bool connect);
    bool deviceConnected() const noexcept { return device_ != nullptr && device_->isOpen(); }
    /// Guided calibration on the connected device (message thread; the processor's timer feeds
    /// it the link's raw packets). begin refuses, saying why, when no device is connected.
    const CalibrationSession& calibration() const noexcept { return device_->calibrationSession(); }
    bool beginCalibration(juce::String& why);
    /// Next / Skip: when that ends the procedure, its result is applied to the link at once.
    bool calibrationNext(juce::String& why);
    void calibrationSkip();
    void cancelCalibration();
    /// Writes the applied guided result as calibration JSON and remembers the file in the
    /// settings (the next connection loads it). False with the reason when it cannot be written.
    bool saveCalibration(const juce::File& file, juce::String& message);
    /// Braille training for the Training panel (message thread). `use` runs with the training
    /// controls of the newest engine, under the lock that engine replacement takes, so the engine
    /// cannot be deleted meanwhile; it is not called (false) when that engine does not run the
    /// braille scene. Never keep the reference: `generation` changes with every new engine (scene,
    /// text, sample rate or arm change), and a new engine's training starts from its first trial.
    bool withBrailleTraining(const std::function<void(braille::BrailleSceneControls&, std::uint64_t generation)>& use);
    /// A copy of the training log of engine `generation`. The control side only queues fixed-size
    /// records; the text is built here, on the message thread, without the control token, so
    /// the audio thread never waits for it. False with the reason when that engine is gone.
    bool copyBrailleTrainingLog(std::uint64_t generation, std::string& csv, juce::String& why);
    std::uint64_t oscMessagesSent() const noexcept { return oscOut_.messagesSent(); }
    /// The OSC input (message thread): its status line and the mount calibration's sample feed.
    OscInput& oscInput() noexcept { return oscIn_; }
    const char* lastGesture() const noexcept { return lastGesture_.load(std::memory_order_relaxed); }
    std::uint64_t gestureCount() const noexcept { return gestureCount_.load(std::memory_order_relaxed); }
    double controlRateMeasured() const noexcept { return measuredRate_.load(std::memory_order_relaxed); }

    static constexpr double kTailSeconds = 5.0;   ///< longest ring-out: cymbal crash (~4 s) + FM tail

private:
    struct EngineRequest {
        int scene = 0;
        double sampleRate = 48000.0;
        bool left = false;
        bool backMotors = false;
        std::string text, score;
        bool operator==(const EngineRequest&) const = default;
    };

    // Message thread
    void timerCallback() override;
    void valueTreePropertyChanged(juce::ValueTree&, const juce::Identifier&) override;
    EngineRequest currentRequest() const;
    std::unique_ptr<live::EngineSlot> buildEngine(const EngineRequest& request);
    void reportEngineFailure();
    void applyPendingEngine();
    void writeLiveOrientationToParameters();
    void applyNetworkSettings();
    void setStatus(const juce::String& message);
    void applyGuidedCalibration();
    void resetToDefaults();
    void installSettings(const juce::ValueTree& loaded);
    static juce::ValueTree defaultSettings();

    // Control loop (whoever holds the token)
    bool tryTakeToken() noexcept;
    void releaseToken() noexcept;
    void controlTick(double dt, const Transport& transport, juce::MidiBuffer* midi, int sampleOffset) noexcept;
    void emitNote(juce::MidiBuffer& midi, int note, float value, int sampleOffset) noexcept;
    void flushNoteOffs(juce::MidiBuffer& midi, int blockSamples) noexcept;

    // Control clock thread
    class ControlClock;
    void clockTick(double dt);

    SceneParameterTable sceneTable_;             // before apvts_: the layout is built from it
    juce::AudioProcessorValueTreeState apvts_;
    std::atomic<float>* elevation_ = nullptr;
    std::atomic<float>* azimuth_ = nullptr;
    std::atomic<float>* roll_ = nullptr;
    std::atomic<float>* source_ = nullptr;
    std::atomic<float>* scene_ = nullptr;

    juce::ValueTree settings_;

    // Engines: built on the message thread, handed over lock-free through loop_ (builder side
    // under builderMutex_, control side by the token holder).
    live::ControlLoop loop_;
    EngineRequest builtRequest_ {};                 // under builderMutex_: what the newest engine was built for
    std::uint64_t engineGeneration_ = 0;            // under builderMutex_: counts engines built
    std::uint64_t reportedFailure_ = 0;             // message thread: generation whose failure was shown
    std::atomic<double> sampleRate_ {48000.0};
    std::atomic<bool> token_ {false};

    // Control state (token holder)
    double controlClock_ = 0.0;                     // s since start, advanced by dt per update
    int samplesToTick_ = 0;
    int lastCc_[3] {-1, -1, -1};
    struct NoteOff { int note = -1; int samplesLeft = 0; };
    std::array<NoteOff, 16> noteOffs_ {};
    // MIDI out storage, sized on the message thread and given to the host's buffer on the first
    // block (processBlock), so emitting gestures never grows the host's buffer on the audio thread.
    static constexpr std::size_t kMidiStorageBytes = 64 * 1024;
    juce::MidiBuffer midiStorage_;
    bool midiStorageGiven_ = false;
    std::uint64_t frameSerial_ = 0;

    // Published
    SeqLock<ArmFrame> frame_;
    SpscQueue<GestureEvent, 128> gesturesOut_;       // control loop → clock thread (OSC)
    std::atomic<const char*> lastGesture_ {""};
    std::atomic<std::uint64_t> gestureCount_ {0};
    std::atomic<double> lastAudioMs_ {-1.0e9};
    std::atomic<double> measuredRate_ {0.0};
    std::atomic<std::uint64_t> ticks_ {0};

    // Sources (their mailboxes are loop_.input(kind))
    mutable std::mutex simMutex_;                    // simulator steering: message ↔ clock thread only
    WanderingMotion simulator_;
    OscOutput oscOut_;
    OscInput oscIn_ {loop_.input(SourceKind::Osc)};
    std::unique_ptr<DeviceConnection> device_;
    juce::String deviceMessage_;

    // Live → parameters (message thread)
    bool gestureOpen_ = false;
    bool autoConnectTried_ = false;                  // message thread: one attempt per port/setting change

    mutable std::mutex statusMutex_;                 // message thread and host state calls; never audio
    juce::String status_;
    juce::String networkStatus_;
    std::atomic<int> midiChannel_ {1};

    std::mutex builderMutex_;                        // engine building: message thread vs prepareToPlay
    std::uint64_t lastWrittenSerial_ = 0;
    std::uint64_t lastSentSerial_ = 0;             // clock thread
    double rateWindowStartMs_ = 0.0;               // clock thread
    std::uint64_t rateWindowTicks_ = 0;            // clock thread
    std::unique_ptr<ControlClock> clock_;

    JUCE_DECLARE_NON_COPYABLE_WITH_LEAK_DETECTOR(ArmadilloProcessor)
};

} // namespace armadillo::plugin
