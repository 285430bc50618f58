#pragma once
// The simulated forearm: a device model that speaks the device side of the thesis protocol,
// with realistic 12-bit counts (thesis §2.3–2.5) and fault injection. Two ways to reach it:
// in-process (a socket pair; the app's default when no device is present) and over a
// pseudo-terminal with a stable path (tests and benchmarks exercise the real serial code).
#include "Link/Calibration.h"
#include "Link/DeviceProtocol.h"
#include "Link/LinkPort.h"
#include "Link/Motion.h"
#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <random>
#include <string>
#include <thread>

namespace armadillo::link {

/// The sensors' physics and ADC. Every field names its unit.
struct SensorModelParams {
    Calibration adc = defaultCalibration();   ///< the board's true counts ↔ SI (calibrate to recover it)
    double fieldStrength = 1.0;               ///< field units (1 = what the default calibration calls ±1)
    double dipDeg = 65.0;                     ///< magnetic dip below horizontal (Boston ≈ 69°)
    double accelNoise = 0.04;                 ///< m/s² RMS per axis
    double gyroNoise = 0.006;                 ///< rad/s RMS per axis
    double magNoise = 0.004;                  ///< field units RMS per axis
    Eigen::Vector3d gyroBiasStart {0.03, -0.02, 0.015};   ///< rad/s at power-up
    Eigen::Vector3d gyroBiasSettled {0.01, -0.005, 0.02}; ///< rad/s after warm-up
    double gyroWarmup = 30.0;                 ///< s: time constant of the warm-up drift (thesis: mostly the first minute)
    double gyroBiasWalk = 0.0005;             ///< rad/s/√s random walk of the bias
    double motorVibration = 0.012;            ///< m/s² RMS of accelerometer noise per unit motor level (summed)
    std::uint64_t seed = 7;
};

/// Counts from motion: gravity (specific force +g up), field with dip, gyro bias drift + noise,
/// linear acceleration, motor vibration on the accelerometer. Not thread-safe.
class SensorModel {
public:
    explicit SensorModel(const SensorModelParams& params = {});
    SensorCounts sample(const MotionState& motion, double t, const ProtocolLevels& motors);
    /// The physical values of the last sample (before the ADC), for tests.
    const core::ImuSample& lastTruth() const noexcept { return truth_; }
    Eigen::Vector3d gyroBias(double t) const;
    const SensorModelParams& params() const noexcept { return params_; }

private:
    SensorModelParams params_;
    std::mt19937_64 rng_;
    std::normal_distribution<double> normal_ {0.0, 1.0};
    Eigen::Vector3d walk_ = Eigen::Vector3d::Zero();
    double lastT_ = 0.0;
    core::ImuSample truth_ {};
};

/// The device without threads or clocks: bytes from the host in, sensor packets out.
class ForearmDevice {
public:
    ForearmDevice(std::shared_ptr<const MotionSource> motion, const SensorModelParams& params = {});
    /// Feeds a host byte; returns true when the device must now answer with a sensor packet.
    bool onByte(std::uint8_t byte) noexcept;
    /// The sensor packet for time t (s since power-up).
    SensorPacketBytes answer(double t);
    const DeviceProtocol& protocol() const noexcept { return protocol_; }
    DeviceProtocol& protocol() noexcept { return protocol_; }
    SensorModel& sensors() noexcept { return sensors_; }
    const SensorCounts& lastCounts() const noexcept { return lastCounts_; }

private:
    std::shared_ptr<const MotionSource> motion_;
    SensorModel sensors_;
    DeviceProtocol protocol_;
    SensorCounts lastCounts_ {};
};

/// Random faults, as probabilities per sensor packet (or per received byte for the host → device
/// direction). All zero by default.
struct FaultConfig {
    double corruptPacket = 0.0;      ///< flip random bits in one byte of the packet
    double dropByte = 0.0;           ///< drop one byte of the packet
    double insertByte = 0.0;         ///< insert one random byte into the packet
    double corruptHostByte = 0.0;    ///< per byte from the host: flip random bits
    double stall = 0.0;              ///< stop answering for stallSeconds
    double stallSeconds = 0.05;
    double disconnect = 0.0;         ///< unplug for disconnectSeconds
    double disconnectSeconds = 0.3;
};

struct SimulatorOptions {
    SensorModelParams sensors {};
    double baud = 0.0;        ///< > 0: pace both directions like an 8N1 wire at this rate; 0: as fast as possible
    FaultConfig faults {};
    std::uint64_t seed = 11;  ///< fault randomness
    /// Link-test aid: write the packet's sequence number (mod 4096) into the ax channel so a test
    /// knows exactly which packets the host received.
    bool stampSequence = false;
    int realtimePriority = 0;  ///< > 0: try SCHED_FIFO for the device thread (steadier pacing)
};

struct SimulatorStats {
    std::uint64_t packetsSent = 0;     ///< sensor packets written
    std::uint64_t motorPackets = 0;    ///< good motor packets received
    std::uint64_t badMotorPackets = 0;
    std::uint64_t resyncAnswers = 0;   ///< answers to a 0x8 byte after waiting
    std::uint64_t connections = 0;     ///< times the endpoint was (re)created
    std::uint64_t faults = 0;          ///< faults injected (scripted + random)
    ProtocolLevels levels {};          ///< latest motor levels received
    int maxLevelApplied = 0;           ///< highest level any good motor packet ever set on any motor
    std::chrono::steady_clock::time_point lastPlug {};   ///< when the endpoint last appeared
};

/// The simulated device on its own thread.
class SimulatedForearm {
public:
    explicit SimulatedForearm(std::shared_ptr<const MotionSource> motion = std::make_shared<WanderingMotion>(),
                              const SimulatorOptions& options = {});
    ~SimulatedForearm();
    SimulatedForearm(const SimulatedForearm&) = delete;
    SimulatedForearm& operator=(const SimulatedForearm&) = delete;

    /// Serve over a pseudo-terminal whose slave is reachable at `linkPath` (a symlink, replaced
    /// on every replug like a udev by-id name). Starts the thread. Throws IoError.
    void startPty(const std::string& linkPath);
    /// Serve in-process; the returned port (open() = plug in) is what the host link uses.
    std::unique_ptr<LinkPort> startInProcess();
    void stop();

    // Scripted, one-shot faults (any thread). They act on the next sensor packet.
    void corruptNextEndNibble();
    void dropNextByte();
    void insertNextByte(std::uint8_t value);
    void stallFor(double seconds);
    void disconnectFor(double seconds);

    SimulatorStats stats() const;
    /// Wakes when the simulator state changes; returns pred(stats) (event-driven, for tests).
    bool waitFor(const std::function<bool(const SimulatorStats&)>& pred, double timeoutSeconds) const;
    std::string ptyPath() const;   ///< the current /dev/pts/N, "" when unplugged
    double now() const noexcept;

private:
    class InProcessPort;
    friend class InProcessPort;
    void run();
    bool plug();
    void unplug();
    void respond(double t);
    void waitUntil(double t);
    bool sleepUnlessStopped(double seconds);
    int takeHostFd();

    SimulatorOptions options_;
    ForearmDevice device_;
    std::mt19937_64 rng_;
    std::thread thread_;
    std::atomic<bool> stop_ {false};
    std::chrono::steady_clock::time_point start_ {};
    bool pty_ = false;
    std::string linkPath_;
    int fd_ = -1;           // device side: pty master or socket
    int slaveKeep_ = -1;    // pty: a slave fd kept open so the master never sees a hang-up
    int hostFd_ = -1;       // in-process: the host's end, waiting to be taken
    double unpluggedUntil_ = 0.0;
    double wireFree_ = 0.0; // paced mode: when the device → host wire is free again

    // Scripted faults.
    std::atomic<int> corruptEnd_ {0}, dropByte_ {0}, insertByte_ {0};
    std::atomic<int> insertValue_ {0};
    std::atomic<double> stallSeconds_ {0.0}, disconnectSeconds_ {0.0};

    mutable std::mutex mutex_;
    mutable std::condition_variable cv_;
    SimulatorStats stats_;
    std::string ptyName_;
};

} // namespace armadillo::link
