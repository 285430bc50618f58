#include "Live/Session/BlockWebView.h"
#include "Live/Session/BlockInstrument.h"
#include "Mqtt/MessageService.h"
#include "Link/TouchProfile.h"
#include "Live/Session/WebWalk.h"
#include <algorithm>
#include <cmath>

namespace armadillo::live {

BlockWebView::BlockWebView(BlockInstrument& instrument, Host host) : instrument_(instrument), host_(std::move(host))
{
    snapshot_.source = "starting";
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
    using C = web::ProcedureCommand;
    std::vector<C> commands;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        commands.swap(pendingCalibration_);
    }
    BlockRig& rig = instrument_.rig();
    for (const C command : commands) {
        std::string why;
        if (command == C::Begin) {
            calibrationNote_ = rig.beginCalibration(why) ? "begun: keep the arm as the step asks" : "not begun: " + why;
            if (why.empty()) {
                std::lock_guard<std::mutex> lock(mutex_);
                calibrationFile_.clear();
            }
        } else if (!rig.deviceConnected() || !rig.calibration().running()) {
            calibrationNote_ = "no calibration runs: begin it first";
        } else if (command == C::Next) {
            calibrationNote_ = rig.calibrationNext(why) ? "step taken" : "not yet: " + why;
        } else if (command == C::Skip) {
            rig.calibrationSkip();
            calibrationNote_ = "step skipped: it keeps the starting calibration's numbers";
        } else {
            rig.cancelCalibration();
            calibrationNote_ = "cancelled: nothing kept";
        }
        if (command != C::Begin && command != C::Cancel && rig.deviceConnected() && rig.calibration().finished()) {
            const procedures::DeviceCalibration& done = rig.calibration();
            const std::string measured = done.measuredList(true), kept = done.measuredList(false);
            calibrationNote_ = "calibration complete: " + (measured.empty() ? std::string("nothing measured") : "measured " + measured) +
                               (kept.empty() ? std::string() : "; kept " + kept) +
                               ". It is the device's calibration now (not saved): download it below, or save it in the Calibration window.";
            std::lock_guard<std::mutex> lock(mutex_);
            calibrationFile_ = link::calibrationToJson(done.result());
        }
    }
    web::ProcedureStatus c;
    c.available = rig.deviceConnected();
    if (!c.available) c.why = "the device calibration needs a device or the simulated forearm connected (Device…)";
    c.steps = procedures::DeviceCalibration::kStepCount;
    if (c.available) {
        const procedures::DeviceCalibration& session = rig.calibration();
        c.running = session.running();
        c.finished = session.finished();
        if (c.running || c.finished) {
            c.step = session.stepNumber();
            c.title = session.stepTitle();
            c.instruction = c.finished ? std::string() : session.instruction();
            c.progress = session.progress();
            c.ready = session.ready();
        }
    }
    c.note = calibrationNote_;
    return c;
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
    using State = procedures::TouchTest::State;
    using C = web::TouchCommand;
    std::vector<C> commands;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        commands.swap(pendingTouch_);
    }
    procedures::TouchTest& test = instrument_.touchTest();
    touch_.available = host_.beginTouchTest && host_.endTouchTest;
    touch_.why = touch_.available ? std::string() : "this front end offers no sensitivity test";
    auto running = [&] { return test.state() == State::Presenting || test.state() == State::Asking; };
    for (const C command : commands) {
        (void) test.poll();
        if (!touch_.available) {
            touch_.note = "not available: " + touch_.why;
        } else if (command == C::Begin) {
            if (running()) {
                touch_.note = "a test runs already: answer it, or cancel it first";
            } else {
                host_.beginTouchTest(static_cast<std::uint64_t>(1 + instrument_.control().ticks()));
                touch_.finished = false;
                touch_.result.clear();
                touch_.note = "begun: one motor at a time; answer each stimulus once it has played";
            }
        } else if (command == C::Cancel) {
            touch_.note = running() ? "cancelled: nothing kept; the motors are the scene's again" : "no test runs";
            if (running()) host_.endTouchTest(false);
        } else if (test.state() != State::Asking) {
            touch_.note = running() ? "wait: the stimulus is still playing" : "no test runs: begin it first";
        } else if (command == C::Again) {
            test.again();
            touch_.note = "again: the same stimulus";
        } else {
            test.answer(command == C::Felt);
            touch_.note = command == C::Felt ? "answered: felt" : "answered: not felt";
        }
    }
    (void) test.poll();
    if (touch_.available && test.state() == State::Done) {
        touch_.finished = true;
        touch_.result = test.summary();
        touch_.note = "complete: " + touch_.result + ". The profile is the reader's now.";
        {
            std::lock_guard<std::mutex> lock(mutex_);
            touchProfile_ = link::touchProfileToJson(test.profile());
        }
        host_.endTouchTest(true);
    }
    touch_.running = running();
    touch_.asking = test.state() == State::Asking;
    touch_.comfort = test.comfortStep();
    touch_.stimuli = test.stimuli();
    touch_.question = touch_.asking ? test.question() : std::string();
}

} // namespace armadillo::live
