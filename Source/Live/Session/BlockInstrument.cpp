#include "Live/Session/BlockInstrument.h"

namespace armadillo::live {

tactile::TactileConfig BlockInstrument::feedbackConfig()
{
    tactile::TactileConfig c;
    c.motorCount = core::kGridMotors + core::kBackMotors;
    return c;
}

BlockInstrument::BlockInstrument(const Host& host)
    : feedbackPlayer_(feedbackConfig(), 0.0),
      adaptive_(feedbackPlayer_),
      control_(instrument_, token_, host.cells, motors_),
      rig_(instrument_, control_, motors_),
      tactorRig_(control_, token_),
      mapping_(control_, *host.sceneTable, host.midiChannel,
               [this](const std::vector<osc::HostPort>& targets) { return rig_.configureMappingOsc(targets); }),
      stageSession_(instrument_.stage())
{
    // Wired before anything runs the step: the scenes' parameters for the mapping.
    control_.setSceneTable(host.sceneTable);
}

BlockInstrument::~BlockInstrument()
{
    stop();
}

void BlockInstrument::start()
{
    if (stopped_) return;
    rig_.start();
}

void BlockInstrument::stop()
{
    if (std::exchange(stopped_, true)) return;
    stopWeb();                               // first: its threads read everything below
    control_.setStimulus(nullptr);
    (void) stageSession_.setOsc(false, 0);   // its OSC thread calls into the stage
    tactorRig_.closeOutput();                // its audio thread reads the step's levels
    rig_.stop();                             // the idle clock, then the device link (all-off)
    instrument_.navigation().stop();         // the position source
    stopMessages();                          // after the clock: the mapping published through it
}

void BlockInstrument::install(std::unique_ptr<EngineSlot> slot)
{
    token_.take();   // the idle clock holds it for < 1 ms; a block that finds it taken is silent
    instrument_.loop().replace(std::move(slot));
    token_.release();
}

void BlockInstrument::prepare(double sampleRate)
{
    token_.take();
    control_.prepare(sampleRate);
    token_.release();
}

std::string BlockInstrument::startWeb(const web::WebConfig& config, BlockWebView::Host host)
{
    stopWeb();
    if (stopped_) return "the instrument has stopped";
    try {
        webView_ = std::make_unique<BlockWebView>(*this, std::move(host));
        web_ = std::make_unique<web::WebServer>(config, *webView_);   // binds now: IoError when the port is taken
        web_->start();
        return {};
    } catch (const std::exception& e) {
        web_.reset();
        webView_.reset();
        return std::string("web page: ") + e.what();
    }
}

void BlockInstrument::stopWeb()
{
    if (web_) web_->stop();
    web_.reset();
    webView_.reset();
}

void BlockInstrument::refreshWeb(const std::string& scene)
{
    if (webView_) webView_->refresh(scene);
}

std::string BlockInstrument::startMessages(const MessagesSettings& settings)
{
    control_.setMqtt(nullptr);
    auto why = instrument_.messages().start(settings);
    control_.setMqtt(instrument_.messages().service());
    return why;
}

void BlockInstrument::stopMessages()
{
    control_.setMqtt(nullptr);
    instrument_.messages().stop();
}

bool BlockInstrument::proceduresIdle() const noexcept
{
    return touchTest_.state() == procedures::TouchTest::State::Idle && adaptive_.state() == procedures::AdaptiveTraining::State::Idle;
}

std::uint64_t BlockInstrument::sourceSamples(SourceKind kind) const
{
    switch (kind) {
    case SourceKind::Simulator: return rig_.simulatorSteps();
    case SourceKind::Device: return rig_.devicePackets();
    case SourceKind::Osc: {
        const auto in = rig_.oscInputStats();
        return in.imu + in.orientation;
    }
    case SourceKind::HostAutomation: return 0;
    }
    return 0;
}

std::uint64_t BlockInstrument::leftArmSamples() const
{
    const auto in = rig_.leftOscInputStats();
    return in.imu + in.orientation;
}

} // namespace armadillo::live
