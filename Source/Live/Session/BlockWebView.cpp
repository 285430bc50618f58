#include "Live/Session/BlockWebView.h"
#include "Live/Session/BlockInstrument.h"
#include "Mqtt/MessageService.h"
#include "Navigation/Guidance.h"
#include <algorithm>
#include <cmath>

namespace armadillo::live {

BlockWebView::BlockWebView(BlockInstrument& instrument, Host host) : instrument_(instrument), host_(std::move(host))
{
    snapshot_.source = "starting";
    snapshot_.calibration.why = kCalibrationElsewhere;
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
    s.calibration.available = false;
    s.calibration.why = kCalibrationElsewhere;
    s.calibration.steps = procedures::DeviceCalibration::kStepCount;
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
    const navigation::NavigationRig& nav = instrument_.navigation();
    if (nav.running()) {
        const navigation::NavigationStatus n = nav.status();
        s.walk.on = true;
        s.walk.route = nav.routeName();
        s.walk.waypoint = n.waypoint;
        s.walk.waypointCount = n.waypointCount;
        s.walk.waypointName = n.name;
        s.walk.arrivals = n.arrivals;
        s.walk.distanceM = std::isfinite(n.distanceM) ? n.distanceM : -1.0;
        s.walk.bearingDeg = std::isfinite(n.bearingDeg) ? n.bearingDeg : -1.0;
        s.walk.finished = n.finished;
        s.walk.fix = navigation::fixStateName(n.fix);
    }
    return s;
}

std::vector<web::ParameterInfo> BlockWebView::parameters() { return host_.parameters ? host_.parameters() : std::vector<web::ParameterInfo> {}; }

void BlockWebView::stage(const core::StageCommand& command) { instrument_.stage().apply(command); }

bool BlockWebView::setParameter(const std::string& id, double value, double& set)
{
    return host_.setParameter && std::isfinite(value) && host_.setParameter(id, value, set);
}

void BlockWebView::calibration(web::ProcedureCommand)
{
    std::lock_guard<std::mutex> lock(mutex_);
    snapshot_.calibration.note = std::string("not here: ") + kCalibrationElsewhere;
}

std::string BlockWebView::calibrationFile() { return {}; }

} // namespace armadillo::live
