#pragma once
// The live instrument on the block clock, assembled once (issue 45): every part the app and the
// plugin run below JUCE, built in one order and torn down in the reverse, so a front end holds
// this one object and its clock instead of its parts. Pure Data's [armadillo~] and the plugin
// drive it from their audio blocks (BlockControl::processBlock through control()); while no audio
// comes, its own idle clock (BlockRig) runs the step.
//
// What it owns, in the order it is built (each part states its thread rules in its own file):
//  - Instrument     the core every clock shares (Instrument.h): messages, navigation, the loop,
//                   the stage, the left arm, the one step and its publisher — first, so it goes
//                   last;
//  - ControlToken   who runs the step now: an audio block or the idle clock;
//  - LevelSchedule  the motor levels stamped for the device link;
//  - the stimuli    the sensitivity test, the feedback player and the adaptive training, which
//                   the control step may point at (unset by stop() before they go);
//  - BlockControl   the block clock: the step on the 200 Hz grid, the mapping's outputs;
//  - BlockRig       the sources (device, simulated arm, OSC, the left arm's sender) and the idle clock;
//  - TactorRig      the Tactors bus and the app's tactor output;
//  - MappingSession the mapping set on the message thread;
//  - StageSession   its OSC thread calls into the stage;
//  - the web page   last, so it goes first (BlockWebView and a web::WebServer, on while the front
//                   end asks: startWeb): its threads read everything above.
//
// Not here: what is the host's (JUCE's parameters, the engine request built from them, the
// editor, the self-voicing). The engines are built by the front end and handed to loop().
//
// Threads: construction, start(), stop() and the accessors' message-thread methods on the message
// thread; control() is driven by the audio thread (processBlock) as BlockControl.h says.
#include "Access/TactilePlayer.h"
#include "Live/Session/BlockControl.h"
#include "Live/Session/BlockRig.h"
#include "Live/Session/BlockWebView.h"
#include "Live/Session/Instrument.h"
#include "Live/Step/ControlLoop.h"
#include "Live/Step/ControlToken.h"
#include "Live/Outputs/MappingSession.h"
#include "Live/Outputs/MessagesRig.h"
#include "Live/Step/SceneParameters.h"
#include "Live/Stage/Stage.h"
#include "Live/Stage/StageSession.h"
#include "Live/Outputs/TactorRig.h"
#include "Link/LevelSchedule.h"
#include "Navigation/NavigationRig.h"
#include "Procedures/AdaptiveTraining.h"
#include "Procedures/TouchTest.h"
#include "Web/WebServer.h"
#include <atomic>
#include <functional>
#include <memory>
#include <string>

namespace armadillo::live {

class BlockInstrument {
public:
    /// What the host gives the instrument: the parameter cells the step reads (host automation and
    /// the source choice), the scenes' parameter table (the mapping's scene destinations; it must
    /// outlive the instrument) and the MIDI channel the classic mapping plays on.
    struct Host {
        BlockControl::Cells cells {};
        const SceneParameterTable* sceneTable = nullptr;
        std::function<int()> midiChannel;
    };
    explicit BlockInstrument(const Host& host);
    /// stop(), then every part in the reverse of its building.
    ~BlockInstrument();
    BlockInstrument(const BlockInstrument&) = delete;
    BlockInstrument& operator=(const BlockInstrument&) = delete;

    /// Starts the idle clock (after the owner has installed an engine and its settings).
    void start();
    /// Motors off and every thread the instrument runs stopped, in order: the web page, the stage's OSC port,
    /// the tactor output, the idle clock and the device link (its last packet all-off), the
    /// position source, the messages. Idempotent; the destructor calls it.
    void stop();

    /// The block clock (audio thread) and its outputs (any thread), BlockControl.h.
    BlockControl& control() noexcept { return control_; }
    const BlockControl& control() const noexcept { return control_; }
    /// Where the step's audio sits in the host's buffer (set with the audio stopped, in prepare;
    /// read by the audio thread at each block).
    void setListen(const BlockControl::Listen& listen) noexcept { listen_ = listen; }
    const BlockControl::Listen& listen() const noexcept { return listen_; }

    /// Message thread, never with the audio running a block that waits on it: hands the step a
    /// new engine between two steps (the token taken, held by an idle step for < 1 ms).
    void install(std::unique_ptr<EngineSlot> slot);
    /// Prepares the block clock for `sampleRate` between two steps (the token taken).
    void prepare(double sampleRate);

    /// The web page (issue 47; message thread): binds now (`config.port` 0 = a free port, loopback
    /// unless `config.bind` names an address, then with a token) and serves the instrument through
    /// BlockWebView with the host's scene parameters. Returns "" or why not (the port taken, an
    /// address that is not this machine's); a running page is stopped first.
    std::string startWeb(const web::WebConfig& config, BlockWebView::Host host);
    void stopWeb();
    /// The page's server while on (its address, what it refused), else null.
    web::WebServer* webServer() noexcept { return web_.get(); }
    /// Message thread, a few times a second while on: the status only it may read.
    void refreshWeb(const std::string& scene);

    /// The core every clock shares (Instrument.h).
    Instrument& instrument() noexcept { return instrument_; }
    const Instrument& instrument() const noexcept { return instrument_; }
    ControlLoop& loop() noexcept { return instrument_.loop(); }
    ControlToken& token() noexcept { return token_; }
    BlockRig& rig() noexcept { return rig_; }
    const BlockRig& rig() const noexcept { return rig_; }
    Stage& stage() noexcept { return instrument_.stage(); }
    const Stage& stage() const noexcept { return instrument_.stage(); }
    StageSession& stageSession() noexcept { return stageSession_; }
    const StageSession& stageSession() const noexcept { return stageSession_; }
    TactorRig& tactorRig() noexcept { return tactorRig_; }
    navigation::NavigationRig& navigation() noexcept { return instrument_.navigation(); }
    const navigation::NavigationRig& navigation() const noexcept { return instrument_.navigation(); }
    MappingSession& mapping() noexcept { return mapping_; }
    MessagesRig& messages() noexcept { return instrument_.messages(); }
    const MessagesRig& messages() const noexcept { return instrument_.messages(); }

    /// Messages on the arm (message thread): started with these settings ("" or why not) or
    /// stopped; the mapping's `mqtt` destinations publish through the running service.
    std::string startMessages(const MessagesSettings& settings);
    void stopMessages();

    /// The stimuli that may take the motors from the scene (message thread): the sensitivity
    /// test, and the player of braille feedback, tactor tests and the adaptive training.
    procedures::TouchTest& touchTest() noexcept { return touchTest_; }
    access::TactilePlayer& feedbackPlayer() noexcept { return feedbackPlayer_; }
    const access::TactilePlayer& feedbackPlayer() const noexcept { return feedbackPlayer_; }
    procedures::AdaptiveTraining& adaptive() noexcept { return adaptive_; }
    /// True while neither the sensitivity test nor the adaptive training runs.
    bool proceduresIdle() const noexcept;

    /// Samples the given source has delivered so far: the simulator's steps, the device link's
    /// good packets, OSC orientation/IMU messages (0 for host automation). Any thread.
    std::uint64_t sourceSamples(SourceKind kind) const;
    /// The left arm's OSC sender's orientation/IMU messages so far.
    std::uint64_t leftArmSamples() const;

private:
    static tactile::TactileConfig feedbackConfig();

    Instrument instrument_;
    ControlToken token_;
    link::LevelSchedule motors_;
    procedures::TouchTest touchTest_;
    access::TactilePlayer feedbackPlayer_;   // all 12 motors: the tactor tests reach the back motors
    procedures::AdaptiveTraining adaptive_;  // plays through feedbackPlayer_
    BlockControl control_;
    BlockControl::Listen listen_ {};
    BlockRig rig_;
    TactorRig tactorRig_;
    MappingSession mapping_;
    StageSession stageSession_;
    std::unique_ptr<BlockWebView> webView_;
    std::unique_ptr<web::WebServer> web_;   // last: its threads read everything above
    bool stopped_ = false;
};

} // namespace armadillo::live
