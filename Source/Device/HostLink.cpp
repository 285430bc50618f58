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
    repeatWait_ = 0.0;
}

void HostLink::fallOutOfStep(double now)
{
    if (stats_.inSync) ++stats_.resyncs;
    stats_.inSync = false;
    stats_.discardedBytes += fill_;
    fill_ = 0;
    state_ = State::Draining;
    outOfStepSince_ = now;
    repeatWait_ = 0.0;
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
        if (gapDetector_.step(dt)) {
            stats_.gaps = gapDetector_.count();
            stats_.longestGap = gapDetector_.longest();
        }
        const double alpha = 1.0 - std::exp(-dt / 1.0);   // 1 s time constant
        stats_.rateHz += alpha * (1.0 / dt - stats_.rateHz);
    }
    stats_.lastPacketTime = now;
    if (state_ == State::InStep && frameStart_ >= lastTx_) {
        // Lock-step round trip: how long the device takes to answer a motor packet.
        const double rtt = frameStart_ - lastTx_;
        roundTrip_ = roundTrip_ > 0.0 ? roundTrip_ + 0.05 * (rtt - roundTrip_) : rtt;
        stats_.roundTripSeconds = roundTrip_;
    }
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
            // The first answer also tells how slow the link is (seeds the round trip).
            if (roundTrip_ <= 0.0 && now > lastBurst_) {
                roundTrip_ = now - lastBurst_;
                stats_.roundTripSeconds = roundTrip_;
            }
            [[fallthrough]];
        case State::Framing:
        case State::InStep:
            if (fill_ == 0) frameStart_ = now;
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
        // Deadlines and checks use the same expressions, so a poll at nextDeadline() always acts.
        const double since = std::max(lastRx_, lastTx_);
        if (now >= since + silenceLimit()) {
            ++stats_.silences;
            fallOutOfStep(now);
            if (now >= lastRx_ + config_.resyncQuiet) {
                state_ = State::Resyncing;
                nextResyncByte_ = now;
            }
        }
        break;
    }
    case State::Draining:
        if (now >= lastRx_ + config_.resyncQuiet) {
            state_ = State::Resyncing;
            nextResyncByte_ = now;
        }
        break;
    case State::Resyncing:
        break;
    }
    if (state_ == State::Resyncing && nextResyncByte_ <= now) {
        // A device in step reads an all-off motor packet and answers; one waiting for 0x8 skips the
        // zeros and answers the last byte; one mid-way through a motor packet completes it with
        // zeros (a bad end nibble), then waits and answers the 0x08. Exactly one answer per burst,
        // so leftovers can never make a whole phantom packet; the next burst only after the device
        // has had twice its round trip to answer.
        peer.send(kResyncPacket.data(), kResyncPacket.size());
        lastBurst_ = now;
        stats_.bytesOut += kMotorPacketSize;
        repeatWait_ = repeatWait_ <= 0.0 ? std::max(config_.resyncRepeat, 2.0 * roundTrip_ + 0.002)
                                         : std::min(2.0 * repeatWait_, std::max(config_.resyncRepeatMax, config_.resyncRepeat));
        nextResyncByte_ = now + repeatWait_;
    }
}

double HostLink::silenceLimit() const noexcept
{
    return config_.adaptiveSilence ? std::max(config_.silenceTimeout, 1.5 * roundTrip_ + 0.002) : config_.silenceTimeout;
}

double HostLink::nextDeadline() const noexcept
{
    switch (state_) {
    case State::InStep:
    case State::Framing: return std::max(lastRx_, lastTx_) + silenceLimit();
    case State::Draining: return lastRx_ + config_.resyncQuiet;
    case State::Resyncing: return nextResyncByte_;
    }
    return 0.0;
}

bool HostLink::reopenDue(double now) const noexcept
{
    return config_.reopenAfter > 0.0 && !stats_.inSync && now >= lastAnswer_ + config_.reopenAfter;
}

} // namespace armadillo::device
