#pragma once
// The plugin's connections to the outside: the device (serial port or the in-process simulated
// forearm, with guided calibration), the built-in simulated arm the user can steer, OSC in and
// out, and the 200 Hz control clock that feeds them and runs the control step while no audio
// comes (BlockControl::idleTick).
//
// Threads:
//  - message thread: everything public except where noted (connect, configure, calibration,
//    steering, status text). Sockets, ports and files are opened and closed here only.
//  - control clock (a JUCE high-resolution timer thread): clockTick — advances the simulated arm
//    into its mailbox, runs idle control steps, sends OSC (the frame, gestures, and the mapping's
//    queued packets), sends the standalone's queued MIDI to its ALSA port, measures the control
//    rate. The mapping's OSC senders are shared with the message thread under mappingOscMutex_. The
//    simulated arm's steering is shared with the message thread under simMutex_, which the audio
//    thread never takes.
//  - device link thread (inside DeviceConnection): calibrates packets into the Device mailbox and
//    answers with the motor levels due on the timeline (Link/LevelSchedule.h).
#include "Link/LevelSchedule.h"
#include "Link/SteerableArm.h"
#include "Live/ControlLoop.h"
#include "Live/BlockControl.h"
#include "Plugin/DeviceConnection.h"
#include "Live/LeftArm.h"
#include "Plugin/MidiPort.h"
#include "Live/OscLink.h"
#include <juce_audio_processors/juce_audio_processors.h>
#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

namespace armadillo::plugin {

class Connections {
public:
    Connections(live::ControlLoop& loop, live::BlockControl& control, device::LevelSchedule& motors);
    ~Connections();   // stops the clock, then the device link (its last packet is all-off)

    /// Starts the control clock (after the owner is fully built).
    void start();

    // Simulated arm (message thread)
    Pose simulatorPose() const;
    bool simulatorWandering() const;
    void steerSimulator(const Pose& pose);
    void setSimulatorWandering(bool on);

    // OSC (message thread): returns "" or what was refused.
    juce::String configureOsc(bool outEnabled, const juce::String& outHost, int outPort, bool inEnabled, int inPort,
                              const juce::String& inFormat, const juce::String& inMount);
    live::OscInput& oscInput() noexcept { return oscIn_; }
    /// The left arm's OSC sender (docs/STAGE.md "Two arms"; message thread): on/off and its
    /// port, the same dialects, detection and mount as the right arm's OSC input (format and
    /// mount detected). Returns "" or what was refused (the left arm is then off).
    juce::String configureLeftArmOsc(bool enabled, int port);
    live::LeftArm& leftArm() noexcept { return leftArm_; }
    bool leftArmOn() const noexcept { return leftArm_.on(); }
    live::OscInput& leftOscInput() noexcept { return leftOscIn_; }
    device::OscInputStats leftOscInputStats() const { return leftOscIn_.stats(); }
    std::uint64_t oscMessagesSent() const noexcept { return oscOut_.messagesSent(); }
    /// The mapping's OSC targets (index = mapping::OscPacket::target), opened here (message
    /// thread). Returns "" or which targets could not be used (their packets are dropped).
    juce::String configureMappingOsc(const std::vector<device::HostPort>& targets);
    /// Packets the mapping sent / dropped (no target, socket full).
    std::uint64_t mappingOscSent() const noexcept { return mappingOscSent_.load(std::memory_order_relaxed); }
    std::uint64_t mappingOscDropped() const noexcept { return mappingOscDropped_.load(std::memory_order_relaxed); }

    /// The standalone app's ALSA sequencer port (docs/PLUGIN.md "MIDI out").
    MidiPort& midiPort() noexcept { return midiPort_; }
    const MidiPort& midiPort() const noexcept { return midiPort_; }

    // Device (message thread)
    void connectDevice(const juce::String& port, int baud, const juce::String& calibrationFile);
    void disconnectDevice();
    bool deviceConnected() const noexcept { return device_ != nullptr && device_->isOpen(); }
    DeviceConnection& device() noexcept { return *device_; }
    const procedures::DeviceCalibration& calibration() const noexcept { return device_->calibrationSession(); }
    bool beginCalibration(juce::String& why);
    bool calibrationNext(juce::String& why);
    void calibrationSkip();
    void cancelCalibration();
    /// Saves the finished guided calibration (noting `port` and the date in it) and applies it.
    bool saveCalibration(const juce::File& file, const juce::String& port, juce::String& message);
    /// Timer: raw packets queued by the link thread → the guided calibration.
    void drainCalibration() { device_->calibrationSession().drain(); }

    /// Link, OSC and control-rate lines for the device panel (message thread).
    juce::String linkStatus() const;
    double controlRateMeasured() const noexcept { return measuredRate_.load(std::memory_order_relaxed); }
    /// Counters for the status line (message thread): simulator steps fed to the control loop,
    /// the device link's good packets (0 when not connected), OSC input statistics.
    std::uint64_t simulatorSteps() const noexcept { return simulatorSteps_.load(std::memory_order_relaxed); }
    std::uint64_t devicePackets() const { return deviceConnected() ? device_->packetsReceived() : 0; }
    device::OscInputStats oscInputStats() const { return oscIn_.stats(); }

private:
    class Clock;
    void clockTick(double dt);   // control clock thread
    void sendMappingOsc();       // control clock thread
    void applyGuidedCalibration();

    live::ControlLoop& loop_;
    live::BlockControl& control_;
    mutable std::mutex simMutex_;      // simulated arm: message ↔ clock thread only
    device::SteerableArm simulator_;
    live::OscOutput oscOut_;
    live::OscInput oscIn_;
    live::LeftArm leftArm_;                  // before leftOscIn_: its mailbox outlives the receiver
    live::OscInput leftOscIn_;
    std::mutex mappingOscMutex_;       // mapping OSC senders: message ↔ clock thread only
    std::vector<std::unique_ptr<device::OscSender>> mappingOsc_;
    std::atomic<std::uint64_t> mappingOscSent_ {0}, mappingOscDropped_ {0};
    MidiPort midiPort_;
    std::unique_ptr<DeviceConnection> device_;
    juce::String deviceMessage_;       // message thread
    juce::String networkStatus_;       // message thread
    std::atomic<double> measuredRate_ {0.0};
    std::atomic<std::uint64_t> simulatorSteps_ {0};
    std::uint64_t lastSentSerial_ = 0; // clock thread
    double rateWindowStartMs_ = 0.0;   // clock thread
    std::uint64_t rateWindowTicks_ = 0;
    std::unique_ptr<Clock> clock_;
};

} // namespace armadillo::plugin
