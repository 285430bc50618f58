#pragma once
// The device source: a serial port (or the device module's simulated forearm, in-process) run by
// the device module's DeviceLink on its own thread. Each good sensor packet is calibrated (counts
// → SI, once, at the edge) and queued for the control loop, which fuses it (SR-UKF in
// ArmTracker); the link answers with the latest motor levels the control loop published.
// The link answers each sensor packet with the motor levels whose time has come on the control
// step's timeline (Link/LevelSchedule.h): all-off when the control steps stop for 25 ms, and an
// all-off packet when the link stops (disconnect, shutdown).
// A real port is claimed through PortRegistry first, so two instances never fight over it.
// Raw packets also go to the guided calibration (procedures::DeviceCalibration) while one runs, and a new
// calibration reaches the running link through a seqlock: no reconnect, no lock on the link thread.
#include "Core/Types.h"
#include "Link/Calibration.h"
#include "Link/LevelSchedule.h"
#include "Procedures/DeviceCalibration.h"
#include "Live/Step/LiveInput.h"
#include "Live/Sources/PortRegistry.h"
#include "Live/Sources/SourceRegistry.h"
#include "Tactile/TactileEngine.h"
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace armadillo::live {

class DeviceConnection {
public:
    /// The port name that selects the device module's simulated forearm (full protocol, no hardware).
    static constexpr const char* kSimulatedPort = "simulated forearm (in-process)";
    /// SCHED_FIFO priority the link thread asks for (below JACK's usual audio priorities).
    static constexpr int kLinkPriority = 20;

    /// `motors`: the control steps' stamped levels; this connection's link thread is its consumer.
    /// `slot`: where the instrument keeps this forearm's source (Instrument.h).
    DeviceConnection(LiveInput& input, link::LevelSchedule& motors, ArmSourceSlot& slot);
    ~DeviceConnection();

    /// Message thread. Returns false with `message` saying why (port owned elsewhere, cannot open…).
    bool connect(const std::string& port, int baud, const std::string& calibrationFile, std::string& message);
    void disconnect();
    bool isOpen() const noexcept { return link_ != nullptr; }
    /// Link statistics for the UI (message thread).
    std::string status() const;
    /// Good sensor packets the link has received since connect() (0 when not open).
    std::uint64_t packetsReceived() const noexcept;
    /// Tests and diagnostics: from the next connect() on, every motor packet the link writes is
    /// logged (time on the monotonic clock, levels); `popSent` drains it (one consumer thread).
    void enableSentLog(bool on) noexcept { sentLog_ = on; }
    bool popSent(double& t, core::MotorLevels& levels) noexcept;
    /// Packets the sent log could not keep (it was not drained in time).
    std::uint64_t sentDropped() const noexcept;

    /// Message thread: the calibration the link applies (or will apply, just after this call).
    const link::Calibration& calibration() const noexcept { return calibration_; }
    /// Message thread: the link uses `calibration` from its next packet on; `note` says where it
    /// came from in status() ("guided calibration", "calibration my-board.json").
    void applyCalibration(const link::Calibration& calibration, const std::string& note);
    const std::string& calibrationNote() const noexcept { return calibrationNote_; }
    /// Each connect / applyCalibration publishes a new calibration generation; the link thread
    /// takes it up at its next packet. Once calibrationInUse() == calibrationPublished(), every
    /// sample queued from then on was converted with the latest calibration (tests rely on it).
    std::uint64_t calibrationPublished() const noexcept { return requestedGeneration_; }
    std::uint64_t calibrationInUse() const noexcept { return linkGeneration_.load(std::memory_order_acquire); }
    /// The guided calibration fed from this link's raw packets (message thread except offer()).
    procedures::DeviceCalibration& calibrationSession() noexcept { return calibrationSession_; }
    const procedures::DeviceCalibration& calibrationSession() const noexcept { return calibrationSession_; }

private:
    /// Calibration as plain numbers for the seqlock (Eigen and std::string are not trivially copyable).
    struct CalibrationNumbers {
        double sensor[3][15] {};   ///< accel, gyro, mag: bias[3] (counts), scale[3] (SI/count), cross[9] row-major
    };
    static CalibrationNumbers toNumbers(const link::Calibration& c) noexcept;
    static void fromNumbers(const CalibrationNumbers& n, link::Calibration& c) noexcept;
    void publishCalibration() noexcept;

    LiveInput& input_;
    link::LevelSchedule& motors_;
    bool sentLog_ = false;
    double linkEpoch_ = 0.0;                   // monotonic s at the link's start (its clock's 0)
    link::Calibration calibration_;          // message thread's copy
    std::string calibrationNote_;
    // Message thread → link thread: the calibration to use and its generation number.
    core::SeqLock<CalibrationNumbers> pendingCalibration_;
    std::atomic<std::uint64_t> pendingGeneration_ {0};
    std::uint64_t requestedGeneration_ = 0;    // message thread
    link::Calibration linkCalibration_;      // link thread only (while the link runs)
    // The last word on the packet timeline (link thread only, prepared by connect()): a safety
    // stage charged with the real time between the packets the link writes, so a link that turns
    // slow (a loaded machine, a slow port) cannot hold a level longer than the budget allows.
    tactile::SafetyStage packetSafety_;
    double lastPacketAt_ = -1.0;               // link thread: monotonic s of the previous packet
    std::uint64_t linkSeen_ = 0;               // link thread only
    std::atomic<std::uint64_t> linkGeneration_ {0};
    procedures::DeviceCalibration calibrationSession_;
    std::unique_ptr<PortClaim> claim_;
    ArmSourceSlot& source_;                  // the forearm, opened through the registry into the instrument's slot
    link::DeviceLink* link_ = nullptr;       // source_'s link (null when not open)
};

} // namespace armadillo::live
