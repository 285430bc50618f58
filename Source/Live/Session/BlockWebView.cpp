#include "Live/Session/BlockWebView.h"
#include "Live/Session/BlockInstrument.h"
#include "Mqtt/MessageService.h"
#include "Live/Session/WebWalk.h"
#include <algorithm>
#include <cmath>

namespace armadillo::live {

BlockWebView::BlockWebView(BlockInstrument& instrument, Host host) : instrument_(instrument), host_(std::move(host))
{
    snapshot_.source = "starting";
    // The sensitivity test through the host (its motors, and the reader's profile when kept).
    touchHooks_.unavailable = [this] {
        return host_.beginTouchTest && host_.endTouchTest ? std::string() : std::string("this front end offers no sensitivity test");
    };
    touchHooks_.begin = [this](std::uint64_t seed) { host_.beginTouchTest(seed); };
    touchHooks_.end = [this](bool keep) { host_.endTouchTest(keep); };
    touchHooks_.finishedHint = "The profile is the reader's now.";
    // The guided calibration is the block rig's, the one the Calibration window runs; a finished
    // one is the device's at once.
    BlockRig& rig = instrument_.rig();
    calibrationHooks_.procedure = [&rig](std::string& why) -> const procedures::DeviceCalibration* {
        if (rig.deviceConnected()) return &rig.calibration();
        why = "the device calibration needs a device or the simulated forearm connected (Device…)";
        return nullptr;
    };
    calibrationHooks_.begin = [&rig](std::string& why) { return rig.beginCalibration(why); };
    calibrationHooks_.next = [&rig](std::string& why) { return rig.calibrationNext(why); };
    calibrationHooks_.skip = [&rig] { rig.calibrationSkip(); };
    calibrationHooks_.cancel = [&rig] { rig.cancelCalibration(); };
    calibrationHooks_.finishedHint = "It is the device's calibration now (not saved): download it below, or save it in the Calibration window.";
}

void BlockWebView::refresh(const std::string& scene)
{
    web::InstrumentStatus s;
    BlockRig& rig = instrument_.rig();
    const SourceKind kind = instrument_.control().source();
    switch (kind) {
    case SourceKind::Simulator:
        s.source = rig.simulatorWandering() ? "simulated forearm (wandering)" : "simulated forearm (steered)";
        s.connected = true;
        break;
    case SourceKind::Device:
        s.source = rig.deviceConnected() ? "device: " + rig.device().status() : std::string("device (not connected)");
        s.connected = rig.deviceConnected() && rig.devicePackets() > 0;
        break;
    case SourceKind::Osc: {
        const osc::OscInputStats in = rig.oscInputStats();
        s.source = rig.oscInput().statusText();
        s.sender = rig.oscInput().deviceName();
        s.connected = in.imu + in.orientation > 0;
        s.badPackets = in.bad;
        break;
    }
    case SourceKind::HostAutomation:
        s.source = "host automation";
        s.connected = true;
        break;
    }
    s.rateHz = rig.controlRateMeasured();
    s.packets = instrument_.sourceSamples(kind);
    s.dropped = instrument_.loop().droppedImu();
    s.scene = scene;
    const StageSession::Info cues = instrument_.stageSession().info();
    if (cues.setList) {
        s.cue = cues.cue;
        for (int i = 0; i < cues.cueCount; ++i)
            s.cues.push_back(i == cues.cue ? cues.cueName + " (" + cues.cueScene + ")" : i == cues.next ? cues.nextName + " (" + cues.nextScene + ")"
                                                                                                          : "Cue " + std::to_string(i + 1));
    }
    if (const mqtt::MessageService* service = instrument_.messages().service()) {
        const std::vector<mqtt::InboxMessage> recent = service->recent(20);
        for (auto m = recent.rbegin(); m != recent.rend(); ++m) s.messages.push_back(m->text + " (from " + m->source + ")");
    }
    s.calibration = runCalibrationCommands();
    runTouchCommands();
    s.touch = touch_;
    std::lock_guard<std::mutex> lock(mutex_);
    snapshot_ = std::move(s);
}

web::InstrumentStatus BlockWebView::status()
{
    web::InstrumentStatus s;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        s = snapshot_;
    }
    const ArmFrame frame = instrument_.control().latestFrame();
    s.t = std::max(0.0, frame.t);
    s.hasPose = frame.valid;
    s.elevationDeg = frame.pose[0];
    s.azimuthDeg = frame.pose[1];
    s.rollDeg = frame.pose[2];
    s.panicked = instrument_.stage().panicked();
    s.panics = instrument_.stage().panics();
    s.walk = webWalk(instrument_.navigation());
    return s;
}

std::vector<web::ParameterInfo> BlockWebView::parameters() { return host_.parameters ? host_.parameters() : std::vector<web::ParameterInfo> {}; }

void BlockWebView::stage(const core::StageCommand& command) { instrument_.stage().apply(command); }

bool BlockWebView::setParameter(const std::string& id, double value, double& set)
{
    return host_.setParameter && std::isfinite(value) && host_.setParameter(id, value, set);
}

void BlockWebView::calibration(web::ProcedureCommand command)
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (pendingCalibration_.size() < 16) pendingCalibration_.push_back(command);   // a flood keeps the first 16
}

std::string BlockWebView::calibrationFile()
{
    std::lock_guard<std::mutex> lock(mutex_);
    return calibrationFile_;
}

web::ProcedureStatus BlockWebView::runCalibrationCommands()
{
    std::vector<web::ProcedureCommand> commands;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        commands.swap(pendingCalibration_);
    }
    for (const web::ProcedureCommand command : commands) calibrationPage_.command(command, calibrationHooks_);
    {
        std::lock_guard<std::mutex> lock(mutex_);
        calibrationFile_ = calibrationPage_.file();
    }
    return calibrationPage_.status(calibrationHooks_);
}

std::vector<std::string> BlockWebView::sceneChoices(std::string& why)
{
    if (!host_.sceneChoices) {
        why = "this front end chooses its scene itself";
        return {};
    }
    return host_.sceneChoices(why);
}

std::string BlockWebView::chooseScene(const std::string& name)
{
    return host_.chooseScene ? host_.chooseScene(name) : std::string("this front end chooses its scene itself");
}

void BlockWebView::touchTest(web::TouchCommand command)
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (pendingTouch_.size() < 16) pendingTouch_.push_back(command);   // a flood keeps the first 16
}

std::string BlockWebView::touchProfileFile()
{
    std::lock_guard<std::mutex> lock(mutex_);
    return touchProfile_;
}

void BlockWebView::runTouchCommands()
{
    std::vector<web::TouchCommand> commands;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        commands.swap(pendingTouch_);
    }
    procedures::TouchTest& test = instrument_.touchTest();
    for (const web::TouchCommand command : commands)
        touchPage_.command(command, test, touchHooks_, static_cast<std::uint64_t>(1 + instrument_.control().ticks()));
    touch_ = touchPage_.status(test, touchHooks_);
    std::lock_guard<std::mutex> lock(mutex_);
    touchProfile_ = touchPage_.file();
}

} // namespace armadillo::live
