#pragma once
// The host side of the thesis link (thesis §2.5.3), transport-agnostic and clock-free: every
// call carries the time `now` (s, any monotonic origin), so tests drive it with a fake clock.
//
// Lock-step: each sensor packet that arrives with the end nibble 0x0 is handed to the owner,
// whose motor levels go back at once as one motor packet. The host keeps the two in step:
// a sensor packet whose end nibble is not 0x0, or 10 ms without a byte from the device while a
// packet is due, puts the link into resync: the host waits for the line to go quiet, then
// sends all-off motor packets `00 00 00 00 08` until the device answers with a sensor packet: a
// device still in step reads "all motors off" (so a resync can never drive a motor), one out of
// step skips the 0x00 bytes and syncs on the 0x08 (thesis §2.5.3). Bursts are exactly one
// motor packet's length (5 bytes), repeated no faster than twice the measured round trip, so
// that resync bytes still in flight when the device answers can never form a phantom motor
// packet (which would leave two exchanges in flight for good on a slow or paced link). A device that never answers
// is reported (reopenDue) so the transport can reconnect: the host is the one that reconnects.
#include "Link/FramingV2.h"
#include "Link/Packets.h"
#include "Core/GapDetector.h"
#include "Core/Types.h"
#include <cstdint>

namespace armadillo::link {

struct LinkConfig {
    double silenceTimeout = 0.010;       ///< s without a byte while a packet is due ⇒ resync (thesis: 10 ms)
    /// Stretch the silence rule to 1.5 × the measured round trip + 2 ms on slow links (Bluetooth:
    /// 30–50 ms turnaround), where a fixed 10 ms would fire on every exchange. On a 57 600-baud
    /// wire (≈ 3.3 ms round trip) it stays exactly silenceTimeout.
    bool adaptiveSilence = true;
    double resyncQuiet = 0.002;          ///< s of line silence before resync bytes are sent (drops stale bytes)
    double resyncRepeat = 0.050;         ///< s: first wait before repeating an unanswered resync burst (also ≥ 2 × round trip)
    double resyncRepeatMax = 0.4;        ///< s: the wait doubles per unanswered burst up to this
    double reopenAfter = 2.0;            ///< s in resync without an answer ⇒ ask for a reconnect; ≤ 0: never
    /// Offer the v2 framing (docs/DEVICE.md §2b) on every reset: the query goes out before the first
    /// resync burst; a v2 board's offer switches the link to v2, a v1 answer (or none within
    /// v2AnswerTimeout) leaves it on v1 exactly as without the option.
    bool negotiateV2 = false;
    double v2AnswerTimeout = 0.25;       ///< s after the query without a complete answer ⇒ v1
};

/// Counters of one link. packets = good sensor packets; badPackets = frames with a wrong end
/// nibble; resyncs = times the link fell out of step after having been in step; silences = 10 ms
/// timeouts; reconnects = transport reopened after a loss (counted by the transport runner).
struct LinkStats {
    std::uint64_t packets = 0;
    std::uint64_t badPackets = 0;
    std::uint64_t resyncs = 0;
    std::uint64_t silences = 0;
    std::uint64_t reconnects = 0;
    std::uint64_t bytesIn = 0;
    std::uint64_t bytesOut = 0;
    std::uint64_t discardedBytes = 0;    ///< bytes dropped while resynchronising
    double rateHz = 0.0;                 ///< recent packet rate (1 s exponential average)
    double roundTripSeconds = 0.0;       ///< motor packet sent → next sensor packet's first byte (average)
    double firstPacketTime = -1.0;       ///< s, `now` of the first good packet; −1 before
    double lastPacketTime = -1.0;        ///< s, `now` of the latest good packet
    std::uint64_t gaps = 0;              ///< good packets that came after a dropout (Core/GapDetector.h)
    double longestGap = 0.0;             ///< s between two good packets, the longest such dropout
    bool inSync = false;
    bool v2 = false;                     ///< the current connection runs the v2 framing
    std::uint64_t seqGaps = 0;           ///< v2: sensor frames lost between good ones (sequence numbers)
    std::uint64_t crcFailures = 0;       ///< v2: frames that failed their CRC (also counted in badPackets)
};

/// What the link needs from its owner: the reply to a packet, and a way to send bytes.
class LinkPeer {
public:
    virtual ~LinkPeer() = default;
    /// A good sensor packet arrived at `now`; return the levels of the motor packet to answer with.
    virtual core::MotorLevels onSensorPacket(const SensorCounts& counts, double now) = 0;
    /// v2: a good sensor frame (with the board's own unwrapped sample time and status). By default
    /// the same as a v1 packet.
    virtual core::MotorLevels onSensorFrameV2(const SensorFrameV2& frame, double now) { return onSensorPacket(frame.counts, now); }
    /// Send bytes to the device (motor packets, resync bytes).
    virtual void send(const std::uint8_t* bytes, std::size_t count) = 0;
};

class HostLink {
public:
    enum class State : std::uint8_t {
        Draining,     ///< out of step: discarding bytes until the line is quiet
        Resyncing,    ///< streaming 0x8 bytes, waiting for the device to answer
        Framing,      ///< in resync, collecting the answer's 14 bytes
        InStep,       ///< collecting the next sensor packet of the lock-step exchange
        Negotiating,  ///< v2 query sent (or due): the board's answer decides v2 or v1
    };

    explicit HostLink(const LinkConfig& config = {});

    /// Forget everything about the line (a new connection): the next exchange starts with a resync.
    void reset(double now);
    /// Bytes received at `now`.
    void receive(const std::uint8_t* bytes, std::size_t count, double now, LinkPeer& peer);
    /// Timers: call at least by nextDeadline().
    void poll(double now, LinkPeer& peer);
    /// The latest time poll() must be called (resync bytes, silence rule).
    double nextDeadline() const noexcept;
    /// True when the device has not answered resync for config.reopenAfter seconds.
    bool reopenDue(double now) const noexcept;
    /// The last word before the port closes (stop, shutdown): an all-off motor packet in the
    /// connection's framing (v1 `00 00 00 00 08`, v2 an all-off motor frame), whatever the state.
    void sendAllOff(double now, LinkPeer& peer);

    State state() const noexcept { return state_; }
    const LinkStats& stats() const noexcept { return stats_; }
    LinkStats& stats() noexcept { return stats_; }
    const LinkConfig& config() const noexcept { return config_; }
    /// The v2 framer (offer, its own counters); mode V1 when v2 is off or not offered.
    const FramingV2Host& framingV2() const noexcept { return v2_; }

private:
    void fallOutOfStep(double now);
    void completeFrame(double now, LinkPeer& peer);
    void receiveByte(std::uint8_t byte, double now, LinkPeer& peer);
    void receiveV2(std::uint8_t byte, double now, LinkPeer& peer);
    void goodPacket(double now);
    void sendV2(const core::MotorLevels& levels, double now, LinkPeer& peer);

    LinkConfig config_;
    State state_ = State::Draining;
    SensorPacketBytes frame_ {};
    std::size_t fill_ = 0;
    double lastRx_ = -1e300;           ///< time of the last byte received
    double lastTx_ = -1e300;           ///< time of the last motor packet sent
    double nextResyncByte_ = 0.0;
    double outOfStepSince_ = 0.0;
    double lastAnswer_ = 0.0;          ///< last time the device sent anything useful (or reset)
    double frameStart_ = 0.0;          ///< time the current frame's first byte arrived
    double roundTrip_ = 0.0;           ///< s: motor packet sent → next packet's first byte (average)
    double repeatWait_ = 0.0;          ///< s: current wait between unanswered bursts (backs off)
    double lastBurst_ = -1e300;        ///< time the last resync burst was sent
    double silenceLimit() const noexcept;
    LinkStats stats_ {};
    FramingV2Host v2_ {};
    bool v2Active_ = false;            ///< this connection speaks v2
    bool queryDue_ = false;            ///< Negotiating: the query has not been sent yet
    double negotiateDeadline_ = 0.0;
    std::vector<SensorFrameV2> v2Frames_;
    std::vector<std::uint8_t> v2Out_;
    core::GapDetector gapDetector_ {}; ///< packet arrival steps; survives reset() (a reconnect is a gap too)
};

} // namespace armadillo::link
