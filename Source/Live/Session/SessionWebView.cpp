#include "Live/Session/SessionWebView.h"
#include "Live/Session/LiveSession.h"
#include "Live/Step/SceneParameters.h"
#include "Live/Session/WebWalk.h"
#include <charconv>
#include <cmath>

namespace armadillo::live {

namespace {

std::string describeSource(const LiveConfig& c)
{
    switch (c.source) {
    case LiveConfig::Source::Port: return "device on " + c.port;
    case LiveConfig::Source::Simulator:
        return c.motionFile.empty() ? std::string("simulated forearm (wandering)") : "simulated forearm (motion " + c.motionFile + ")";
    case LiveConfig::Source::Osc:
        return c.oscSerialPort.empty() ? "OSC sender on UDP port " + std::to_string(c.oscInPort) : "OSC over SLIP on " + c.oscSerialPort;
    }
    return "?";
}

/// "id=value" settings as numbers: a number, or a choice's name as its index.
void readAssignments(const std::vector<std::string>& assignments, const std::vector<core::ParamSpec>& specs,
                     std::map<std::string, double>& values)
{
    for (const std::string& a : assignments) {
        const std::size_t eq = a.find('=');
        if (eq == std::string::npos) continue;
        const std::string id = a.substr(0, eq), text = a.substr(eq + 1);
        for (const core::ParamSpec& s : specs) {
            if (s.id != id) continue;
            double v = 0.0;
            const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
            if (ec == std::errc() && end == text.data() + text.size()) values[id] = v;
            for (std::size_t k = 0; k < s.choices.size(); ++k)
                if (s.choices[k] == text) values[id] = static_cast<double>(k);
        }
    }
}

} // namespace

SessionWebView::SessionWebView(LiveSession& session) : session_(session), source_(describeSource(session.config()))
{
    const std::vector<core::ParamSpec> specs = session.engine().scene().parameters();
    for (const core::ParamSpec& s : specs) values_[s.id] = s.defaultValue;
    readAssignments(session.config().engine.parameters, specs, values_);
    if (live::CuePlayer* cues = session.cuePlayer())
        for (int i = 0; i < cues->cueCount(); ++i) {
            const std::vector<core::ParamSpec> cueSpecs = cues->engine(i).scene().parameters();
            for (const core::ParamSpec& s : cueSpecs) values_.emplace(s.id, s.defaultValue);
            readAssignments(cues->cue(i).parameters, cueSpecs, values_);
        }
    // The guided calibration runs here, on the raw packets the session hands out (a device or the
    // simulated forearm); the result is a file for --calibration.
    calibrationHooks_.procedure = [this](std::string& why) -> const procedures::DeviceCalibration* {
        if (session_.rawPackets() != nullptr) return &calibration_;
        why = "the device calibration needs a device (--port) or the simulated forearm; this source sends OSC";
        return nullptr;
    };
    calibrationHooks_.begin = [this](std::string&) {
        link::RawPacket stale;
        while (session_.rawPackets()->pop(stale)) {}   // only what comes from now on
        calibration_.begin(session_.config().calibration);
        return true;
    };
    calibrationHooks_.next = [this](std::string& why) { return calibration_.next(why); };
    calibrationHooks_.skip = [this] { calibration_.skip(); };
    calibrationHooks_.cancel = [this] { calibration_.cancel(); };
    calibrationHooks_.finishedHint = "Download it below and use it with --calibration.";
    // The sensitivity test's player takes the session's motors from the next step.
    touchHooks_.unavailable = [this] {
        return session_.hasMotors() ? std::string()
                                    : std::string("the sensitivity test needs motors: a device (--port), the simulated forearm or a tactor output (--tactors)");
    };
    touchHooks_.begin = [this](std::uint64_t seed) {
        touch_.begin(seed);
        session_.setStimulus(&touch_.player());
    };
    touchHooks_.end = [this](bool) {
        session_.setStimulus(nullptr);
        touch_.cancel();
    };
    touchHooks_.finishedHint = "Download it below and use it with --touch-profile.";
}

SessionWebView::~SessionWebView() { session_.setStimulus(nullptr); }

web::InstrumentStatus SessionWebView::status()
{
    web::InstrumentStatus s;
    const SessionSummary sum = session_.summary();
    s.t = std::max(0.0, session_.sessionTime());
    s.source = source_;
    s.connected = session_.connected() && session_.controlUpdates() > 0;
    s.rateHz = sum.rateHz;
    s.packets = sum.packets;
    s.badPackets = sum.badPackets;
    s.gaps = sum.gaps;
    s.dropped = session_.droppedImu();
    s.sender = session_.senderName(false);
    const ArmFrame frame = session_.latestFrame();
    s.hasPose = frame.serial > 0;
    s.elevationDeg = frame.pose[0];
    s.azimuthDeg = frame.pose[1];
    s.rollDeg = frame.pose[2];
    s.scene = std::string(session_.engine().scene().name());
    s.panicked = session_.stage().panicked();
    s.panics = session_.stage().panics();
    if (live::CuePlayer* cues = session_.cuePlayer()) {
        s.cue = cues->current();
        for (int i = 0; i < cues->cueCount(); ++i) s.cues.push_back(cues->cue(i).name.empty() ? cues->cue(i).scene : cues->cue(i).name);
    }
    s.messages = session_.recentMessages();
    {
        std::lock_guard<std::mutex> lock(calibrationMutex_);
        pumpCalibration();
        s.calibration = calibrationPage_.status(calibrationHooks_);
    }
    {
        std::lock_guard<std::mutex> lock(touchMutex_);
        s.touch = touchPage_.status(touch_, touchHooks_);
    }
    if (const navigation::NavigationRig* nav = session_.navigation()) s.walk = webWalk(*nav);
    return s;
}

std::vector<web::ParameterInfo> SessionWebView::parameters()
{
    const std::vector<core::ParamSpec> specs = session_.engine().scene().parameters();
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<web::ParameterInfo> out;
    for (const core::ParamSpec& s : specs) {
        const auto v = values_.find(s.id);
        out.push_back({s.id, s.name, s.unit, s.min, s.max, v != values_.end() ? v->second : static_cast<double>(s.defaultValue), s.choices});
    }
    return out;
}

void SessionWebView::stage(const core::StageCommand& command) { session_.stage().apply(command); }

bool SessionWebView::setParameter(const std::string& id, double value, double& set)
{
    core::Scene& scene = session_.engine().scene();
    const std::vector<core::ParamSpec> specs = scene.parameters();
    for (std::size_t i = 0; i < specs.size(); ++i) {
        if (specs[i].id != id) continue;
        mapping::SceneParamChange change;
        change.value = static_cast<float>(std::clamp(value, -1e9, 1e9));
        change.normalised = false;
        const float v = live::sceneParamValue(specs[i], change);   // clamped to the range, a choice rounded
        scene.setParameter(static_cast<int>(i), v);                // the scene's atomics (Core/Scene.h)
        std::lock_guard<std::mutex> lock(mutex_);
        values_[id] = v;
        set = v;
        return true;
    }
    return false;
}

void SessionWebView::pumpCalibration()
{
    core::SpscQueue<link::RawPacket, 1024>* packets = session_.rawPackets();
    if (packets == nullptr || !calibration_.running()) return;
    link::RawPacket p;
    while (packets->pop(p)) calibration_.offer(p.t, p.counts);
    calibration_.drain();
}

void SessionWebView::calibration(web::ProcedureCommand command)
{
    std::lock_guard<std::mutex> lock(calibrationMutex_);
    pumpCalibration();
    calibrationPage_.command(command, calibrationHooks_);
}

std::vector<std::string> SessionWebView::sceneChoices(std::string& why) { return session_.sceneChoices(why); }

std::string SessionWebView::chooseScene(const std::string& name)
{
    {
        std::lock_guard<std::mutex> lock(touchMutex_);
        if (touch_.state() != procedures::TouchTest::State::Idle) return "the sensitivity test runs: cancel it first";
    }
    return session_.chooseScene(name);
}

void SessionWebView::touchTest(web::TouchCommand command)
{
    std::lock_guard<std::mutex> lock(touchMutex_);
    touchPage_.command(command, touch_, touchHooks_, static_cast<std::uint64_t>(std::max(1.0, 1000.0 * session_.sessionTime())));
}

std::string SessionWebView::touchProfileFile()
{
    std::lock_guard<std::mutex> lock(touchMutex_);
    return touchPage_.file();
}

std::string SessionWebView::calibrationFile()
{
    std::lock_guard<std::mutex> lock(calibrationMutex_);
    return calibrationPage_.file();
}

} // namespace armadillo::live
