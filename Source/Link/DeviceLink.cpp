#include "Link/DeviceLink.h"
#include "Core/ThreadPriority.h"
#include "Core/Errors.h"
#include <algorithm>
#include <array>
#include <cmath>
#include <pthread.h>
#include <sched.h>

namespace armadillo::link {

DeviceLink::DeviceLink(std::unique_ptr<LinkPort> port, Handler handler, const DeviceLinkOptions& options)
    : port_(std::move(port)), handler_(std::move(handler)), options_(options), link_(options.link),
      latencyHist_(kLatencyBins + 1)
{
    if (!port_) throw std::invalid_argument("DeviceLink needs a port");
    if (!handler_) handler_ = [](const SensorCounts&, double) { return core::MotorLevels {}; };
}

DeviceLink::~DeviceLink() { stop(); }

double DeviceLink::now() const noexcept
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void DeviceLink::start()
{
    if (thread_.joinable()) return;
    stop_.store(false);
    start_ = std::chrono::steady_clock::now();
    link_.reset(0.0);
    v2Anchored_ = false;
    thread_ = std::thread([this] { run(); });
}

void DeviceLink::stop()
{
    if (!thread_.joinable()) return;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_.store(true);
    }
    cv_.notify_all();
    thread_.join();
    // Motors off before the port closes: a board keeps its last levels until its own watchdog
    // (50 ms in the reference firmware, none in the thesis's), so stop, shutdown and a host that
    // removes the plugin end with an all-off packet on the wire. A broken port cannot take it.
    if (port_->isOpen()) {
        try {
            link_.sendAllOff(now(), *this);
        } catch (const std::exception& e) {
            setError(e.what());
        }
    }
    port_->close();
    connected_.store(false);
    publish();
}

std::string DeviceLink::lastError() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return lastError_;
}

std::string DeviceLink::backend() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return backend_;
}

void DeviceLink::setError(const std::string& e)
{
    std::lock_guard<std::mutex> lock(mutex_);
    lastError_ = e;
}

bool DeviceLink::sleepUnlessStopped(double seconds)
{
    std::unique_lock<std::mutex> lock(mutex_);
    return !cv_.wait_for(lock, std::chrono::duration<double>(seconds), [&] { return stop_.load(); });
}

bool DeviceLink::waitFor(const std::function<bool(const LinkStats&)>& pred, double timeoutSeconds) const
{
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                                  std::chrono::duration<double>(timeoutSeconds));
    std::unique_lock<std::mutex> lock(mutex_);
    ++waiters_;
    bool ok = false;
    for (;;) {
        ok = pred(stats_.load());
        if (ok || std::chrono::steady_clock::now() >= deadline) break;
        // The link thread notifies after every loop turn while someone waits; the timed wait only
        // bounds the case of a stopped link.
        cv_.wait_until(lock, std::min(deadline, std::chrono::steady_clock::now() + std::chrono::milliseconds(50)));
    }
    --waiters_;
    return ok;
}

void DeviceLink::publish()
{
    stats_.store(link_.stats());
    if (waiters_.load(std::memory_order_relaxed) > 0) {
        std::lock_guard<std::mutex> lock(mutex_);
        cv_.notify_all();
    }
}

core::MotorLevels DeviceLink::onSensorPacket(const SensorCounts& counts, double t)
{
    packets_.push(RawPacket {t, counts});
    wroteMotorPacket_ = true;
    lastHandlerT_ = t;
    return handler_(counts, t);
}

core::MotorLevels DeviceLink::onSensorFrameV2(const SensorFrameV2& frame, double now)
{
    if (!v2Anchored_) {
        v2Anchored_ = true;
        v2AnchorUs_ = frame.deviceTimeUs;
        v2AnchorT_ = std::max(now, lastHandlerT_ + 1e-6);
    }
    // The board's unwrapped µs clock on the link's timeline; never backwards across reconnects.
    const double t = std::max(v2AnchorT_ + static_cast<double>(frame.deviceTimeUs - v2AnchorUs_) * 1e-6, lastHandlerT_ + 1e-6);
    return onSensorPacket(frame.counts, t);
}

void DeviceLink::send(const std::uint8_t* bytes, std::size_t count)
{
    port_->write(bytes, count);
    // What a write is: a v1 motor packet (or resync burst), a v2 motor frame, or the v2 query with
    // its resync burst (logged as that burst: all off).
    const bool v1Packet = count == kMotorPacketSize;
    const bool v2Frame = count == kV2MotorFrameSize && bytes[0] == kV2MotorSync;
    const bool v2Query = count == sizeof kV2Query + kMotorPacketSize;
    if (sentLogEnabled_ && (v1Packet || v2Frame || v2Query)) {
        SentMotorPacket p;
        p.t = now();
        p.resync = !wroteMotorPacket_;
        if (v1Packet) decodeMotorPacket(bytes, p.levels);
        if (v2Frame) {
            std::uint8_t seq = 0, flags = 0;
            decodeMotorFrameV2(bytes, seq, p.levels, flags);
        }
        if (v2Query) decodeMotorPacket(bytes + sizeof kV2Query, p.levels);
        if (!sentLog_.push(p)) sentLogDropped_.fetch_add(1, std::memory_order_relaxed);
    }
    if (wroteMotorPacket_ && (v1Packet || v2Frame)) {
        wroteMotorPacket_ = false;
        const double us = (now() - arrival_) * 1e6;
        const std::size_t bin = std::min<std::size_t>(static_cast<std::size_t>(std::max(us, 0.0)), kLatencyBins);
        latencyHist_[bin].fetch_add(1, std::memory_order_relaxed);
        latencyCount_.fetch_add(1, std::memory_order_relaxed);
        latencySumUs_.store(latencySumUs_.load(std::memory_order_relaxed) + us, std::memory_order_relaxed);
        if (us > latencyMaxUs_.load(std::memory_order_relaxed)) latencyMaxUs_.store(us, std::memory_order_relaxed);
    }
}

LatencySummary DeviceLink::latency() const
{
    LatencySummary s;
    s.count = latencyCount_.load();
    if (s.count == 0) return s;
    s.meanUs = latencySumUs_.load() / static_cast<double>(s.count);
    s.maxUs = latencyMaxUs_.load();
    auto percentile = [&](double p) {
        const std::uint64_t target = static_cast<std::uint64_t>(std::ceil(p * static_cast<double>(s.count)));
        std::uint64_t acc = 0;
        for (std::size_t i = 0; i <= kLatencyBins; ++i) {
            acc += latencyHist_[i].load();
            if (acc >= target) return static_cast<double>(i) + 1.0;   // upper edge of the 1 µs bin
        }
        return s.maxUs;
    };
    s.p50Us = percentile(0.5);
    s.p99Us = percentile(0.99);
    return s;
}

void DeviceLink::run()
{
    core::requestRealtimePriority(options_.realtimePriority);
    std::array<std::uint8_t, 512> buffer {};
    // A port the owner opened before start() (to fail early with its own message) is a connection
    // like any other: losing it and opening it again is a reconnect.
    bool everConnected = false;
    if (port_->isOpen()) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            backend_ = port_->backend();
        }
        everConnected = true;
        connected_.store(true, std::memory_order_release);
        publish();
    }
    double backoff = options_.reconnectMin;
    while (!stop_.load(std::memory_order_relaxed)) {
        if (!port_->isOpen()) {
            try {
                port_->open();
                {
                    std::lock_guard<std::mutex> lock(mutex_);
                    backend_ = port_->backend();
                    lastError_.clear();
                }
                if (everConnected) ++link_.stats().reconnects;
                everConnected = true;
                backoff = options_.reconnectMin;
                link_.reset(now());
                v2Anchored_ = false;
                connected_.store(true, std::memory_order_release);
                publish();
            } catch (const std::exception& e) {
                setError(e.what());
                publish();
                if (!sleepUnlessStopped(backoff)) break;
                backoff = std::min(backoff * 2.0, options_.reconnectMax);
                continue;
            }
        }
        try {
            const double timeout = std::clamp(link_.nextDeadline() - now(), 0.0, 0.05);
            const std::size_t n = port_->read(buffer.data(), buffer.size(), timeout);
            if (n > 0) {
                arrival_ = now();
                link_.receive(buffer.data(), n, arrival_, *this);
            }
            const double t = now();
            link_.poll(t, *this);
            if (link_.reopenDue(t)) {
                setError("the device on " + port_->name() + " does not answer; reopening the port");
                port_->close();
                connected_.store(false, std::memory_order_release);
                link_.stats().inSync = false;
            }
        } catch (const core::IoError& e) {
            setError(e.what());
            port_->close();
            connected_.store(false, std::memory_order_release);
            link_.stats().inSync = false;
        }
        publish();
    }
}

} // namespace armadillo::link
