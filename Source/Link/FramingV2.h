#pragma once
// The optional v2 framing of the link (docs/DEVICE.md "v2 framing"), host side: negotiation with a
// board that offers it, CRC-16 checked and sequence-numbered frames carrying the board's own sample
// time, and the fallback to the thesis protocol v1 for boards that do not answer the offer.
// Clock-free and transport-free like HostLink: bytes in, frames out; the owner owns time.
//
// Wire format (byte values; CRC = CRC-16/CCITT-FALSE, big-endian, over every byte before it):
//   query    host → board   41 52 4D 76 32 ("ARMv2"), then the v1 resync burst 00 00 00 00 08
//   offer    board → host   41 52 4D 76 32 | ver=02 | motors | rate Hz (2) | 00 00 | CRC (2) | 5F     14 bytes
//   motor    host → board   C3 | seq | 9 levels as nibbles + flags nibble (5) | CRC (2)                9 bytes
//   sensor   board → host   3C | seq | sample time µs, 24 bits (3) | 9 × 12-bit + status nibble (14) | CRC (2)  21 bytes
// Why v1 peers never misread it: every query byte has a low nibble ≠ 8, so a waiting v1 board skips
// it and a board in step reads a bad packet and waits; five such bytes never occur in a valid v1
// motor stream (every fifth byte ends in 8). Only a v2 board answers with an offer, whose last
// nibble (F) a v1 framer would reject; a v2 board sends frames only after a host's query.
#include "Link/Packets.h"
#include <cstdint>
#include <vector>

namespace armadillo::link {

inline constexpr std::uint8_t kV2Query[5] = {0x41, 0x52, 0x4D, 0x76, 0x32};
inline constexpr std::size_t kV2OfferSize = 14;
inline constexpr std::size_t kV2MotorFrameSize = 9;
inline constexpr std::size_t kV2SensorFrameSize = 21;
inline constexpr std::uint8_t kV2MotorSync = 0xC3;
inline constexpr std::uint8_t kV2SensorSync = 0x3C;
inline constexpr std::uint8_t kV2OfferEnd = 0x5F;
inline constexpr std::uint8_t kV2FlagLeave = 0x1;        ///< motor-frame flag: the board returns to v1 after answering

/// Status nibble bits of a sensor frame (what the board reports about itself).
inline constexpr std::uint8_t kV2StatusWatchdog = 0x1;   ///< its 50 ms link watchdog switched the motors off
inline constexpr std::uint8_t kV2StatusHeatLimit = 0x2;  ///< its own heat limit holds a motor at the rating
inline constexpr std::uint8_t kV2StatusSensorError = 0x4;///< its last IMU read failed

/// CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF); crc16Ccitt("123456789") = 0x29B1.
std::uint16_t crc16Ccitt(const std::uint8_t* data, std::size_t n, std::uint16_t crc = 0xFFFF) noexcept;

struct OfferV2 {
    std::uint8_t version = 0;
    std::uint8_t motors = 0;
    std::uint16_t sensorRateHz = 0;   ///< the IMU rate the board measured it sustains
};
std::array<std::uint8_t, kV2OfferSize> encodeOfferV2(const OfferV2& offer) noexcept;
/// False for anything but a well-formed offer (magic, CRC, end byte, version ≥ 2).
bool decodeOfferV2(const std::uint8_t* bytes, OfferV2& offer) noexcept;

struct SensorFrameV2 {
    std::uint8_t seq = 0;
    std::uint64_t deviceTimeUs = 0;   ///< unwrapped from the frame's 24 bits by the decoder's owner
    std::uint32_t rawTimeUs = 0;      ///< the 24 bits as sent
    SensorCounts counts {};
    std::uint8_t status = 0;
};
std::array<std::uint8_t, kV2SensorFrameSize> encodeSensorFrameV2(const SensorFrameV2& frame) noexcept;
/// Checks sync and CRC; fills frame (deviceTimeUs = rawTimeUs).
bool decodeSensorFrameV2(const std::uint8_t* bytes, SensorFrameV2& frame) noexcept;
std::array<std::uint8_t, kV2MotorFrameSize> encodeMotorFrameV2(std::uint8_t seq, const ProtocolLevels& levels,
                                                               std::uint8_t flags = 0) noexcept;
bool decodeMotorFrameV2(const std::uint8_t* bytes, std::uint8_t& seq, ProtocolLevels& levels, std::uint8_t& flags) noexcept;

struct FramingV2Stats {
    std::uint64_t frames = 0;          ///< good sensor frames
    std::uint64_t crcFailures = 0;     ///< sync byte found, frame failed its CRC
    std::uint64_t seqGaps = 0;         ///< frames missing between good ones (sequence numbers skipped)
    std::uint64_t discardedBytes = 0;  ///< bytes skipped while hunting for a sync byte
};

/// The host's v2 side. Mode V1: not in use (the owner runs HostLink). startNegotiation() →
/// Negotiating: the next 14 bytes decide: an offer ⇒ V2; a v1 sensor packet ⇒ V1 (the packet is
/// kept in v1Answer() for the v1 link); anything else ⇒ V1 as well. In V2, receive() frames
/// sensor frames with sync hunting and CRC, counts sequence gaps and unwraps the board's clock.
class FramingV2Host {
public:
    enum class Mode : std::uint8_t { V1, Negotiating, V2 };

    /// Appends the query and the resync burst to `out`; mode becomes Negotiating.
    void startNegotiation(std::vector<std::uint8_t>& out);
    /// One byte from the board; good sensor frames are appended to `frames`.
    void receive(std::uint8_t byte, std::vector<SensorFrameV2>& frames);
    /// Appends the next motor frame (sequence number advances).
    void encodeMotor(const ProtocolLevels& levels, std::vector<std::uint8_t>& out, std::uint8_t flags = 0);
    /// The owner's timeout for an unanswered negotiation (or a v2 link it gives up on).
    void fallBackToV1() noexcept;
    /// Forgets a partly received frame (the owner resynchronises after a silence).
    void dropPartialFrame() noexcept { if (mode_ == Mode::V2) fill_ = 0; }

    Mode mode() const noexcept { return mode_; }
    const OfferV2& offer() const noexcept { return offer_; }
    /// The v1 sensor packet that ended a negotiation with a v1 board (valid when hasV1Answer()).
    const SensorPacketBytes& v1Answer() const noexcept { return v1Answer_; }
    bool hasV1Answer() const noexcept { return hasV1Answer_; }
    const FramingV2Stats& stats() const noexcept { return stats_; }

private:
    Mode mode_ = Mode::V1;
    OfferV2 offer_ {};
    SensorPacketBytes v1Answer_ {};
    bool hasV1Answer_ = false;
    std::uint8_t buf_[kV2SensorFrameSize] {};
    std::size_t fill_ = 0;
    std::uint8_t motorSeq_ = 0;
    bool haveSeq_ = false;
    std::uint8_t lastSeq_ = 0;
    std::uint32_t lastRawTime_ = 0;
    std::uint64_t time_ = 0;
    FramingV2Stats stats_ {};
};

} // namespace armadillo::link
