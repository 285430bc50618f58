#pragma once
// OSC sensor input, after the codec and before fusion: detects the sender's dialect, keeps to one
// device, converts units (OscDialects), turns the sensor's axes into the forearm's (Mount), and
// merges sensors that arrive in separate messages at different rates into IMU samples with
// honest timing: each sample carries its bundle's time tag (mapped onto the receiver's clock)
// or, for "immediately" / bare messages, its arrival time on the monotonic clock — never a
// synthetic fixed-rate clock, so a dropout is visible to the filter as a gap.
//
// Bad input is counted by kind and never reaches the orientation: wrong type tags, NaN/∞,
// absurd magnitudes, malformed or too deeply nested bundles, time going backwards, a second
// device or dialect interleaved, floods beyond 3× the stream's own rate.
//
// Thread rules: everything runs on the receiver thread; stats()/format()/deviceName() may be read
// from any thread (atomics, a tiny spin lock for the name). No allocation after construction.
#include "Core/SpscQueue.h"
#include "Core/Types.h"
#include "Link/Mount.h"
#include "Osc/Osc.h"
#include "Osc/OscDialects.h"
#include <atomic>
#include <cstdint>
#include <string>

namespace armadillo::osc {

struct OscInputOptions {
    OscFormat format = OscFormat::Auto;   ///< Auto = detect from the first recognised message
    bool mountGiven = false;              ///< false: the detected format's usual preset (phones: phone-screen-up)
    link::Mount mount {};                 ///< sensor axes → device frame when mountGiven
    double accelHoldSeconds = 0.25;       ///< s: an accelerometer reading this old still completes a gyro sample
    double magHoldSeconds = 0.5;          ///< s: older magnetometer/compass readings are dropped (6-axis instead)
    double gyroActiveSeconds = 0.5;       ///< s: a gyro stream this recent makes the sender's quaternion redundant
    double deviceTimeoutSeconds = 2.0;    ///< s: the chosen device silent this long lets another take over
    double floodFactor = 3.0;             ///< samples beyond this × the stream's measured rate are dropped
    double tiltLowPassSeconds = 0.05;     ///< s: accelerometer-only senders: low-pass of the gravity direction
    double restPeriodSeconds = 0.02;      ///< s: Sensors2OSC at rest (nothing changed, nothing sent): one held sample per this
    /// > 0: the receiving thread asks for SCHED_FIFO at this priority (falls back silently), as the
    /// device link's thread does: a sample's arrival stamp is where the plugin places its control
    /// step (issue 36), so a receiver that waits behind other work adds its wait to the jitter.
    int realtimePriority = 0;
    double warmupSeconds = 0.3;           ///< s: a new stream's first readings only show which sensors it sends (a
                                          ///< first sample without the compass that follows it would start the
                                          ///< filter without heading); not for ARMadillo's own messages
};

/// Samples per second let through before a stream's own rate is measured (its first second):
/// above the fastest OSC sensors (NGIMU, phones: up to ~1 kHz), so only floods are cut.
inline constexpr double kOscFloodCeilingHz = 2000.0;

struct OscInputStats {
    std::uint64_t datagrams = 0;
    std::uint64_t imu = 0;            ///< IMU samples delivered
    std::uint64_t orientation = 0;    ///< orientations delivered (sender's quaternion, or tilt from an accelerometer alone)
    std::uint64_t bad = 0;            ///< refused: malformed + tooDeep + wrongTypes + nonFinite + absurd
    std::uint64_t ignored = 0;        ///< addresses nobody uses (other apps, battery, touch, …)
    std::uint64_t malformed = 0;      ///< datagrams that are not OSC 1.0
    std::uint64_t tooDeep = 0;        ///< bundles nested deeper than kOscMaxBundleDepth
    std::uint64_t wrongTypes = 0;     ///< a known address with the wrong argument count or types
    std::uint64_t nonFinite = 0;      ///< NaN or infinity
    std::uint64_t absurd = 0;         ///< magnitudes no arm makes
    std::uint64_t outOfOrder = 0;     ///< time not increasing (late or duplicated bundles)
    std::uint64_t otherFormat = 0;    ///< another dialect's sensor messages after one was chosen
    std::uint64_t otherDevice = 0;    ///< another device's messages while the chosen one is live
    std::uint64_t deviceSwitches = 0; ///< the chosen device went silent and another took over
    std::uint64_t flood = 0;          ///< samples dropped for arriving faster than floodFactor × the stream's rate
    std::uint64_t incomplete = 0;     ///< gyro readings without a recent accelerometer (no sample made)
    std::uint64_t unusedOrientation = 0;   ///< sender quaternions not used because its gyro stream is fused instead
    std::uint64_t clockResets = 0;    ///< the sender's time tags jumped (> 1 s against arrival): re-anchored
    std::uint64_t tiltOnly = 0;       ///< of `orientation`: tilt from an accelerometer alone (no heading)
    std::uint64_t synthesizedField = 0;    ///< samples whose magnetometer comes from a compass heading (one per compass reading)
    std::uint64_t json = 0;           ///< datagrams (or stream objects) that were ZIG SIM JSON
    std::uint64_t unchanged = 0;      ///< samples made while a Sensors2OSC sender at rest sent nothing (unchanged readings)
};

/// What each sensor stream of the chosen device measured: rates in Hz (0 = not seen).
struct OscSensorRates {
    double gyro = 0.0, accel = 0.0, gravity = 0.0, userAccel = 0.0, mag = 0.0, heading = 0.0, imu = 0.0, orientation = 0.0;
    /// The rate the fusion gets (gyroscope or whole-IMU messages; the orientation for quaternion-only senders).
    double fusion() const noexcept;
};

/// What arrived that was not used (for "nothing arrives" diagnostics): the first few distinct
/// OSC addresses no dialect claimed, the first bytes of datagrams that were neither OSC nor
/// JSON, and the senders heard.
struct OscHeard {
    static constexpr int kSlots = 4;
    char addresses[kSlots][48] {};
    std::uint64_t addressCount[kSlots] {};
    char junk[kSlots][24] {};           ///< hex of the first bytes
    char senders[kSlots][64] {};
    std::uint64_t senderCount[kSlots] {};
};
/// One line in words: "OSC addresses /foo (12), …; not OSC or JSON: 48 65 …; senders: 10.0.0.2:5000 (3)".
std::string describeHeard(const OscHeard& h);

/// The app setting to change when `rate` Hz is too slow for `format` ("" when fine).
std::string lowRateAdvice(OscFormat format, double rate);

/// {"format":"ngimu","device":"…","malformed":…,…} (no braces around: the caller nests it).
std::string oscStatsJson(const OscInputStats& s, const char* format, const std::string& device);

/// One sensor-frame sample for the mount calibration (before the mount).
struct SensorFrameSample {
    double t = 0.0;
    double accel[3] {};   ///< m/s², specific force, sensor axes
    double gyro[3] {};    ///< rad/s, sensor axes (NaN when the sender has none)
};

class OscSampleMerger {
public:
    using ImuSink = void (*)(void* context, const core::ImuSample& sample);
    using OrientationSink = void (*)(void* context, double t, const Eigen::Quaterniond& q);

    explicit OscSampleMerger(const OscInputOptions& options = {});
    void setSinks(ImuSink imu, OrientationSink orientation, void* context) noexcept;

    /// One datagram: decodes it and dispatches what it holds. `arrival` = monotonic seconds;
    /// `senderKey` identifies the sender (address and port; 0 = unknown); `senderName` its text.
    void handleDatagram(const std::uint8_t* data, std::size_t size, double arrival, std::uint64_t senderKey, const char* senderName) noexcept;
    /// One decoded message (public for tests).
    void handleMessage(const OscMessage& m, double arrival, std::uint64_t senderKey, const char* senderName) noexcept;
    /// One ZIG SIM JSON object (ServiceManager.getJSON): a datagram starting with '{', or one
    /// object cut from a TCP stream. Allocates (the JSON reader): receiver thread only.
    void handleJson(const std::uint8_t* data, std::size_t size, double arrival, std::uint64_t senderKey, const char* senderName) noexcept;
    /// Called by the receiver between datagrams (at least every 20 ms) with the arrival clock:
    /// a Sensors2OSC sender at rest sends nothing (its unchanged-value filter), so its held
    /// readings are sampled here; a sender that was moving and went silent is a gap (nothing made).
    void tick(double now) noexcept;

    OscInputStats stats() const noexcept;
    OscFormat format() const noexcept { return format_.load(std::memory_order_acquire); }
    std::string deviceName() const;
    /// The latest other device whose messages were ignored while the chosen one streamed (its
    /// own name or its address:port), "" when none: who else tried (docs/SECURITY.md).
    std::string otherDeviceName() const;
    /// The reason the latest message was refused (a static string), or "".
    const char* lastError() const noexcept;
    /// The mount in use (after detection when none was given).
    link::Mount mount() const;
    /// Measured rate of each sensor stream of the chosen device.
    OscSensorRates rates() const noexcept;
    /// What arrived and was not used (any thread; a copy under the name lock).
    OscHeard heard() const;

    /// Sensor-frame samples for the mount calibration: enable, then pop from one other thread.
    void enableSensorTap(bool on) noexcept { tapOn_.store(on, std::memory_order_release); }
    bool popSensorSample(SensorFrameSample& out) noexcept { return tap_.pop(out); }

private:
    struct Held {
        Eigen::Vector3d v {0, 0, 0};
        double t = -1e300;
        bool fresh(double now, double hold) const noexcept { return now - t <= hold && now >= t - 1e-9; }
    };
    double timeOf(const OscMessage& m, double arrival) noexcept;
    double senderTime(double senderSeconds, double arrival) noexcept;
    bool acceptDevice(const SensorReading& r, double arrival, std::uint64_t senderKey, const char* senderName) noexcept;
    void lockFormat(OscFormat f) noexcept;
    void onReading(const SensorReading& r, double t) noexcept;
    void emitImu(double t, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, const Eigen::Vector3d& mag) noexcept;
    void emitOrientation(double t, const Eigen::Quaterniond& q, bool tilt) noexcept;
    bool admit(double t) noexcept;   // monotonic time and flood limit for delivered samples
    void refuse(DecodeStatus s, const char* why) noexcept;
    void resetStreams() noexcept;
    Eigen::Vector3d fieldFromHeading(const Eigen::Vector3d& up) const noexcept;
    void noteRate(int stream, double t) noexcept;
    void noteAddress(std::string_view address) noexcept;
    void noteJunk(const std::uint8_t* data, std::size_t size) noexcept;
    void noteSender(const char* name) noexcept;
    bool holdsUnchanged() const noexcept;

    OscInputOptions options_;
    ImuSink imuSink_ = nullptr;
    OrientationSink orientationSink_ = nullptr;
    void* context_ = nullptr;
    std::atomic<OscFormat> format_ {OscFormat::Auto};
    Eigen::Quaterniond mountQ_ = Eigen::Quaterniond::Identity();
    std::string mountName_;

    // Device choice.
    std::uint64_t deviceKey_ = 0;
    double deviceLastArrival_ = -1e300;
    mutable std::atomic<bool> nameLock_ {false};
    char deviceName_[64] {};
    char otherDeviceName_[64] {};   // under nameLock_

    // Time tags → receiver clock.
    bool haveOffset_ = false;
    double tagOffset_ = 0.0;

    // Latest readings, device frame.
    Held gyro_, accel_, gravity_, user_, mag_, heading_;
    Eigen::Vector3d headingAxis_ {0, 1, 0};
    bool headingNormal_ = false;
    bool gyroSeen_ = false;               // a gyroscope message arrived (Sensors2OSC: else its readings are all zero)
    Eigen::Vector3d lastGyroRaw_ {0, 0, 0};
    double lastArrival_ = -1e300;         // any message of the chosen device
    double lastMade_ = -1e300;            // the latest sample made (message or held)
    double headingDeg_ = 0.0;
    double headingUsedT_ = -1e300;        // the compass reading already made into a field (each is used once)
    double firstAccelT_ = -1.0;
    double streamStart_ = -1.0;
    Eigen::Vector3d tiltUp_ {0, 0, 0};
    double tiltT_ = -1.0;

    // Delivery: monotonic times and the flood limit.
    double lastOut_ = -1e300;
    double windowStart_ = -1.0;
    int windowCount_ = 0;
    bool windowLimited_ = false;
    double rateEstimate_ = 0.0;
    double tokens_ = 0.0;
    double tokensT_ = -1.0;

    // Per-stream rates: an average interval per stream (gyro, accel, gravity, user, mag, heading, imu, orientation).
    static constexpr int kStreams = 8;
    double streamLast_[kStreams] {};
    std::atomic<double> streamInterval_[kStreams] {};
    OscHeard heard_ {};   // under nameLock_

    std::atomic<const char*> lastError_ {nullptr};
    struct Counters {
        std::atomic<std::uint64_t> datagrams {0}, imu {0}, orientation {0}, ignored {0}, malformed {0}, tooDeep {0}, wrongTypes {0},
            nonFinite {0}, absurd {0}, outOfOrder {0}, otherFormat {0}, otherDevice {0}, deviceSwitches {0}, flood {0}, incomplete {0},
            unusedOrientation {0}, clockResets {0}, tiltOnly {0}, synthesizedField {0}, json {0}, unchanged {0};
    } n_;
    std::atomic<bool> tapOn_ {false};
    core::SpscQueue<SensorFrameSample, 1024> tap_;
};

} // namespace armadillo::osc
