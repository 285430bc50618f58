#pragma once
// The sources and outputs of the rig on the block clock (the app and the plugin): the device
// (serial port or the in-process simulated forearm, with the guided calibration,
// procedures::DeviceCalibration), the built-in simulated arm the user can steer, OSC in and out,
// the left arm's OSC sender, the mapping's OSC targets, and the 200 Hz control clock that feeds
// them and runs the control step while no audio comes (BlockControl::idleTick). `play` wires
// the same sources in LiveSession on the source's own clock. No JUCE.
//
// Threads:
//  - message thread: everything public except where noted (connect, configure, calibration,
//    steering, status text). Sockets, ports and files are opened and closed here only.
//  - control clock (a thread of its own, every 5 ms): clockTick — advances the simulated arm
//    into its mailbox, runs idle control steps, sends OSC (the frame, gestures, and the mapping's
//    queued packets), runs the front end's clock hook (the standalone's MIDI port drains its
//    queue there), measures the control rate. The mapping's OSC senders are shared with the message thread under mappingOscMutex_. The
//    simulated arm's steering is shared with the message thread under simMutex_, which the audio
//    thread never takes.
//  - device link thread (inside DeviceConnection): calibrates packets into the Device mailbox and
//    answers with the motor levels due on the timeline (Link/LevelSchedule.h).
#include "Link/LevelSchedule.h"
#include "Link/SteerableArm.h"
#include "Live/Session/BlockControl.h"
#include "Live/Step/ControlLoop.h"
#include "Live/Sources/DeviceConnection.h"
#include "Live/Step/LeftArm.h"
#include "Live/Sources/OscLink.h"
#include "Osc/HostPort.h"
#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace armadillo::osc {
class OscSender;
}

namespace armadillo::live {

class BlockRig {
public:
    /// The sources of `instrument` (Instrument.h: its mailboxes, its left arm and the slots its
    /// sources are kept in, all of which outlive this rig) on the block clock `control`.
    BlockRig(Instrument& instrument, BlockControl& control, link::LevelSchedule& motors);
    ~BlockRig();   // stops the clock, then the device link (its last packet is all-off)

    /// Before start(): called on the control clock after every tick (the front end's own
    /// non-real-time outputs, e.g. the standalone app's MIDI port).
    void setClockHook(std::function<void()> hook) { clockHook_ = std::move(hook); }
    /// Starts the control clock (after the owner is fully built).
    void start();
    /// Stops the control clock (waiting for a running tick), then the device link (its last
    /// packet all-off). Idempotent; the destructor calls it. The device stays disconnected.
    void stop();

    // Simulated arm (message thread)
    core::Pose simulatorPose() const;
    bool simulatorWandering() const;
    void steerSimulator(const core::Pose& pose);
    void setSimulatorWandering(bool on);
    /// The simulated arm follows `motion` (a pose or quaternion file: link::FileMotion) from now,
    /// on the control clock's time; null: it wanders again (issue 46: Pure Data's `simulate FILE`).
    void followSimulatorMotion(std::shared_ptr<const link::MotionSource> motion);

    // OSC (message thread): returns "" or what was refused.
    std::string configureOsc(bool outEnabled, const std::string& outHost, int outPort, bool inEnabled, int inPort,
                             const std::string& inFormat, const std::string& inMount);
    OscInput& oscInput() noexcept { return oscIn_; }
    /// The left arm's OSC sender (docs/STAGE.md "Two arms"; message thread): on/off and its
    /// port, the same dialects, detection and mount as the right arm's OSC input (format and
    /// mount detected). Returns "" or what was refused (the left arm is then off).
    std::string configureLeftArmOsc(bool enabled, int port);
    LeftArm& leftArm() noexcept { return leftArm_; }
    bool leftArmOn() const noexcept { return leftArm_.on(); }
    OscInput& leftOscInput() noexcept { return leftOscIn_; }
    osc::OscInputStats leftOscInputStats() const { return leftOscIn_.stats(); }
    std::uint64_t oscMessagesSent() const noexcept { return oscOut_.messagesSent(); }
    /// The mapping's OSC targets (index = mapping::OscPacket::target), opened here (message
    /// thread). Returns "" or which targets could not be used (their packets are dropped).
    std::string configureMappingOsc(const std::vector<osc::HostPort>& targets);
    /// Packets the mapping sent / dropped (no target, socket full).
    std::uint64_t mappingOscSent() const noexcept { return mappingOscSent_.load(std::memory_order_relaxed); }
    std::uint64_t mappingOscDropped() const noexcept { return mappingOscDropped_.load(std::memory_order_relaxed); }

    // Device (message thread)
    void connectDevice(const std::string& port, int baud, const std::string& calibrationFile);
    void disconnectDevice();
    bool deviceConnected() const noexcept { return device_ != nullptr && device_->isOpen(); }
    DeviceConnection& device() noexcept { return *device_; }
    const procedures::DeviceCalibration& calibration() const noexcept { return device_->calibrationSession(); }
    bool beginCalibration(std::string& why);
    bool calibrationNext(std::string& why);
    void calibrationSkip();
    void cancelCalibration();
    /// Saves the finished guided calibration (noting `port` and the date in it) and applies it.
    bool saveCalibration(const std::string& path, const std::string& port, std::string& message);
    /// Timer: raw packets queued by the link thread → the guided calibration.
    void drainCalibration() { device_->calibrationSession().drain(); }

    /// Link, OSC and control-rate lines for the device panel (message thread).
    std::string linkStatus() const;
    double controlRateMeasured() const noexcept { return measuredRate_.load(std::memory_order_relaxed); }
    /// Counters for the status line (message thread): simulator steps fed to the control loop,
    /// the device link's good packets (0 when not connected), OSC input statistics.
    std::uint64_t simulatorSteps() const noexcept { return simulatorSteps_.load(std::memory_order_relaxed); }
    std::uint64_t devicePackets() const { return deviceConnected() ? device_->packetsReceived() : 0; }
    osc::OscInputStats oscInputStats() const { return oscIn_.stats(); }

private:
    void clockLoop();            // control clock thread
    void clockTick(double dt);   // control clock thread
    void sendMappingOsc();       // control clock thread
    void applyGuidedCalibration();

    ControlLoop& loop_;
    BlockControl& control_;
    mutable std::mutex simMutex_;      // simulated arm: message ↔ clock thread only
    link::SteerableArm simulator_;
    OscOutput oscOut_;
    OscInput oscIn_;
    LeftArm& leftArm_;                 // the instrument's: its mailbox outlives the receiver
    OscInput leftOscIn_;
    std::mutex mappingOscMutex_;       // mapping OSC senders: message ↔ clock thread only
    std::vector<std::unique_ptr<osc::OscSender>> mappingOsc_;
    std::atomic<std::uint64_t> mappingOscSent_ {0}, mappingOscDropped_ {0};
    std::unique_ptr<DeviceConnection> device_;
    std::string deviceMessage_;        // message thread
    std::string networkStatus_;        // message thread
    std::atomic<double> measuredRate_ {0.0};
    std::atomic<std::uint64_t> simulatorSteps_ {0};
    std::uint64_t lastSentSerial_ = 0; // clock thread
    double rateWindowStartMs_ = 0.0;   // clock thread
    std::uint64_t rateWindowTicks_ = 0;
    std::function<void()> clockHook_;
    std::atomic<bool> clockRunning_ {false};
    std::thread clock_;
};

} // namespace armadillo::live
