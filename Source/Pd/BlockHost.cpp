#include "Pd/BlockHost.h"
#include "Core/Errors.h"
#include "Core/StageCommand.h"
#include "Link/Motion.h"
#include "Live/Session/BlockInstrument.h"
#include "Live/Sources/SourceRegistry.h"

namespace armadillo::pd {

BlockHost::BlockHost(double sampleRate) : sampleRate_(sampleRate > 0.0 ? sampleRate : 48000.0)
{
    setSourceCell(live::SourceKind::Device);   // no device connected: nothing is fused until a source is chosen
    live::BlockInstrument::Host host;
    host.cells = {&elevation_, &azimuth_, &roll_, &sourceCell_};
    host.sceneTable = &table_;
    host.midiChannel = [] { return 1; };
    instrument_ = std::make_unique<live::BlockInstrument>(host);
    instrument_->prepare(sampleRate_);
    left_.assign(64, 0.0f);
    right_.assign(64, 0.0f);
    instrument_->start();   // the idle clock: the step runs (and the messages flow) while Pd's DSP is off
}

BlockHost::~BlockHost() = default;

void BlockHost::prepare(double sampleRate, int maxBlock)
{
    if (maxBlock > static_cast<int>(left_.size())) {
        left_.assign(static_cast<std::size_t>(maxBlock), 0.0f);
        right_.assign(static_cast<std::size_t>(maxBlock), 0.0f);
    }
    const bool newRate = sampleRate > 0.0 && sampleRate != sampleRate_;
    if (newRate) sampleRate_ = sampleRate;
    instrument_->prepare(sampleRate_);   // between two idle steps
    if (newRate && commands_ != nullptr) installEngine();
}

void BlockHost::render(float* out, int n) noexcept
{
    if (n <= 0) return;
    if (n > static_cast<int>(left_.size())) {
        for (int i = 0; i < n; ++i) out[i] = 0.0f;
        return;
    }
    float* channels[2] = {left_.data(), right_.data()};
    for (int i = 0; i < n; ++i) left_[static_cast<std::size_t>(i)] = right_[static_cast<std::size_t>(i)] = 0.0f;
    const live::AudioBlock block {channels, 2, n};
    instrument_->control().processBlock(block, midi_, core::Transport {}, false);
    for (int i = 0; i < n; ++i) out[i] = 0.5f * (left_[static_cast<std::size_t>(i)] + right_[static_cast<std::size_t>(i)]);
}

void BlockHost::installEngine()
{
    auto slot = std::make_unique<live::EngineSlot>();
    const engine::EngineConfig config = commands_->engineConfig(sampleRate_);
    slot->engine = std::make_unique<engine::Engine>(config);   // InputError: the old engine plays on
    slot->sceneName = config.scene;
    slot->generation = ++generation_;
    instrument_->install(std::move(slot));   // Pd's thread runs no block now
}

void BlockHost::chooseSource(const Settings& s)
{
    live::BlockRig& rig = instrument_->rig();
    std::shared_ptr<const link::MotionSource> motion;
    if (s.source == Settings::Source::Simulate && !s.motionFile.empty())
        motion = std::make_shared<link::FileMotion>(s.motionFile);   // InputError before anything changes
    if (s.source != Settings::Source::Port && rig.deviceConnected()) rig.disconnectDevice();
    if (s.source != Settings::Source::Osc) (void) rig.configureOsc(false, "", 0, false, 0, "", "");
    switch (s.source) {
    case Settings::Source::Simulate:
        rig.followSimulatorMotion(std::move(motion));   // null: the wandering arm
        setSourceCell(live::SourceKind::Simulator);
        break;
    case Settings::Source::Port:
        if (rig.deviceConnected()) rig.disconnectDevice();
        {
            // The rig's link waits for a missing port (the app shows "waiting"); a patch is told
            // now: the port is opened once here (IoError naming it), closed, then given to the rig.
            live::ForearmPortRequest probe;
            probe.port = s.port;
            probe.baud = s.baud;
            (void) live::openForearmPort(probe);
        }
        rig.connectDevice(s.port, s.baud, s.calibrationFile);
        if (!rig.deviceConnected()) {
            setSourceCell(live::SourceKind::Device);
            throw core::IoError("port " + s.port + ": " + rig.linkStatus());
        }
        setSourceCell(live::SourceKind::Device);
        break;
    case Settings::Source::Osc: {
        const std::string why = rig.configureOsc(false, "", 0, true, s.oscPort, s.format == "auto" ? "" : s.format, s.mount);
        if (!why.empty()) throw core::IoError("osc " + std::to_string(s.oscPort) + ": " + why);
        setSourceCell(live::SourceKind::Osc);
        break;
    }
    case Settings::Source::None: setSourceCell(live::SourceKind::Device); break;
    }
}

void BlockHost::apply(const Settings& settings)
{
    if (commands_ == nullptr) return;
    installEngine();   // the scene, its parameters, the arm, the touch profile (a bad one throws first)
    source_ = "none";
    chooseSource(settings);
    switch (settings.source) {
    case Settings::Source::Simulate: source_ = "simulate"; break;
    case Settings::Source::Port: source_ = "port"; break;
    case Settings::Source::Osc: source_ = "osc"; break;
    case Settings::Source::None: break;
    }
    setStopped(settings.source == Settings::Source::None);
}

void BlockHost::setStopped(bool stopped)
{
    // Without a source the scene would go on playing its last intents (the patch's targets, a
    // theremin's note): the stage holds it silent, motors off, until a source comes — unless
    // the patch asked for panic itself, which only `resume` ends.
    stopped_ = stopped;
    if (stopped_) instrument_->stage().apply({core::StageCommand::Kind::Panic});
    else if (!userPanic_) instrument_->stage().apply({core::StageCommand::Kind::Resume});
}

void BlockHost::stopSource()
{
    live::BlockRig& rig = instrument_->rig();
    if (rig.deviceConnected()) rig.disconnectDevice();   // its last packet is all-off
    (void) rig.configureOsc(false, "", 0, false, 0, "", "");
    setSourceCell(live::SourceKind::Device);              // nothing arrives: no arm is fused
    source_ = "none";
    setStopped(true);
}

void BlockHost::setParameter(const std::string& id, const std::string& value)
{
    // The engine installed last (Pd's thread installs every engine); the scene stores it in atomics.
    if (live::EngineSlot* slot = instrument_->loop().newest(); slot != nullptr && slot->engine) slot->engine->setSceneParameter(id, value);
}

void BlockHost::panic()
{
    userPanic_ = true;
    instrument_->stage().apply({core::StageCommand::Kind::Panic});
}

void BlockHost::resume()
{
    userPanic_ = false;
    if (!stopped_) instrument_->stage().apply({core::StageCommand::Kind::Resume});
}

bool BlockHost::poll(Frame& frame)
{
    const live::ArmFrame f = instrument_->control().latestFrame();
    if (f.serial == lastSerial_) return false;
    lastSerial_ = f.serial;
    frame.valid = f.valid && source_ != "none";
    for (int i = 0; i < 3; ++i) frame.pose[i] = f.pose[i];
    for (int i = 0; i < 4; ++i) frame.q[i] = f.q[i];
    frame.motors = f.motors;
    frame.motorCount = f.motorCount;
    return true;
}

bool BlockHost::nextGesture(std::string& name)
{
    // The instrument's gesture queue feeds its OSC sender; a front end reads the newest one.
    const std::uint64_t count = instrument_->control().gestureCount();
    if (count == lastGestureCount_) return false;
    lastGestureCount_ = count;
    name = instrument_->control().lastGesture();
    return !name.empty();
}

Status BlockHost::status() const
{
    Status s;
    s.source = source_;
    const live::BlockRig& rig = instrument_->rig();
    if (source_ == "simulate") s.connection = "connected";
    if (source_ == "port") s.connection = rig.deviceConnected() && rig.devicePackets() > 0 ? "connected" : "waiting";
    if (source_ == "osc") {
        const auto in = rig.oscInputStats();
        s.connection = in.imu + in.orientation > 0 ? "connected" : "waiting";
        s.dropped += in.bad;
    }
    s.dropped += instrument_->loop().droppedImu();
    return s;
}

std::uint64_t BlockHost::controlSteps() const { return instrument_->control().ticks(); }

} // namespace armadillo::pd
