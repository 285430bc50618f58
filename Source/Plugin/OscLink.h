#pragma once
// OSC for Max/MSP and Pd (INTERFACES.md "OSC"), on the device module's own codec and sockets:
// out = orientation, pose, gyro, motors, gestures; in = /armadillo/orientation ffff or
// /armadillo/imu fffffffff into the live-input mailbox. Neither runs on the audio thread.
#include "Core/Types.h"
#include "Device/OscIo.h"
#include "Plugin/LiveInput.h"
#include <atomic>
#include <memory>
#include <mutex>
#include <string>

namespace armadillo::plugin {

/// What one control update publishes (audio/control thread → UI and OSC, through a seqlock).
struct ArmFrame {
    double t = 0.0;                          ///< s, control clock
    double q[4] {1.0, 0.0, 0.0, 0.0};        ///< w x y z, device → earth
    double pose[3] {};                       ///< elevation, azimuth, roll (deg)
    double gyro[3] {};                       ///< rad/s, device frame
    MotorLevels motors {};                   ///< after the safety stage
    int motorCount = kGridMotors;
    bool valid = false;
    std::uint64_t serial = 0;                ///< increments with each control update
};

class OscOutput {
public:
    /// Message thread. Returns false with a reason when the target cannot be used.
    bool configure(bool enabled, const std::string& host, int port, std::string& whyNot);
    /// Any one non-audio thread (the control clock).
    void sendFrame(const ArmFrame& frame);
    void sendGesture(const char* name);
    std::uint64_t messagesSent() const;

private:
    mutable std::mutex mutex_;   // configure (message thread) vs sends (clock thread); never audio
    std::unique_ptr<device::OscSender> sender_;
};

class OscInput {
public:
    explicit OscInput(LiveInput& live) : live_(live) {}
    ~OscInput();
    /// Message thread. Opens (or closes with enabled = false) the UDP port.
    bool configure(bool enabled, int port, std::string& whyNot);
    device::OscInputStats stats() const;

private:
    LiveInput& live_;
    mutable std::mutex mutex_;
    std::unique_ptr<device::OscReceiver> receiver_;
    int openPort_ = 0;
};

} // namespace armadillo::plugin
