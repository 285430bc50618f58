#include "Link/HostLink.h"
#include <algorithm>
#include <cmath>

namespace armadillo::link {

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
    v2_.fallBackToV1();
    v2Active_ = false;
    stats_.v2 = false;
    queryDue_ = config_.negotiateV2;
    if (config_.negotiateV2) state_ = State::Negotiating;
}

void HostLink::fallOutOfStep(double now)
{
    if (stats_.inSync) ++stats_.resyncs;
    stats_.inSync = false;
    stats_.discardedBytes += fill_;
    fill_ = 0;
    if (v2Active_) v2_.dropPartialFrame();   // the board's answer to the next motor frame starts afresh
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
    goodPacket(now);
    const core::MotorLevels levels = peer.onSensorPacket(counts, now);
    const MotorPacketBytes out = encodeMotorPacket(levels);
    peer.send(out.data(), out.size());
    stats_.bytesOut += out.size();
    lastTx_ = now;
}

void HostLink::goodPacket(double now)
{
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
}

void HostLink::sendV2(const core::MotorLevels& levels, double now, LinkPeer& peer)
{
    ProtocolLevels lv {};
    for (std::size_t i = 0; i < lv.size(); ++i) lv[i] = levels[i];   // clamped to 15 by the encoder
    v2Out_.clear();
    v2_.encodeMotor(lv, v2Out_);
    peer.send(v2Out_.data(), v2Out_.size());
    stats_.bytesOut += v2Out_.size();
    lastTx_ = now;
}

void HostLink::receiveV2(std::uint8_t byte, double now, LinkPeer& peer)
{
    const FramingV2Stats before = v2_.stats();
    if (fill_ == 0 && state_ != State::Draining) frameStart_ = now;
    v2Frames_.clear();
    v2_.receive(byte, v2Frames_);
    const FramingV2Stats& after = v2_.stats();
    stats_.discardedBytes += after.discardedBytes - before.discardedBytes;
    stats_.seqGaps += after.seqGaps - before.seqGaps;
    if (after.crcFailures != before.crcFailures) {
        stats_.crcFailures += after.crcFailures - before.crcFailures;
        stats_.badPackets += after.crcFailures - before.crcFailures;
    }
    // fill_ mirrors "a frame is being collected" for the silence rule's frame start.
    fill_ = (after.discardedBytes == before.discardedBytes && v2Frames_.empty()) ? fill_ + 1 : 0;
    for (const SensorFrameV2& f : v2Frames_) {
        if (state_ == State::Draining) {
            // Out of step, as in v1: a late frame is not answered (that would put a second
            // exchange in flight next to the resync frame's); its sequence number is still seen.
            stats_.discardedBytes += kV2SensorFrameSize;
            continue;
        }
        goodPacket(now);
        sendV2(peer.onSensorFrameV2(f, now), now, peer);
    }
}

void HostLink::receiveByte(std::uint8_t byte, double now, LinkPeer& peer)
{
    if (v2Active_) {
        receiveV2(byte, now, peer);
        lastRx_ = now;
        return;
    }
    switch (state_) {
    case State::Negotiating:
        lastRx_ = now;
        if (queryDue_) {   // bytes before our query: stale, the board has not heard it yet
            ++stats_.discardedBytes;
            return;
        }
        v2Frames_.clear();
        v2_.receive(byte, v2Frames_);
        if (v2_.mode() == FramingV2Host::Mode::V2) {
            // The board offers v2: the first motor frame (all off) goes out at once from poll().
            v2Active_ = true;
            stats_.v2 = true;
            fill_ = 0;
            if (roundTrip_ <= 0.0 && now > lastBurst_) roundTrip_ = stats_.roundTripSeconds = now - lastBurst_;
            state_ = State::Resyncing;
            nextResyncByte_ = now;
            repeatWait_ = 0.0;
            lastAnswer_ = now;
        } else if (v2_.mode() == FramingV2Host::Mode::V1) {
            // A v1 board answered the query's resync burst: that answer is the v1 link's first packet.
            state_ = State::Resyncing;
            if (v2_.hasV1Answer()) {
                for (std::uint8_t b : v2_.v1Answer()) receiveByte(b, now, peer);
            } else {
                stats_.discardedBytes += kSensorPacketSize;
                state_ = State::Draining;
            }
        }
        return;
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
        frame_[fill_++] = byte;
        if (fill_ == kSensorPacketSize) completeFrame(now, peer);
        break;
    }
    lastRx_ = now;
}

void HostLink::receive(const std::uint8_t* bytes, std::size_t count, double now, LinkPeer& peer)
{
    stats_.bytesIn += count;
    for (std::size_t i = 0; i < count; ++i) receiveByte(bytes[i], now, peer);
}

void HostLink::poll(double now, LinkPeer& peer)
{
    if (state_ == State::Negotiating) {
        if (queryDue_) {
            // The v2 query, with the v1 resync burst right behind it (docs/DEVICE.md §2b).
            v2Out_.clear();
            v2_.startNegotiation(v2Out_);
            peer.send(v2Out_.data(), v2Out_.size());
            stats_.bytesOut += v2Out_.size();
            queryDue_ = false;
            lastBurst_ = now;
            negotiateDeadline_ = now + config_.v2AnswerTimeout;
            return;
        }
        if (now < negotiateDeadline_) return;
        // No (complete) answer: a v1 board that missed the burst, or nobody. v1 from here on.
        v2_.fallBackToV1();
        state_ = State::Draining;
    }
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
    case State::Negotiating:
        break;
    }
    if (state_ == State::Resyncing && nextResyncByte_ <= now) {
        // A device in step reads an all-off motor packet and answers; one waiting for 0x8 skips the
        // zeros and answers the last byte; one mid-way through a motor packet completes it with
        // zeros (a bad end nibble), then waits and answers the 0x08. Exactly one answer per burst,
        // so leftovers can never make a whole phantom packet; the next burst only after the device
        // has had twice its round trip to answer.
        if (v2Active_) {
            sendV2(core::MotorLevels {}, now, peer); // v2's resync: an all-off motor frame, which the board answers
        } else {
            peer.send(kResyncPacket.data(), kResyncPacket.size());
            stats_.bytesOut += kMotorPacketSize;
        }
        lastBurst_ = now;
        repeatWait_ = repeatWait_ <= 0.0 ? std::max(config_.resyncRepeat, 2.0 * roundTrip_ + 0.002)
                                         : std::min(2.0 * repeatWait_, std::max(config_.resyncRepeatMax, config_.resyncRepeat));
        nextResyncByte_ = now + repeatWait_;
    }
}

void HostLink::sendAllOff(double now, LinkPeer& peer)
{
    // A device in step reads it as its next motor packet; one out of step reads it as a resync
    // burst and answers; either way its motors are off. The answer is not waited for.
    if (v2Active_) {
        sendV2(core::MotorLevels {}, now, peer);
    } else {
        peer.send(kResyncPacket.data(), kResyncPacket.size());
        stats_.bytesOut += kMotorPacketSize;
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
    case State::Negotiating: return queryDue_ ? -1e300 : negotiateDeadline_;
    }
    return 0.0;
}

bool HostLink::reopenDue(double now) const noexcept
{
    return config_.reopenAfter > 0.0 && !stats_.inSync && now >= lastAnswer_ + config_.reopenAfter;
}

} // namespace armadillo::link
