#pragma once
// The live pipeline of `armadillo play`: a source (serial device, simulated forearm or OSC),
// calibration (counts → SI, once), the live rig's control step (live::ControlLoop, the same one
// the plugin runs on its audio blocks: the source's mailbox → ArmTracker (fusion + features) →
// Engine (scene → shaping → safety stage)) and the motor packet back to the device, plus the
// optional outputs: audio file, tactile CSV, session log and OSC out.
//
// Threads: the source's thread is the control thread (DeviceLink for devices, OscReceiver for
// OSC): calibration, tracking, engine.control() and the motor packet all run there, so a motor
// packet leaves microseconds after its sensor packet arrived. One audio thread calls
// engine.renderAudio(): the audio-file thread (audioOut, paced by the wall clock) or the sound
// card's (soundCard, paced by the card); a host that owns audio (the plugin) sets neither and
// calls engine().renderAudio() from its own audio callback. Log/tactile rows leave the
// control thread through lock-free queues.
#include "Core/GapDetector.h"
#include "Core/Pose.h"
#include "Core/SpscQueue.h"
#include "Link/Calibration.h"
#include "Link/DeviceLink.h"
#include "Osc/OscInput.h"
#include "Core/Wav.h"
#include "Engine/Engine.h"
#include "Live/Step/ControlLoop.h"
#include "Live/Step/LeftArm.h"
#include "Mapping/MappingSpec.h"
#include "Navigation/NavigationRig.h"
#include "Mqtt/MessageService.h"
#include "Live/Stage/SetList.h"
#include "Live/Stage/Stage.h"
#include "Live/Step/StepRunner.h"
#include "Live/Session/Instrument.h"
#include "Live/Outputs/StepPublisher.h"
#include "Live/Outputs/TactorOutput.h"
#include "Web/WebServer.h"
#include <array>
#include <deque>
#include <mutex>
#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>

namespace armadillo::audio {
class SoundCard;
class SequencerOut;
}
namespace armadillo::mapping {
struct StageEvent;
struct MqttMessage;
}
namespace armadillo::fusion {
class ArmTracker;
}
namespace armadillo::osc {
class OscReceiver;
class OscSender;
}

namespace armadillo::live {

class ArmSource;
class MappingRig;
class StreamingCsvWriter;
class StreamingWavWriter;

struct LiveConfig {
    enum class Source { Port, Simulator, Osc };
    Source source = Source::Simulator;
    std::string port;                 ///< Source::Port: device path
    int baud = 57600;
    std::string motionFile;           ///< Source::Simulator: pose/quaternion CSV; empty = wandering arm
    double simulatorBaud = 57600.0;   ///< Source::Simulator: wire pacing (0 = as fast as possible)
    int oscInPort = 0;                ///< Source::Osc: UDP (and TCP) port (0 = any free port)
    std::string oscSerialPort;        ///< Source::Osc: read SLIP-framed OSC from this serial port instead (NGIMU over USB)
    int oscSerialBaud = 115200;
    osc::OscInputOptions osc {};   ///< Source::Osc: dialect (auto-detected by default) and mount
    link::Calibration calibration = link::defaultCalibration();
    engine::EngineConfig engine {};
    double bpm = 120.0;               ///< the audio-clock transport's tempo
    /// The panic gesture (docs/STAGE.md): the right forearm hanging straight down (elevation
    /// ≤ −75°) for 2 s panics what plays — the scene, every cue of a set list, both arms' duo.
    /// Off by default (`play --panic-gesture` turns it on). Run by the control step (ControlLoop).
    bool panicGesture = false;
    std::string audioOut;             ///< WAV path; empty = no audio file
    bool audioFloat = false;
    std::string soundCard;            ///< ALSA device to play on when audioOut is empty ("" = none)
    bool soundCardOptional = false;   ///< true: a card that cannot be opened is a warning, not an error
    /// A recording (WAV) the scene listens to while it plays out with the scene's audio
    /// (`play --audio-in`): from the session's start, block by block on the audio thread,
    /// into Engine::processInput and mixed into the output. Its sample rate must be the
    /// engine's; the scene must listen (InputError otherwise). Empty = none.
    std::string audioIn;
    /// Instead of audioIn: stems (`play --stem NAME=FILE`, several `--audio-in`), one file each,
    /// named in engine.sceneConfig.stems in the same order (audio-touch feels each on its own
    /// motors, docs/INSTRUMENTS.md). Each is mixed to mono; the scene hears one channel per stem
    /// and the listener their sum. At most kMaxAudioInChannels.
    std::vector<std::string> audioStems;
    static constexpr int kMaxAudioInChannels = 16;
    bool audioInLoop = false;         ///< the recording starts again at its end (`play --loop`); else silence follows it
    std::string tactileOut;           ///< t,m1..m9 CSV of every motor packet
    std::string logOut;               ///< session log CSV, one row per sensor packet
    std::string oscOut;               ///< HOST:PORT; empty = none. With a mapping: its OSC destinations' default
                                      ///< target, and the fixed /armadillo/* messages are not sent
    /// `--map`: the mapping matrix run at every control update (Source/Mapping); null = none, and
    /// then nothing but the fixed OSC stream leaves.
    std::shared_ptr<const mapping::MappingDocument> mapping;
    std::string mappingName;          ///< for messages ("classic", a path)
    std::string midiOut;              ///< with a mapping: an ALSA sequencer output port of this name (IoError when absent)
    double forwardDeg = 0.0;          ///< with a mapping: the forward direction to start from (azimuth, °)
    link::DeviceLinkOptions link {};
    /// A set list (docs/STAGE.md; `play --setlist`): its cues replace `engine.scene`, which then
    /// only tracks the arm (monitor); sample rate, seed, arm side and motor count come from
    /// `engine`. Empty = none.
    std::string setList;
    /// Two arms (docs/STAGE.md; `play --motion-left` / `--port-left` / `--osc-in-left`): the left
    /// arm's own source, link, calibration (or mount) and fusion; the scene sees both
    /// (EngineConfig::twoArms is set) and the left arm's motor packets go back to its own device
    /// (an OSC sender has no motors). None = one arm.
    enum class LeftSource { None, Port, Simulator, Osc };
    LeftSource leftSource = LeftSource::None;
    std::string leftPort;             ///< LeftSource::Port
    int leftBaud = 57600;
    std::string leftMotionFile;       ///< LeftSource::Simulator: pose/quaternion CSV; empty = wandering arm
    int leftOscInPort = 0;            ///< LeftSource::Osc: UDP (and TCP) port (0 = any free port)
    osc::OscInputOptions leftOsc {};       ///< LeftSource::Osc: its own dialect detection and mount (`--mount-left`)
    link::Calibration leftCalibration = link::defaultCalibration();
    /// Two arms: t,qw,qx,qy,qz,left_qw,left_qx,left_qy,left_qz per control update. Empty = none.
    std::string armsLog;
    /// The motor grid live as audio (`play --tactors`, docs/TACTORS.md): every control step's
    /// levels (the right arm's, as sent to its device) onto an ALSA PCM or JACK ports, beside
    /// the device. tactors.device empty = none.
    live::TactorOutputConfig tactors {};
    /// A walk (`armadillo navigate`, docs/NAVIGATION.md): the route, the guidance, and where the
    /// positions come from (gpsd, an OSC port of their own, or the arm's own OSC port: a phone
    /// that sends motion and gps). The session opens the position source
    /// (navigation::NavigationRig, the one place it is built) and runs the navigation scene in
    /// place of `engine.scene`, which then only names it. Not with a set list or two arms. No
    /// route = no walk.
    struct Walk {
        std::shared_ptr<const navigation::Route> route;
        navigation::NavigationOptions options {};
        navigation::NavigationRig::Source positions = navigation::NavigationRig::Source::Gpsd;
        std::string where;   ///< gpsd's HOST[:PORT], or the OSC port
    };
    Walk walk {};
    /// Messages on the arm and the mapping's MQTT destinations (docs/MQTT.md; `play --mqtt`,
    /// `read`): the broker, the topics shown on the arm and how. The session owns the service
    /// (mqtt::MessageService: the client, its inbox, the presenter), starts it with the sources and
    /// stops it after them; the mapping's `mqtt` destinations publish through it and OSC
    /// /armadillo/message texts join its inbox. Off: no broker.
    struct Messages {
        bool on = false;
        mqtt::MqttConfig config {};
        mqtt::PresenterOptions options {};
    };
    Messages messages {};
    /// The instrument as a web page (`play`/`read`/`navigate --web PORT [--web-bind ADDR]`,
    /// docs/INTERFACES.md "The web page"): the session owns the server, binds it at construction
    /// (IoError when the port is taken), starts it with the sources and stops it before them.
    web::WebConfig web {};
};

struct SessionSummary {
    std::uint64_t packets = 0, badPackets = 0, resyncs = 0, reconnects = 0;
    std::uint64_t gaps = 0;    ///< dropouts in the source's stream (Core/GapDetector.h)
    double longestGap = 0.0;   ///< s
    double rateHz = 0.0;       ///< sustained: (packets − 1) / (last − first packet time)
    double seconds = 0.0;      ///< session length
    std::string oscJson;       ///< Source::Osc: the input's format, device and refusal counters (JSON members)
    bool v2 = false;           ///< the link ran the v2 framing (LinkConfig::negotiateV2 and a board that offers it)
    std::uint64_t seqGaps = 0, crcFailures = 0;   ///< v2 only
};
/// {"packets":…,"bad_packets":…,"resyncs":…,"reconnects":…,"rate_hz":…} (INTERFACES.md) plus
/// "gaps" and "longest_gap_s" (docs/DEVICE.md); when the link ran v2, also "v2":true, "seq_gaps"
/// and "crc_failures".
std::string summaryJson(const SessionSummary& s);

/// The session log's header: t, raw counts, calibrated SI values (IMU names), qw qx qy qz, then the
/// link's running counters bad_packets, resyncs, reconnects, gaps, longest_gap_s (docs/DEVICE.md).
const std::vector<std::string>& sessionLogHeader();

class LiveSession {
public:
    /// Validates and prepares everything that can fail early (files, ports, OSC, scene):
    /// InputError for bad files, IoError for a port or socket that cannot be opened.
    explicit LiveSession(const LiveConfig& config);
    ~LiveSession();
    LiveSession(const LiveSession&) = delete;
    LiveSession& operator=(const LiveSession&) = delete;

    void start();
    /// Motors off (a last all-zero motor packet when a device is in step), threads stopped.
    void stop();
    /// After stop(): writes the audio, tactile and log files whole (IoError on failure).
    void finish();
    /// The recordings' files that existed before the session, in words: "'A.wav' existed: kept
    /// as 'A.wav.1'" (Live/Outputs/SessionWriters.h), one line each.
    std::vector<std::string> keptAside() const;
    /// After stop(), instead of finish(): a session that played nothing leaves no file (each
    /// recording removed, a file kept aside put back under its name).
    void discardRecordings() noexcept;

    SessionSummary summary() const;
    const LiveConfig& config() const noexcept { return config_; }
    /// The guided mount calibration's samples of an OSC sender (`left`: the left arm's):
    /// enableSensorTap starts keeping its sensor-frame samples (false: that arm has no OSC
    /// input); popSensorFrame takes the oldest (accel m/s², gyro rad/s or NaN), false when none;
    /// senderName is the sender's device name, for the mount file. Any one thread.
    bool enableSensorTap(bool left);
    bool popSensorFrame(bool left, osc::SensorFrameSample& sample);
    std::string senderName(bool left) const;
    /// The engine that runs: the set list's current cue's, or the one scene's.
    engine::Engine& engine() noexcept { return sounding(); }
    /// The set list's player (null without --setlist): its cues and the one playing, any thread.
    live::CuePlayer* cuePlayer() noexcept { return cues_; }
    /// The stage (Live/Stage/Stage.h): every stage command (keys, the control port, the mapping) goes
    /// through Stage::apply and acts at the next control step; its panic count. Any thread.
    live::Stage& stage() noexcept { return stage_; }
    /// Any thread (the web page): `name` (engine::sceneNames()) plays instead of the scene from the
    /// next control step, built with the session's settings and the scene's own defaults. "" or
    /// why not: not with a set list (its cues), a walk, a mapping, messages or --audio-in (each is
    /// bound to the first scene), nor after kMaxSceneChanges changes (every engine given up stays
    /// alive until the session ends), nor while holdScene() holds it.
    std::string chooseScene(const std::string& name);
    static constexpr std::size_t kMaxSceneChanges = 64;
    /// The scenes chooseScene() takes now, or none with `why` not.
    std::vector<std::string> sceneChoices(std::string& why);
    /// A front end that holds the scene itself (the command line's training log holds the braille
    /// scene): no scene change from now on, for `why`.
    void holdScene(const std::string& why);
    /// A guided procedure's player has the motors instead of the scene from the next step on
    /// (live::StepRunner::setStimulus; never during a panic); nullptr gives them back. Any thread.
    void setStimulus(access::TactilePlayer* player) noexcept { instrument_.runner().setStimulus(player); }
    /// Whether the session drives motors: a device or the simulated forearm, or a tactor output.
    bool hasMotors() const noexcept { return link_ != nullptr || tactors_ != nullptr; }
    /// Two arms: the left arm's link (null with one arm) and its latest pose (any thread).
    link::DeviceLink* leftLink() noexcept { return leftLink_; }
    /// Two arms with an OSC sender as the left arm: its receiver (format, device, counters); null otherwise.
    osc::OscReceiver* leftOscReceiver() noexcept { return leftOscIn_; }
    core::Pose latestLeftPose() const noexcept { return leftPose_.load(); }
    /// IMU samples the control step dropped (more than ControlLoop::kMaxImuPerStep waiting).
    std::uint64_t droppedImu() const noexcept { return loop_.droppedImu(); }
    /// The newest step's frame: pose, orientation, gyro and the levels that went to the motors,
    /// read whole (serial 0: no step yet). Any thread, lock-free (Live/Outputs/StepPublisher.h).
    ArmFrame latestFrame() const noexcept { return published_.latest(); }
    /// The scene's gestures (strikes, rolls, postures: GestureEvent::name a string literal), in
    /// order, for one consumer thread (a front end that presents them: Pure Data's [armadillo]).
    /// At most 128 wait; more are dropped and counted.
    bool popGesture(engine::GestureEvent& event) noexcept { return published_.popGesture(event); }
    std::uint64_t gesturesDropped() const noexcept { return published_.gesturesDropped(); }
    bool connected() const noexcept;
    std::string lastError() const;
    std::uint64_t controlUpdates() const noexcept { return published_.steps(); }
    /// The device link of a port or simulator source (null for OSC): statistics, the sent-packet log.
    link::DeviceLink* deviceLink() noexcept { return link_; }
    /// Every raw packet of a device source, for one consumer thread (calibration, UI); null for OSC.
    core::SpscQueue<link::RawPacket, 1024>* rawPackets() noexcept { return link_ ? &link_->packets() : nullptr; }
    /// Sensor-packet arrival → motor packet written (device sources; empty otherwise).
    link::LatencySummary latency() const;
    /// The mapping's counters (null without --map).
    const live::MappingRig* mapping() const noexcept { return mapping_.get(); }
    live::MappingRig* mapping() noexcept { return mapping_.get(); }
    /// Panics the mapping fired (a `"stage": "panic"` destination; docs/STAGE.md), any thread.
    std::uint32_t mappingPanics() const noexcept { return mappingPanics_.load(std::memory_order_relaxed); }
    /// Source::Osc: the UDP port listened on (useful with oscInPort 0); 0 otherwise.
    int oscInPort() const noexcept;
    /// Source::Osc: the receiver (format, device, counters, the mount calibration's tap); null otherwise.
    osc::OscReceiver* oscReceiver() noexcept { return oscIn_; }
    /// Why an optional sound card is not in use ("" when it is, or none was asked for).
    const std::string& soundCardWarning() const noexcept { return soundCardWarning_; }
    /// The outputs as opened, in words for the person who runs the session: "sound on 'default'
    /// (48000 Hz, S16_LE, 21.3 ms buffer)", "tactors on JACK …". After start().
    std::vector<std::string> outputLines() const;
    /// An output that stopped since the last call (the sound card, the tactor output), each said
    /// once. One thread (the front end's).
    std::vector<std::string> outputFailures();
    /// After stop(): what the outputs have to say at the end (a sound card that ran dry).
    std::vector<std::string> outputClosingLines() const;
    /// The outputs' counters as JSON members for the summary line: ,"tactor_frames":…,
    /// "tactor_dropped":…,"tactor_limited":… with a tactor output (docs/TACTORS.md); "" otherwise.
    std::string outputsJson() const;
    /// Messages (LiveConfig::messages): whether topics are shown on the arm; for the front end's
    /// thread, the waiting messages handed to the braille scene when it is free (what happened,
    /// in words: "message 3 from 'arm/inbox' on the arm: …"); the connection and the inbox; a
    /// text from elsewhere (OSC /armadillo/message) queued; the summary's ,"mqtt":{…}.
    bool showsMessages() const noexcept { return messages_ && !messages_->config().topics.empty(); }
    std::vector<std::string> presentMessages();
    mqtt::MqttStatus messagesStatus() const;
    mqtt::InboxStats messagesInbox() const;
    void offerMessage(const std::string& text, int priority);
    std::string messagesJson() const;
    /// The walk (LiveConfig::walk): its route, status, log (drained by one front-end thread) and
    /// position source; null without one.
    navigation::NavigationRig* navigation() noexcept { return navigation_; }
    /// The tactor output (null without LiveConfig::tactors.device): for tests and benchmarks.
    live::TactorOutput* tactors() noexcept { return tactors_.get(); }
    /// The recording (LiveConfig::audioIn) has been played to its end (never with audioInLoop or
    /// without a recording): by the audio thread's position, or by the wall clock when no audio
    /// thread runs (a sound card that could not be opened).
    bool recordingEnded() const noexcept;
    /// Seconds of the recording (0 without one).
    double recordingSeconds() const noexcept;
    /// The session's time: the latest sensor packet's time, s (the tactile CSV's t; −1 before one). Any thread.
    double sessionTime() const noexcept { return latestT_.load(std::memory_order_relaxed); }
    /// The messages presentMessages() put on the arm, newest first (at most 20). Any thread.
    std::vector<std::string> recentMessages() const;
    /// The web page's server (LiveConfig::web; null without it): its address, what it refused.
    web::WebServer* webServer() noexcept { return web_.get(); }

private:
    friend struct LiveSessionAudioProbe;   // Tests/Live/RealtimeLoopTests.cpp: renderBlock under the real-time guard
    // The constructor's steps, in order.
    void buildEngine();
    void openMessagesAndMapping();
    void openRightSource();
    void openLeftArm();
    void openRecordings();
    void openAudio();
    core::MotorLevels control(double t, const link::SensorCounts* counts, const core::ImuSample* imu, const Eigen::Quaterniond* q);
    /// Packets, errors, reconnects and gaps of the source so far (any thread; no session length).
    SessionSummary linkCounters() const;
    void audioLoop();

    LiveConfig config_;
    // The core every clock shares (Instrument.h): messages, navigation, the loop, the stage, the
    // left arm, the one step and its publisher. First, so it goes last: everything below reads it.
    live::Instrument instrument_;
    navigation::NavigationRig* navigation_ = nullptr;         // instrument_'s while a walk runs (null: none)
    mqtt::MessageService* messages_ = nullptr;                 // instrument_'s service (null: no messages)
    braille::BrailleSceneControls* messageScene_ = nullptr;    // the scene the messages are shown on (null: none)
    static bool publishMapped(void* self, const mapping::MqttMessage& message);
    live::ControlLoop& loop_ = instrument_.loop();   // the control step: mailbox → fusion → Engine::control (owns the engine)
    live::SourceKind sourceKind_ = live::SourceKind::Device;
    // The loop's engine: the control thread stores the new one when a scene change took over
    // (chooseScene); the audio, main and web threads read it. Engines given up stay alive in
    // retiredEngines_ until the session ends, so no thread ever reads a deleted one.
    std::atomic<engine::Engine*> engine_ {nullptr};
    std::string sceneChangeRefusal() const;   // (sceneMutex_ held)
    engine::Engine& loopEngine() const noexcept { return *engine_.load(std::memory_order_acquire); }
    std::mutex sceneMutex_;                                        // chooseScene, holdScene (builder side of loop_)
    std::vector<std::unique_ptr<live::EngineSlot>> retiredEngines_;
    std::string sceneHeld_;                                         // why the scene may not change ("" = it may)
    live::Stage& stage_ = instrument_.stage();   // the set list's player, panic and resume (one switch: Stage::apply)
    live::CuePlayer* cues_ = nullptr;   // stage_'s player, installed at construction, never replaced (null: none)
    std::atomic<std::uint32_t> mappingPanics_ {0};
    /// The mapping's stage commands (control thread, real-time): as `play`'s keys and OSC do.
    static void applyStage(void* self, const mapping::StageEvent& event) noexcept;
    // Two arms: the left arm's source and link; its calibrated samples reach the control thread
    // through a mailbox, where its own tracker fuses them; the two-arm engine plays both.
    live::LeftArm* leftArm_ = nullptr;            // instrument_'s, on with two arms (null: one arm)
    live::ArmSource* left_ = nullptr;             // in instrument_'s Left slot, opened through the registry (Live/Sources/SourceRegistry.h)
    link::DeviceLink* leftLink_ = nullptr;        // left_'s link (a forearm) or
    osc::OscReceiver* leftOscIn_ = nullptr;       // its OSC receiver (a sender)
    core::SeqLock<core::MotorLevels> leftLevels_;
    core::SeqLock<core::Pose> leftPose_;
    std::unique_ptr<StreamingCsvWriter> armsLog_;
    engine::Engine& sounding() noexcept { return cues_ ? cues_->engine(cues_->current()) : loopEngine(); }
    live::ArmSource* right_ = nullptr;            // the right arm, in instrument_'s Device or Osc slot
    link::DeviceLink* link_ = nullptr;            // right_'s link (a forearm) or
    osc::OscReceiver* oscIn_ = nullptr;           // its OSC receiver (a sender)
    std::unique_ptr<osc::OscSender> oscOut_;
    std::unique_ptr<live::MappingRig> mapping_;      // control thread once started
    std::unique_ptr<audio::SequencerOut> midiOut_;   // written by the control thread only
    std::unique_ptr<StreamingCsvWriter> log_, tactile_;
    std::unique_ptr<StreamingWavWriter> wav_;
    /// Audio thread: the scene's block with the recording (audioIn) heard and played out.
    void renderBlock(float* left, float* right, int n) noexcept;
    void renderScene(float* left, float* right, int n) noexcept;   ///< renderBlock without the hand-over to the tactors
    core::AudioBuffer recording_;            ///< audioIn (or the stems, one channel each), read at construction
    bool recordingIsStems_ = false;          ///< recording_ holds stems: all channels heard, their sum played out
    std::vector<float> recordingSilence_;    ///< zeros for after the recording's end
    std::uint64_t recordingAt_ = 0;          ///< audio thread: next frame of the recording (counts on past its end)
    std::atomic<std::uint64_t> recordingPlayed_ {0};   ///< recordingAt_, for other threads
    std::unique_ptr<audio::SoundCard> soundCard_;
    std::unique_ptr<live::TactorOutput> tactors_;
    std::string soundCardWarning_;
    bool shownCardFailure_ = false, shownTactorFailure_ = false;   // outputFailures(): said once
    std::thread audioThread_;
    std::atomic<bool> running_ {false};
    std::atomic<bool> motorsOff_ {false};
    std::atomic<std::uint64_t> zeroPacketsSent_ {0};
    std::atomic<double> zeroPacketT_ {-1.0};   ///< source time of the first all-off packet answered at stop()
    StepPublisher& published_ = instrument_.published();   // the frame and gestures of each step
    double lastT_ = -1.0;
    core::GapDetector sourceGaps_;                         // control thread: gaps of a source without a link (OSC)
    std::atomic<std::uint64_t> oscGaps_ {0};
    std::atomic<double> oscLongestGap_ {0.0};
    std::atomic<double> firstT_ {-1.0}, latestT_ {-1.0};   // source packet times (for the OSC rate)
    std::chrono::steady_clock::time_point started_ {}, stopped_ {};
    std::string audioError_;
    mutable std::mutex recentMutex_;                    // recent_
    std::deque<std::string> recent_;                    // messages on the arm, newest first
    // Last, so it goes first: its threads read everything above.
    std::unique_ptr<web::InstrumentView> webView_;      // the session as the page sees it (Live/SessionWebView.h)
    std::unique_ptr<web::WebServer> web_;
};

} // namespace armadillo::live
