#include "Plugin/OscLink.h"
#include "Core/Pose.h"
#include <exception>

namespace armadillo::plugin {

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
        sender_ = std::make_unique<device::OscSender>(device::HostPort {host.empty() ? "127.0.0.1" : host, port});
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
    sender_->sendPose(Pose {f.pose[0], f.pose[1], f.pose[2]});
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
    if (receiver_ != nullptr) receiver_->stop();
}

bool OscInput::configure(bool enabled, int port, std::string& whyNot)
{
    std::lock_guard<std::mutex> lock(mutex_);
    whyNot.clear();
    if (enabled && receiver_ != nullptr && openPort_ == port) return true;
    if (receiver_ != nullptr) receiver_->stop();
    receiver_.reset();
    openPort_ = 0;
    if (! enabled) return true;
    if (port < 1 || port > 65535) {
        whyNot = "OSC input port must be 1-65535";
        return false;
    }
    try {
        // Handlers run on the receiver's thread; the mailbox takes them without locks.
        receiver_ = std::make_unique<device::OscReceiver>(
            port,
            [this](const ImuSample& s) { live_.pushImu(s); },
            [this](double t, const Eigen::Quaterniond& q) { live_.storeOrientation(t, q); });
        receiver_->start();
    } catch (const std::exception& e) {
        receiver_.reset();
        whyNot = e.what();
        return false;
    }
    openPort_ = port;
    return true;
}

device::OscInputStats OscInput::stats() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return receiver_ != nullptr ? receiver_->stats() : device::OscInputStats {};
}

} // namespace armadillo::plugin
