#include "Device/HostLink.h"
#include <algorithm>
#include <cmath>

namespace armadillo::device {

HostLink::HostLink(const LinkConfig& config) : config_(config)
{
    reset(0.0);
}

void HostLink::reset(double now)
{
    state_ = State::Draining;
    fill_ = 0;
    lastRx_ = -1e300;
    lastTx_ = -1e300;
    nextResyncByte_ = now;
    outOfStepSince_ = now;
    lastAnswer_ = now;
    stats_.inSync = false;
    stats_.rateHz = 0.0;
}

void HostLink::fallOutOfStep(double now)
{
    if (stats_.inSync) ++stats_.resyncs;
    stats_.inSync = false;
    stats_.discardedBytes += fill_;
    fill_ = 0;
    state_ = State::Draining;
    outOfStepSince_ = now;
}

void HostLink::sendByte(std::uint8_t b, LinkPeer& peer)
{
    peer.send(&b, 1);
    ++stats_.bytesOut;
}

void HostLink::completeFrame(double now, LinkPeer& peer)
{
    fill_ = 0;
    SensorCounts counts {};
    if (!decodeSensorPacket(frame_.data(), counts)) {
        ++stats_.badPackets;
        stats_.discardedBytes += kSensorPacketSize;
        fallOutOfStep(now);
        return;
    }
    // A good packet: in step (again).
    ++stats_.packets;
    if (stats_.firstPacketTime < 0.0) stats_.firstPacketTime = now;
    if (stats_.lastPacketTime >= 0.0) {
        const double dt = std::max(now - stats_.lastPacketTime, 1e-6);
        const double alpha = 1.0 - std::exp(-dt / 1.0);   // 1 s time constant
        stats_.rateHz += alpha * (1.0 / dt - stats_.rateHz);
    }
    stats_.lastPacketTime = now;
    stats_.inSync = true;
    state_ = State::InStep;
    lastAnswer_ = now;

    const MotorLevels levels = peer.onSensorPacket(counts, now);
    const MotorPacketBytes out = encodeMotorPacket(levels);
    peer.send(out.data(), out.size());
    stats_.bytesOut += out.size();
    lastTx_ = now;
}

void HostLink::receive(const std::uint8_t* bytes, std::size_t count, double now, LinkPeer& peer)
{
    stats_.bytesIn += count;
    for (std::size_t i = 0; i < count; ++i) {
        switch (state_) {
        case State::Draining:
            ++stats_.discardedBytes;   // stale: part of a packet we lost the start of
            break;
        case State::Resyncing:
            state_ = State::Framing;   // the device answers: stop streaming, frame its packet
            [[fallthrough]];
        case State::Framing:
        case State::InStep:
            frame_[fill_++] = bytes[i];
            if (fill_ == kSensorPacketSize) completeFrame(now, peer);
            break;
        }
        lastRx_ = now;
    }
}

void HostLink::poll(double now, LinkPeer& peer)
{
    switch (state_) {
    case State::InStep:
    case State::Framing: {
        // Thesis rule: 10 ms without a byte from the device while a packet is due ⇒ resync.
        const double since = std::max(lastRx_, lastTx_);
        if (now - since >= config_.silenceTimeout) {
            ++stats_.silences;
            fallOutOfStep(now);
            if (now - lastRx_ >= config_.resyncQuiet) {
                state_ = State::Resyncing;
                nextResyncByte_ = now;
            }
        }
        break;
    }
    case State::Draining:
        if (now - lastRx_ >= config_.resyncQuiet) {
            state_ = State::Resyncing;
            nextResyncByte_ = now;
        }
        break;
    case State::Resyncing:
        break;
    }
    if (state_ == State::Resyncing) {
        // A device that waits for 0x8 answers the first byte; one mid-way through a motor
        // packet needs at most five. Catch up at most five bytes after a late poll.
        int sent = 0;
        while (nextResyncByte_ <= now && sent < static_cast<int>(kMotorPacketSize)) {
            sendByte(kResyncByte, peer);
            nextResyncByte_ += config_.resyncByteInterval;
            ++sent;
        }
        if (nextResyncByte_ <= now) nextResyncByte_ = now + config_.resyncByteInterval;
    }
}

double HostLink::nextDeadline() const noexcept
{
    switch (state_) {
    case State::InStep:
    case State::Framing: return std::max(lastRx_, lastTx_) + config_.silenceTimeout;
    case State::Draining: return lastRx_ + config_.resyncQuiet;
    case State::Resyncing: return nextResyncByte_;
    }
    return 0.0;
}

bool HostLink::reopenDue(double now) const noexcept
{
    return config_.reopenAfter > 0.0 && !stats_.inSync && now - lastAnswer_ >= config_.reopenAfter;
}

} // namespace armadillo::device
