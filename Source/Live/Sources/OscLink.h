#pragma once
// OSC for Max/MSP and Pd (INTERFACES.md "OSC"), on the device module's own codec and sockets:
// out = orientation, pose, gyro, motors, gestures; in = /armadillo/orientation ffff,
// /armadillo/imu fffffffff, or a phone app / NGIMU dialect (docs/SENSORS.md: detected, or forced
// with the options, and turned into the forearm's frame by the mount) into the live-input
// mailbox. Neither runs on the audio thread.
#include "Core/Types.h"
#include "Osc/OscIo.h"
#include "Live/Step/ArmFrame.h"
#include "Live/Step/LiveInput.h"
#include "Live/Sources/SourceRegistry.h"
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <string>

namespace armadillo::live {

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
    std::unique_ptr<osc::OscSender> sender_;
};

class OscInput {
public:
    /// SCHED_FIFO priority of the receiving thread (one below the device link's, DeviceConnection).
    static constexpr int kReceiverPriority = 19;
    /// `live` the mailbox it fills; `slot` where the instrument keeps its source (Instrument.h).
    OscInput(live::LiveInput& live, ArmSourceSlot& slot) : live_(live), source_(slot) {}
    ~OscInput();
    /// Message thread. Opens (or closes with enabled = false) the UDP port; `options` force a
    /// format and/or give a mount (default: detect, and the detected format's usual mount).
    bool configure(bool enabled, int port, std::string& whyNot, const osc::OscInputOptions& options = {});
    /// The same from the plugin's settings: `format` a name ("" = auto, docs/SENSORS.md) and
    /// `mount` a preset name or mount file ("" = the detected format's usual one). A bad name or
    /// file is refused with a reason (the input stays as it was).
    bool configure(bool enabled, int port, const std::string& format, const std::string& mount, std::string& whyNot);
    osc::OscInputStats stats() const;
    /// The sender's format (Auto until detected), device, and a one-line summary for the panel.
    osc::OscFormat format() const;
    std::string deviceName() const;
    std::string statusText() const;
    /// The mount calibration's feed (message thread): sensor-frame samples from the merger's
    /// tap, kept on across reconfigurations while on. pop returns false when there is none.
    void enableSensorTap(bool on);
    bool popSensorSample(osc::SensorFrameSample& out);

private:
    live::LiveInput& live_;
    mutable std::mutex mutex_;
    ArmSourceSlot& source_;                    // the sender's port, opened through the registry into the instrument's slot
    osc::OscReceiver* receiver_ = nullptr;     // source_'s receiver (null when off)
    int openPort_ = 0;
    osc::OscFormat openFormat_ = osc::OscFormat::Auto;
    Eigen::Quaterniond openMount_ = Eigen::Quaterniond::Identity();
    bool openMountGiven_ = false;
    bool tapOn_ = false;
    std::chrono::steady_clock::time_point openedAt_ {};   // when the receiver started listening
};

} // namespace armadillo::live
