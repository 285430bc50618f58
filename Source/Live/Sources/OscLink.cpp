#include "Live/Sources/OscLink.h"
#include "Core/Pose.h"
#include "Link/Mount.h"
#include <cstdio>
#include <exception>

namespace armadillo::live {

bool OscOutput::configure(bool enabled, const std::string& host, int port, std::string& whyNot)
{
    std::lock_guard<std::mutex> lock(mutex_);
    sender_.reset();
    whyNot.clear();
    if (! enabled) return true;
    if (port < 1 || port > 65535) {
        whyNot = "OSC port must be 1-65535";
        return false;
    }
    try {
        sender_ = std::make_unique<osc::OscSender>(osc::HostPort {host.empty() ? "127.0.0.1" : host, port});
    } catch (const std::exception& e) {
        whyNot = e.what();
        return false;
    }
    return true;
}

void OscOutput::sendFrame(const ArmFrame& f)
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (sender_ == nullptr || ! f.valid) return;
    sender_->sendOrientation(Eigen::Quaterniond(f.q[0], f.q[1], f.q[2], f.q[3]));
    sender_->sendPose(core::Pose {f.pose[0], f.pose[1], f.pose[2]});
    sender_->sendGyro(Eigen::Vector3d(f.gyro[0], f.gyro[1], f.gyro[2]));
    sender_->sendMotors(f.motors, f.motorCount);
}

void OscOutput::sendGesture(const char* name)
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (sender_ != nullptr) sender_->sendGesture(name);
}

std::uint64_t OscOutput::messagesSent() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return sender_ != nullptr ? sender_->sent() : 0;
}

OscInput::~OscInput()
{
    std::lock_guard<std::mutex> lock(mutex_);
    source_.close();
}

bool OscInput::configure(bool enabled, int port, std::string& whyNot, const osc::OscInputOptions& options)
{
    std::lock_guard<std::mutex> lock(mutex_);
    whyNot.clear();
    const bool sameOptions = openFormat_ == options.format && openMountGiven_ == options.mountGiven
                             && (! options.mountGiven || openMount_.isApprox(options.mount.rotation));
    if (enabled && receiver_ != nullptr && openPort_ == port && sameOptions) return true;
    source_.close();
    receiver_ = nullptr;
    openPort_ = 0;
    if (! enabled) return true;
    if (port < 1 || port > 65535) {
        whyNot = "OSC input port must be 1-65535";
        return false;
    }
    try {
        // Handlers run on the receiver's thread; the mailbox takes them without locks.
        // The receiving thread keeps time as the device link's does: each sample's arrival is
        // where its control step goes in the host's block (BlockControl, issue 36).
        ArmSourceDescription description;
        description.kind = ArmSourceDescription::Kind::OscUdp;
        description.oscPort = port;
        description.osc = options;
        description.osc.realtimePriority = kReceiverPriority;
        ArmSourceHandlers handlers;
        handlers.onImu = [this](const core::ImuSample& s) { live_.pushImu(s); };
        handlers.onOrientation = [this](double t, const Eigen::Quaterniond& q) { live_.storeOrientation(t, q); };
        receiver_ = source_.open(description, std::move(handlers)).osc();   // IoError when the port is taken
        receiver_->merger().enableSensorTap(tapOn_);
        source_->start();
    } catch (const std::exception& e) {
        source_.close();
        receiver_ = nullptr;
        whyNot = e.what();
        return false;
    }
    openPort_ = port;
    openedAt_ = std::chrono::steady_clock::now();
    openFormat_ = options.format;
    openMountGiven_ = options.mountGiven;
    openMount_ = options.mount.rotation;
    return true;
}

bool OscInput::configure(bool enabled, int port, const std::string& format, const std::string& mount, std::string& whyNot)
{
    osc::OscInputOptions options;
    if (! format.empty() && ! osc::parseOscFormat(format, options.format)) {
        whyNot = "unknown sender format '" + format + "' (one of " + osc::oscFormatNames() + ")";
        return false;
    }
    if (! mount.empty()) {
        try {
            options.mount = link::mountFromArgument(mount);
            options.mountGiven = true;
        } catch (const std::exception& e) {
            whyNot = e.what();
            return false;
        }
    }
    return configure(enabled, port, whyNot, options);
}

osc::OscFormat OscInput::format() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return receiver_ != nullptr ? receiver_->format() : osc::OscFormat::Auto;
}

std::string OscInput::deviceName() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return receiver_ != nullptr ? receiver_->deviceName() : std::string();
}

std::string OscInput::statusText() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (receiver_ == nullptr) return "OSC input off";
    const osc::OscInputStats s = receiver_->stats();
    std::string text = std::string("OSC in: ") + osc::oscFormatName(receiver_->format());
    if (receiver_->format() == osc::OscFormat::Auto) text += " (waiting for a sender)";
    else text += " from " + receiver_->deviceName() + ", mount " + receiver_->merger().mount().name;
    const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - openedAt_).count();
    if (s.imu + s.orientation == 0 && waited >= 5.0) {
        // Nothing usable after a few seconds: what was heard instead helps find out why.
        text += "; nothing usable on UDP/TCP port " + std::to_string(receiver_->port()) + " for " + std::to_string(static_cast<int>(waited)) +
                " s, heard: " + osc::describeHeard(receiver_->merger().heard()) +
                " (check the sender's target address and port, the network and the firewall)";
    } else if (s.imu + s.orientation > 0) {
        const osc::OscSensorRates r = receiver_->merger().rates();
        char rate[48];
        std::snprintf(rate, sizeof rate, "; %.0f Hz", r.fusion());
        text += rate;
        const std::string advice = s.unchanged == 0 ? osc::lowRateAdvice(receiver_->format(), r.fusion()) : std::string();
        if (!advice.empty()) text += "; warning: " + advice;
    }
    text += "; refused " + std::to_string(s.bad) + " (wrong types " + std::to_string(s.wrongTypes) + ", NaN/inf " + std::to_string(s.nonFinite)
            + ", absurd " + std::to_string(s.absurd) + ", malformed " + std::to_string(s.malformed + s.tooDeep) + "), other device "
            + std::to_string(s.otherDevice) + ", other app " + std::to_string(s.otherFormat) + ", flood " + std::to_string(s.flood);
    const char* e = receiver_->merger().lastError();
    if (e[0] != 0) text += "; last: " + std::string(e);
    return text;
}

void OscInput::enableSensorTap(bool on)
{
    std::lock_guard<std::mutex> lock(mutex_);
    tapOn_ = on;
    if (receiver_ != nullptr) receiver_->merger().enableSensorTap(on);
}

bool OscInput::popSensorSample(osc::SensorFrameSample& out)
{
    std::lock_guard<std::mutex> lock(mutex_);
    return receiver_ != nullptr && receiver_->merger().popSensorSample(out);
}

osc::OscInputStats OscInput::stats() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return receiver_ != nullptr ? receiver_->stats() : osc::OscInputStats {};
}

} // namespace armadillo::live
