#include "Live/Session/BlockRig.h"
#include "Core/Clock.h"
#include "Core/ThreadPriority.h"
#include "Link/Calibration.h"
#include "Osc/OscIo.h"
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>

namespace armadillo::live {

namespace {
/// The control clock's SCHED_FIFO priority (below the device link's and the OSC receiver's).
constexpr int kClockPriority = 18;
} // namespace

BlockRig::BlockRig(Instrument& instrument, BlockControl& control, link::LevelSchedule& motors)
    : loop_(instrument.loop()), control_(control), oscIn_(loop_.input(SourceKind::Osc), instrument.source(Instrument::Feed::Osc)),
      leftArm_(instrument.leftArm()), leftOscIn_(leftArm_.input(), instrument.source(Instrument::Feed::Left)),
      device_(std::make_unique<DeviceConnection>(loop_.input(SourceKind::Device), motors, instrument.source(Instrument::Feed::Device)))
{
}

BlockRig::~BlockRig()
{
    stop();
}

void BlockRig::stop()
{
    clockRunning_.store(false);
    if (clock_.joinable()) clock_.join();   // waits for a running tick
    device_.reset();    // link thread stopped; its last packet was all-off
}

void BlockRig::start()
{
    if (clockRunning_.exchange(true)) return;
    clock_ = std::thread([this] { clockLoop(); });
}

void BlockRig::clockLoop()
{
    (void) core::requestRealtimePriority(kClockPriority); // steadier idle steps where the system allows it
    using Clock = std::chrono::steady_clock;
    constexpr auto kPeriod = std::chrono::microseconds(5000);   // 200 Hz
    auto next = Clock::now();
    double last = -1.0;
    while (clockRunning_.load(std::memory_order_relaxed)) {
        next += kPeriod;
        std::this_thread::sleep_until(next);
        if (Clock::now() - next > 20 * kPeriod) next = Clock::now();   // a stall (suspend, debugger): no burst of catch-up ticks
        const double now = core::monotonicSeconds();
        clockTick(last < 0.0 ? 0.005 : now - last);
        last = now;
    }
}

// ------------------------------------------------------------------------------------------------
// Control clock thread

void BlockRig::clockTick(double dt)
{
    dt = std::clamp(dt, 0.0, 0.1);
    if (control_.source() == SourceKind::Simulator) {
        Eigen::Quaterniond q;
        double t = 0.0;
        {
            std::lock_guard<std::mutex> lock(simMutex_);
            q = simulator_.advance(dt);
            t = simulator_.time();
        }
        loop_.input(SourceKind::Simulator).storeOrientation(t, q);
        simulatorSteps_.fetch_add(1, std::memory_order_relaxed);
    }
    control_.idleTick(dt);

    const auto f = control_.latestFrame();
    if (f.serial != lastSentSerial_) {
        lastSentSerial_ = f.serial;
        oscOut_.sendFrame(f);
    }
    engine::GestureEvent g;
    while (control_.popGesture(g)) oscOut_.sendGesture(g.name);
    sendMappingOsc();
    if (clockHook_) clockHook_();

    const double now = core::monotonicSeconds() * 1e3;
    if (now - rateWindowStartMs_ >= 1000.0) {
        const auto ticks = control_.ticks();
        if (rateWindowStartMs_ > 0.0)
            measuredRate_.store((ticks - rateWindowTicks_) * 1000.0 / (now - rateWindowStartMs_), std::memory_order_relaxed);
        rateWindowTicks_ = ticks;
        rateWindowStartMs_ = now;
    }
}

void BlockRig::sendMappingOsc()
{
    // The control side queued encoded packets (Mapping/Mapper.h OscPacket); each leaves as it is
    // to its target through the device module's sender (IPv4 and IPv6, non-blocking).
    std::lock_guard<std::mutex> lock(mappingOscMutex_);
    mapping::OscPacket p;
    while (control_.mappingOutputs().popOsc(p)) {
        const auto target = static_cast<std::size_t>(p.target);
        osc::OscSender* sender = p.target >= 0 && target < mappingOsc_.size() ? mappingOsc_[target].get() : nullptr;
        const bool sent = sender != nullptr && sender->sendPacket(p.bytes.data(), p.size);
        (sent ? mappingOscSent_ : mappingOscDropped_).fetch_add(1, std::memory_order_relaxed);
    }
}

std::string BlockRig::configureMappingOsc(const std::vector<osc::HostPort>& targets)
{
    std::vector<std::unique_ptr<osc::OscSender>> senders;
    std::string problems;
    for (const auto& t : targets) {
        try {
            senders.push_back(std::make_unique<osc::OscSender>(t));
        } catch (const std::exception& e) {
            senders.push_back(nullptr);
            problems += (problems.empty() ? "" : " ") + std::string("OSC target ") + t.host + ":" + std::to_string(t.port) + ": " + e.what() + ".";
        }
    }
    std::lock_guard<std::mutex> lock(mappingOscMutex_);
    mappingOsc_.swap(senders);
    return problems;   // the old senders close here, after the lock: no send is using them
}

// ------------------------------------------------------------------------------------------------
// Simulated arm

core::Pose BlockRig::simulatorPose() const
{
    std::lock_guard<std::mutex> lock(simMutex_);
    return simulator_.pose();
}

bool BlockRig::simulatorWandering() const
{
    std::lock_guard<std::mutex> lock(simMutex_);
    return simulator_.wandering();
}

void BlockRig::steerSimulator(const core::Pose& pose)
{
    std::lock_guard<std::mutex> lock(simMutex_);
    simulator_.steerTo(pose);
}

void BlockRig::setSimulatorWandering(bool on)
{
    std::lock_guard<std::mutex> lock(simMutex_);
    simulator_.setWandering(on);
}

void BlockRig::followSimulatorMotion(std::shared_ptr<const link::MotionSource> motion)
{
    std::lock_guard<std::mutex> lock(simMutex_);   // (message ↔ clock thread only; never audio)
    simulator_.follow(std::move(motion));
}

// ------------------------------------------------------------------------------------------------
// OSC

std::string BlockRig::configureOsc(bool outEnabled, const std::string& outHost, int outPort, bool inEnabled, int inPort,
                                   const std::string& inFormat, const std::string& inMount)
{
    std::string why;
    std::string message;
    if (! oscOut_.configure(outEnabled, outHost, outPort, why)) message += "OSC out: " + why + ".";
    if (! oscIn_.configure(inEnabled, inPort, inFormat, inMount, why)) message += (message.empty() ? "" : " ") + std::string("OSC in: ") + why + ".";
    networkStatus_ = message;
    return networkStatus_;
}

std::string BlockRig::configureLeftArmOsc(bool enabled, int port)
{
    std::string why;
    const bool ok = leftOscIn_.configure(enabled, port, why);
    leftArm_.setOn(enabled && ok);   // the control side fuses it (and the engine hears two arms) only while it listens
    return ok ? std::string() : "Left arm OSC in: " + why + ".";
}

// ------------------------------------------------------------------------------------------------
// Device and guided calibration

void BlockRig::connectDevice(const std::string& port, int baud, const std::string& calibrationFile)
{
    std::string message;
    device_->connect(port, baud, calibrationFile, message);
    deviceMessage_ = message;
}

void BlockRig::disconnectDevice()
{
    const bool calibrating = device_->calibrationSession().running();
    device_->disconnect();   // cancels a running calibration: its packets stop; the last packet is all-off
    deviceMessage_ = calibrating ? "Not connected; the calibration was cancelled." : "Not connected.";
}

bool BlockRig::beginCalibration(std::string& why)
{
    if (! deviceConnected()) {
        why = "Connect a device (or the simulated forearm) first: the calibration measures its raw sensor counts.";
        return false;
    }
    device_->calibrationSession().begin(device_->calibration());
    why.clear();
    return true;
}

bool BlockRig::calibrationNext(std::string& why)
{
    const bool ok = device_->calibrationSession().next(why);
    if (ok && device_->calibrationSession().finished()) applyGuidedCalibration();
    return ok;
}

void BlockRig::calibrationSkip()
{
    device_->calibrationSession().skip();
    if (device_->calibrationSession().finished()) applyGuidedCalibration();
}

void BlockRig::cancelCalibration()
{
    device_->calibrationSession().cancel();
}

void BlockRig::applyGuidedCalibration()
{
    if (! deviceConnected()) return;   // the link went away: nothing to apply it to (disconnect cancels anyway)
    device_->applyCalibration(device_->calibrationSession().result(), "guided calibration, not saved");
    deviceMessage_ = "Guided calibration applied (not saved).";
}

bool BlockRig::saveCalibration(const std::string& path, const std::string& port, std::string& message)
{
    const auto& session = device_->calibrationSession();
    if (! session.finished()) {
        message = "There is no finished calibration to save.";
        return false;
    }
    link::Calibration c = session.result();
    c.device = port;
    const std::time_t now = std::time(nullptr);
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    c.date = date;
    const std::string name = path.substr(path.find_last_of('/') == std::string::npos ? 0 : path.find_last_of('/') + 1);
    try {
        link::saveCalibration(path, c);
    } catch (const std::exception& e) {
        message = "Calibration not saved: " + std::string(e.what());
        return false;
    }
    if (deviceConnected()) {
        device_->applyCalibration(c, "calibration " + path);
        deviceMessage_ = "Guided calibration applied and saved as " + name + ".";
    }
    message = "Saved as " + name + "; the next connection loads it.";
    return true;
}

std::string BlockRig::linkStatus() const
{
    std::string s = deviceMessage_;
    if (deviceConnected()) s += "\n" + device_->status();
    const auto in = oscIn_.stats();
    char line[200];
    std::snprintf(line, sizeof line, "\nControl rate %.1f Hz; OSC sent %llu, received %llu (bad %llu)", controlRateMeasured(),
                  static_cast<unsigned long long>(oscOut_.messagesSent()), static_cast<unsigned long long>(in.imu + in.orientation),
                  static_cast<unsigned long long>(in.bad));
    s += line;
    s += "\n" + oscIn_.statusText();   // sender format, device, mount, refusals by kind
    if (leftArm_.on()) s += "\nLeft arm " + leftOscIn_.statusText();
    if (! networkStatus_.empty()) s += "\n" + networkStatus_;
    const auto first = s.find_first_not_of(" \n"), last = s.find_last_not_of(" \n");
    return first == std::string::npos ? std::string() : s.substr(first, last - first + 1);
}

} // namespace armadillo::live
