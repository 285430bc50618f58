#include "Pd/SessionInstrument.h"
#include "Core/Pose.h"
#include "Core/StageCommand.h"
#include "Link/Mount.h"
#include "Live/Session/LiveSession.h"
#include "Osc/OscDialects.h"

namespace armadillo::pd {

namespace {
const char* sourceName(Settings::Source s)
{
    switch (s) {
    case Settings::Source::Simulate: return "simulate";
    case Settings::Source::Port: return "port";
    case Settings::Source::Osc: return "osc";
    case Settings::Source::None: break;
    }
    return "none";
}
} // namespace

SessionInstrument::SessionInstrument() = default;
SessionInstrument::~SessionInstrument() = default;   // the session stops its threads, motors off

void SessionInstrument::apply(const Settings& settings)
{
    session_.reset();   // first: the old source lets go of its port or socket
    source_ = "none";
    lastUpdate_ = 0;
    if (settings.source == Settings::Source::None || commands_ == nullptr) return;
    live::LiveConfig c;
    c.engine = commands_->engineConfig(48000.0);   // no audio leaves [armadillo]: its rate is nominal
    c.calibration = commands_->calibration();
    switch (settings.source) {
    case Settings::Source::Simulate:
        c.source = live::LiveConfig::Source::Simulator;
        c.motionFile = settings.motionFile;
        break;
    case Settings::Source::Port:
        c.source = live::LiveConfig::Source::Port;
        c.port = settings.port;
        c.baud = settings.baud;
        break;
    case Settings::Source::Osc:
        c.source = live::LiveConfig::Source::Osc;
        c.oscInPort = settings.oscPort;
        osc::parseOscFormat(settings.format, c.osc.format);
        if (!settings.mount.empty()) {
            c.osc.mount = link::mountFromArgument(settings.mount);
            c.osc.mountGiven = true;
        }
        break;
    case Settings::Source::None: break;
    }
    auto session = std::make_unique<live::LiveSession>(c);   // InputError / IoError: nothing runs
    if (panicked_) session->stage().apply({core::StageCommand::Kind::Panic});
    session->start();
    session_ = std::move(session);
    source_ = sourceName(settings.source);
}

void SessionInstrument::stopSource()
{
    session_.reset();
    source_ = "none";
}

void SessionInstrument::setParameter(const std::string& id, const std::string& value)
{
    if (session_) session_->engine().setSceneParameter(id, value);   // the scene stores it in atomics
}

void SessionInstrument::panic()
{
    panicked_ = true;
    if (session_) session_->stage().apply({core::StageCommand::Kind::Panic});
}

void SessionInstrument::resume()
{
    panicked_ = false;
    if (session_) session_->stage().apply({core::StageCommand::Kind::Resume});
}

bool SessionInstrument::poll(Frame& frame)
{
    if (!session_) return false;
    const live::ArmFrame f = session_->latestFrame();   // one step whole: pose, orientation and levels together
    if (f.serial == lastUpdate_) return false;
    lastUpdate_ = f.serial;
    frame.valid = f.valid;
    for (int i = 0; i < 3; ++i) frame.pose[i] = f.pose[i];
    for (int i = 0; i < 4; ++i) frame.q[i] = f.q[i];
    frame.motors = f.motors;
    frame.motorCount = f.motorCount;
    return true;
}

bool SessionInstrument::nextGesture(std::string& name)
{
    engine::GestureEvent g;
    if (!session_ || !session_->popGesture(g)) return false;
    name = g.name;
    return true;
}

Status SessionInstrument::status() const
{
    Status s;
    s.source = source_;
    if (!session_) return s;
    // An OSC port is open from the start: the sender counts as connected once its data came.
    const bool heard = source_ != "osc" || session_->controlUpdates() > 0;
    s.connection = session_->connected() && heard ? "connected" : "waiting";
    const live::SessionSummary sum = session_->summary();
    s.dropped = session_->droppedImu() + sum.badPackets + session_->gesturesDropped();
    return s;
}

std::uint64_t SessionInstrument::controlSteps() const { return session_ ? session_->controlUpdates() : 0; }

} // namespace armadillo::pd
