#pragma once
// A deterministic, clock-free model of the serial wire between HostLink and the device side of
// the protocol: bytes take `byteTime` each and `latency` to cross; the device stamps a sequence
// number into ax so tests know exactly which packets the host received. Faults are scripted per
// packet sequence number. No threads, no sleeps: time is a variable.
#include "Link/DeviceProtocol.h"
#include "Link/HostLink.h"
#include <algorithm>
#include <deque>
#include <functional>
#include <map>
#include <stdexcept>
#include <vector>

namespace armadillo::link::testing {

enum class WireFault { CorruptEnd, DropByte, InsertByte, Stall, CorruptMotorEnd };

class VirtualWire : public link::LinkPeer {
public:
    double t = 0.0;
    double byteTime = 10.0 / 57600.0;
    double latency = 50e-6;
    double deviceDelay = 20e-6;           ///< device turnaround
    double stallSeconds = 0.05;
    link::HostLink host;
    link::DeviceProtocol device;
    std::uint16_t seq = 0;                ///< next sequence number the device stamps
    std::vector<std::uint16_t> received;  ///< sequence numbers of the good packets the host got
    std::vector<double> receivedAt;
    std::map<std::uint16_t, WireFault> faults;   ///< fault applied to the packet with this seq
    core::MotorLevels reply {};
    std::uint64_t motorPacketsAtDevice = 0;

    explicit VirtualWire(const link::LinkConfig& cfg = {}) : host(cfg) { host.reset(0.0); }

    core::MotorLevels onSensorPacket(const link::SensorCounts& counts, double now) override
    {
        received.push_back(counts[link::kAx]);
        receivedAt.push_back(now);
        return reply;
    }
    void send(const std::uint8_t* bytes, std::size_t count) override
    {
        double when = std::max(t, hostWireFree_) + latency;
        for (std::size_t i = 0; i < count; ++i) {
            when += byteTime;
            toDevice_.push_back({when, bytes[i]});
        }
        hostWireFree_ = when - latency;
        // A corrupted motor packet end: flip the last byte's low nibble of the next motor packet.
        if (corruptNextMotor_ && count == link::kMotorPacketSize) {
            toDevice_.back().second = static_cast<std::uint8_t>(toDevice_.back().second ^ 0x01);
            corruptNextMotor_ = false;
        }
    }

    /// Runs until `until` seconds of model time.
    void runUntil(double until)
    {
        int stuck = 0;
        while (t < until) {
            const double before = t;
            double next = std::min(until, host.nextDeadline());
            if (!toDevice_.empty()) next = std::min(next, toDevice_.front().first);
            if (!toHost_.empty()) next = std::min(next, toHost_.front().first);
            t = std::max(t, next);
            while (!toDevice_.empty() && toDevice_.front().first <= t) {
                const std::uint8_t b = toDevice_.front().second;
                toDevice_.pop_front();
                const auto e = device.onByte(b);
                if (e == link::DeviceProtocol::Event::MotorPacket) ++motorPacketsAtDevice;
                if (e == link::DeviceProtocol::Event::MotorPacket || e == link::DeviceProtocol::Event::Resynced) deviceAnswer();
            }
            while (!toHost_.empty() && toHost_.front().first <= t) {
                const std::uint8_t b = toHost_.front().second;
                toHost_.pop_front();
                host.receive(&b, 1, t, *this);
            }
            host.poll(t, *this);
            // Model time must advance: a deadline that poll() does not act on would spin forever.
            stuck = t == before && toDevice_.empty() && toHost_.empty() ? stuck + 1 : 0;
            if (stuck > 1000) throw std::logic_error("virtual wire: host deadline does not advance");
        }
    }

private:
    void deviceAnswer()
    {
        link::SensorCounts c {};
        c[link::kAx] = seq;
        c[link::kAy] = 100;
        c[link::kMz] = 0x5A5;
        auto p = encodeSensorPacket(c);
        std::vector<std::uint8_t> bytes(p.begin(), p.end());
        double start = std::max(t + deviceDelay, deviceWireFree_);
        const auto f = faults.find(seq);
        ++seq;
        if (f != faults.end()) {
            switch (f->second) {
            case WireFault::CorruptEnd: bytes[13] = static_cast<std::uint8_t>(bytes[13] | 0x03); break;
            case WireFault::DropByte: bytes.erase(bytes.begin() + 5); break;
            case WireFault::InsertByte: bytes.insert(bytes.begin() + 3, 0x77); break;
            case WireFault::Stall: start += stallSeconds; break;
            case WireFault::CorruptMotorEnd: corruptNextMotor_ = true; break;
            }
        }
        double when = start + latency;
        for (const auto b : bytes) {
            when += byteTime;
            toHost_.push_back({when, b});
        }
        deviceWireFree_ = when - latency;
    }

    std::deque<std::pair<double, std::uint8_t>> toDevice_, toHost_;
    double hostWireFree_ = 0.0, deviceWireFree_ = 0.0;
    bool corruptNextMotor_ = false;
};

} // namespace armadillo::link::testing
