#pragma once
// The host link on its own thread: a LinkPort, the HostLink state machine and reconnection with
// backoff. Each good sensor packet is handed to the handler on the link thread (the control
// thread in live use: calibration → tracking → engine → levels) and its motor packet leaves at
// once. Stats, the connection state and the raw packets cross to other threads lock-free
// (SeqLock, atomics, SpscQueue).
#include "Core/SpscQueue.h"
#include "Link/HostLink.h"
#include "Link/LinkPort.h"
#include <atomic>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace armadillo::link {

/// One sensor packet as it arrived: t in s since the link started.
struct RawPacket {
    double t = 0.0;
    SensorCounts counts {};
};

/// One motor packet as the link wrote it to the port: t in s since the link started. Resync
/// packets are in it too (all off), so the log is exactly what reached the wire.
struct SentMotorPacket {
    double t = 0.0;
    ProtocolLevels levels {};
    bool resync = false;
};

struct DeviceLinkOptions {
    LinkConfig link {};
    double reconnectMin = 0.05;   ///< s: first retry after a loss
    double reconnectMax = 0.25;   ///< s: backoff cap (a returning port is found within this)
    int realtimePriority = 0;     ///< > 0: try SCHED_FIFO at this priority for the link thread (falls back silently)
};


/// Sensor-packet arrival → motor-packet written, measured on the link thread.
struct LatencySummary {
    std::uint64_t count = 0;
    double meanUs = 0.0, p50Us = 0.0, p99Us = 0.0, maxUs = 0.0;
};

class DeviceLink final : private LinkPeer {
public:
    /// Runs on the link thread for every good packet; returns the next motor levels. In v2
    /// (LinkConfig::negotiateV2 and a board that offers it) `t` advances with the board's own
    /// sample clock (anchored on the link's clock at the connection's first frame), so dropouts
    /// show as the board measured them.
    using Handler = std::function<core::MotorLevels(const SensorCounts& counts, double t)>;

    DeviceLink(std::unique_ptr<LinkPort> port, Handler handler, const DeviceLinkOptions& options = {});
    ~DeviceLink() override;
    DeviceLink(const DeviceLink&) = delete;
    DeviceLink& operator=(const DeviceLink&) = delete;

    void start();
    /// Stops the thread and closes the port (no motor packet is sent after this returns).
    void stop();
    bool running() const noexcept { return thread_.joinable(); }

    LinkStats stats() const noexcept { return stats_.load(); }
    bool connected() const noexcept { return connected_.load(std::memory_order_acquire); }
    /// The latest transport error ("" when none) — for messages, not for control flow.
    std::string lastError() const;
    std::string portName() const { return port_->name(); }
    std::string backend() const;
    /// Seconds since start() on the link's clock.
    double now() const noexcept;

    /// Waits (event-driven) until pred(stats) holds or the timeout passes; returns pred's value.
    bool waitFor(const std::function<bool(const LinkStats&)>& pred, double timeoutSeconds) const;

    /// Every good packet, for one consumer thread (UI, calibration, recording). Full ⇒ dropped.
    core::SpscQueue<RawPacket, 1024>& packets() noexcept { return packets_; }
    /// Every motor packet written, for one consumer thread (safety checks on what reached the
    /// wire). Off unless enabled before start(); full ⇒ dropped and counted.
    void enableSentLog() noexcept { sentLogEnabled_ = true; }
    core::SpscQueue<SentMotorPacket, 4096>& sentLog() noexcept { return sentLog_; }
    std::uint64_t sentLogDropped() const noexcept { return sentLogDropped_.load(std::memory_order_relaxed); }
    LatencySummary latency() const;
    /// The board's v2 offer (version 0 when none): read it from the handler or after stop().
    const OfferV2& v2Offer() const noexcept { return link_.framingV2().offer(); }

private:
    core::MotorLevels onSensorPacket(const SensorCounts& counts, double now) override;
    core::MotorLevels onSensorFrameV2(const SensorFrameV2& frame, double now) override;
    void send(const std::uint8_t* bytes, std::size_t count) override;
    void run();
    void publish();
    void setError(const std::string& e);
    bool sleepUnlessStopped(double seconds);

    std::unique_ptr<LinkPort> port_;
    Handler handler_;
    DeviceLinkOptions options_;
    HostLink link_;
    std::thread thread_;
    std::atomic<bool> stop_ {false};
    std::atomic<bool> connected_ {false};
    core::SeqLock<LinkStats> stats_;
    core::SpscQueue<RawPacket, 1024> packets_;
    bool sentLogEnabled_ = false;
    core::SpscQueue<SentMotorPacket, 4096> sentLog_;
    std::atomic<std::uint64_t> sentLogDropped_ {0};
    double arrival_ = 0.0;                 // link thread: when the bytes being parsed arrived
    bool wroteMotorPacket_ = false;
    // v2: the board's clock anchored on the link's at the first frame of a connection.
    bool v2Anchored_ = false;
    std::uint64_t v2AnchorUs_ = 0;
    double v2AnchorT_ = 0.0;
    double lastHandlerT_ = -1e300;
    std::chrono::steady_clock::time_point start_ {};

    static constexpr std::size_t kLatencyBins = 10000;   // 1 µs bins up to 10 ms, then overflow
    std::vector<std::atomic<std::uint32_t>> latencyHist_;
    std::atomic<std::uint64_t> latencyCount_ {0};
    std::atomic<double> latencySumUs_ {0.0};
    std::atomic<double> latencyMaxUs_ {0.0};

    mutable std::mutex mutex_;             // error text and the wait condition only
    mutable std::condition_variable cv_;
    mutable std::atomic<int> waiters_ {0};
    std::string lastError_;
    std::string backend_;
};

} // namespace armadillo::link
