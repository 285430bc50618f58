#pragma once
// OSC for Max/MSP and Pd (INTERFACES.md "OSC"): out = orientation, pose, gyro, motors, gestures;
// in = /armadillo/orientation ffff or /armadillo/imu fffffffff into the live-input mailbox.
// Neither runs on the audio thread.
#include "Core/Types.h"
#include "Plugin/LiveInput.h"
#include <juce_osc/juce_osc.h>
#include <atomic>
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
    void sendGesture(const char* name, float value);
    std::uint64_t messagesSent() const noexcept { return sent_.load(std::memory_order_relaxed); }

private:
    std::mutex mutex_;   // between configure (message thread) and sends (clock thread), never audio
    juce::OSCSender sender_;
    bool connected_ = false;
    std::atomic<std::uint64_t> sent_ {0};
};

class OscInput : private juce::OSCReceiver::Listener<juce::OSCReceiver::RealtimeCallback> {
public:
    explicit OscInput(LiveInput& live) : live_(live) { receiver_.addListener(this); }
    ~OscInput() override;
    /// Message thread. Opens (or closes with enabled = false) the UDP port.
    bool configure(bool enabled, int port, std::string& whyNot);
    std::uint64_t messagesReceived() const noexcept { return received_.load(std::memory_order_relaxed); }
    std::uint64_t messagesRejected() const noexcept { return rejected_.load(std::memory_order_relaxed); }

    /// Parses one message into the mailbox; public so tests can drive it without sockets.
    bool handle(const juce::OSCMessage& message);

private:
    void oscMessageReceived(const juce::OSCMessage& message) override;
    LiveInput& live_;
    juce::OSCReceiver receiver_;
    int openPort_ = 0;
    std::atomic<std::uint64_t> received_ {0}, rejected_ {0};
};

} // namespace armadillo::plugin
