#include "Plugin/Connections.h"
#include "Link/Calibration.h"

namespace armadillo::plugin {

class Connections::Clock : public juce::HighResolutionTimer {
public:
    explicit Clock(Connections& owner) : owner_(owner) {}
    ~Clock() override { stopTimer(); }
    void hiResTimerCallback() override
    {
        const double now = juce::Time::getMillisecondCounterHiRes();
        const double dt = last_ < 0.0 ? 0.005 : (now - last_) * 1.0e-3;
        last_ = now;
        owner_.clockTick(dt);
    }

private:
    Connections& owner_;
    double last_ = -1.0;
};

Connections::Connections(live::ControlLoop& loop, live::BlockControl& control, device::LevelSchedule& motors)
    : loop_(loop), control_(control), oscIn_(loop.input(live::SourceKind::Osc)), leftOscIn_(leftArm_.input()),
      device_(std::make_unique<DeviceConnection>(loop.input(live::SourceKind::Device), motors))
{
}

Connections::~Connections()
{
    clock_.reset();     // waits for a running callback
    device_.reset();    // link thread stopped; its last packet was all-off
}

void Connections::start()
{
    clock_ = std::make_unique<Clock>(*this);
    clock_->startTimer(5);   // 200 Hz
}

// ------------------------------------------------------------------------------------------------
// Control clock thread

void Connections::clockTick(double dt)
{
    dt = juce::jlimit(0.0, 0.1, dt);
    if (control_.source() == live::SourceKind::Simulator) {
        Eigen::Quaterniond q;
        double t = 0.0;
        {
            std::lock_guard<std::mutex> lock(simMutex_);
            q = simulator_.advance(dt);
            t = simulator_.time();
        }
        loop_.input(live::SourceKind::Simulator).storeOrientation(t, q);
        simulatorSteps_.fetch_add(1, std::memory_order_relaxed);
    }
    control_.idleTick(dt);

    const auto f = control_.latestFrame();
    if (f.serial != lastSentSerial_) {
        lastSentSerial_ = f.serial;
        oscOut_.sendFrame(f);
    }
    GestureEvent g;
    while (control_.popGesture(g)) oscOut_.sendGesture(g.name);
    sendMappingOsc();
    midiPort_.drain();

    const double now = juce::Time::getMillisecondCounterHiRes();
    if (now - rateWindowStartMs_ >= 1000.0) {
        const auto ticks = control_.ticks();
        if (rateWindowStartMs_ > 0.0)
            measuredRate_.store((ticks - rateWindowTicks_) * 1000.0 / (now - rateWindowStartMs_), std::memory_order_relaxed);
        rateWindowTicks_ = ticks;
        rateWindowStartMs_ = now;
    }
}

void Connections::sendMappingOsc()
{
    // The control side queued encoded packets (Mapping/Mapper.h OscPacket); each leaves as it is
    // to its target through the device module's sender (IPv4 and IPv6, non-blocking).
    std::lock_guard<std::mutex> lock(mappingOscMutex_);
    mapping::OscPacket p;
    while (control_.mappingOutputs().popOsc(p)) {
        const auto target = static_cast<std::size_t>(p.target);
        device::OscSender* sender = p.target >= 0 && target < mappingOsc_.size() ? mappingOsc_[target].get() : nullptr;
        const bool sent = sender != nullptr && sender->sendPacket(p.bytes.data(), p.size);
        (sent ? mappingOscSent_ : mappingOscDropped_).fetch_add(1, std::memory_order_relaxed);
    }
}

juce::String Connections::configureMappingOsc(const std::vector<device::HostPort>& targets)
{
    std::vector<std::unique_ptr<device::OscSender>> senders;
    juce::String problems;
    for (const auto& t : targets) {
        try {
            senders.push_back(std::make_unique<device::OscSender>(t));
        } catch (const std::exception& e) {
            senders.push_back(nullptr);
            problems << "OSC target " << juce::String(t.host) << ":" << t.port << ": " << juce::String(e.what()) << ". ";
        }
    }
    std::lock_guard<std::mutex> lock(mappingOscMutex_);
    mappingOsc_.swap(senders);
    return problems.trim();   // the old senders close here, after the lock: no send is using them
}

// ------------------------------------------------------------------------------------------------
// Simulated arm

Pose Connections::simulatorPose() const
{
    std::lock_guard<std::mutex> lock(simMutex_);
    return simulator_.pose();
}

bool Connections::simulatorWandering() const
{
    std::lock_guard<std::mutex> lock(simMutex_);
    return simulator_.wandering();
}

void Connections::steerSimulator(const Pose& pose)
{
    std::lock_guard<std::mutex> lock(simMutex_);
    simulator_.steerTo(pose);
}

void Connections::setSimulatorWandering(bool on)
{
    std::lock_guard<std::mutex> lock(simMutex_);
    simulator_.setWandering(on);
}

// ------------------------------------------------------------------------------------------------
// OSC

juce::String Connections::configureOsc(bool outEnabled, const juce::String& outHost, int outPort, bool inEnabled, int inPort,
                                       const juce::String& inFormat, const juce::String& inMount)
{
    std::string why;
    juce::String message;
    if (! oscOut_.configure(outEnabled, outHost.toStdString(), outPort, why)) message << "OSC out: " << juce::String(why) << ". ";
    if (! oscIn_.configure(inEnabled, inPort, inFormat.toStdString(), inMount.toStdString(), why))
        message << "OSC in: " << juce::String(why) << ".";
    networkStatus_ = message.trim();
    return networkStatus_;
}

juce::String Connections::configureLeftArmOsc(bool enabled, int port)
{
    std::string why;
    const bool ok = leftOscIn_.configure(enabled, port, why);
    leftArm_.setOn(enabled && ok);   // the control side fuses it (and the engine hears two arms) only while it listens
    return ok ? juce::String() : "Left arm OSC in: " + juce::String(why) + ".";
}

// ------------------------------------------------------------------------------------------------
// Device and guided calibration

void Connections::connectDevice(const juce::String& port, int baud, const juce::String& calibrationFile)
{
    std::string message;
    device_->connect(port.toStdString(), baud, calibrationFile.toStdString(), message);
    deviceMessage_ = juce::String(message);
}

void Connections::disconnectDevice()
{
    const bool calibrating = device_->calibrationSession().running();
    device_->disconnect();   // cancels a running calibration: its packets stop; the last packet is all-off
    deviceMessage_ = calibrating ? "Not connected; the calibration was cancelled." : "Not connected.";
}

bool Connections::beginCalibration(juce::String& why)
{
    if (! deviceConnected()) {
        why = "Connect a device (or the simulated forearm) first: the calibration measures its raw sensor counts.";
        return false;
    }
    device_->calibrationSession().begin(device_->calibration());
    why.clear();
    return true;
}

bool Connections::calibrationNext(juce::String& why)
{
    std::string reason;
    const bool ok = device_->calibrationSession().next(reason);
    why = juce::String(reason);
    if (ok && device_->calibrationSession().finished()) applyGuidedCalibration();
    return ok;
}

void Connections::calibrationSkip()
{
    device_->calibrationSession().skip();
    if (device_->calibrationSession().finished()) applyGuidedCalibration();
}

void Connections::cancelCalibration()
{
    device_->calibrationSession().cancel();
}

void Connections::applyGuidedCalibration()
{
    if (! deviceConnected()) return;   // the link went away: nothing to apply it to (disconnect cancels anyway)
    device_->applyCalibration(device_->calibrationSession().result(), "guided calibration, not saved");
    deviceMessage_ = "Guided calibration applied (not saved).";
}

bool Connections::saveCalibration(const juce::File& file, const juce::String& port, juce::String& message)
{
    const auto& session = device_->calibrationSession();
    if (! session.finished()) {
        message = "There is no finished calibration to save.";
        return false;
    }
    device::Calibration c = session.result();
    c.device = port.toStdString();
    c.date = juce::Time::getCurrentTime().toISO8601(true).toStdString();
    try {
        device::saveCalibration(file.getFullPathName().toStdString(), c);
    } catch (const std::exception& e) {
        message = "Calibration not saved: " + juce::String(e.what());
        return false;
    }
    if (deviceConnected()) {
        device_->applyCalibration(c, "calibration " + file.getFullPathName().toStdString());
        deviceMessage_ = "Guided calibration applied and saved as " + file.getFileName() + ".";
    }
    message = "Saved as " + file.getFileName() + "; the next connection loads it.";
    return true;
}

juce::String Connections::linkStatus() const
{
    juce::String s = deviceMessage_;
    if (deviceConnected()) s << "\n" << juce::String(device_->status());
    const auto in = oscIn_.stats();
    s << "\nControl rate " << juce::String(controlRateMeasured(), 1) << " Hz; OSC sent "
      << juce::String(static_cast<juce::int64>(oscOut_.messagesSent())) << ", received "
      << juce::String(static_cast<juce::int64>(in.imu + in.orientation)) << " (bad " << juce::String(static_cast<juce::int64>(in.bad)) << ")";
    s << "\n" << juce::String(oscIn_.statusText());   // sender format, device, mount, refusals by kind
    if (leftArm_.on()) s << "\nLeft arm " << juce::String(leftOscIn_.statusText());
    if (networkStatus_.isNotEmpty()) s << "\n" << networkStatus_;
    return s.trim();
}

} // namespace armadillo::plugin
