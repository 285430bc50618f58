#pragma once
// The device side of the ARMadillo link, as the reference firmware runs it: the thesis protocol v1
// (thesis §2.5.3, Table 2-2; ARMADILLO.md §2) and the optional v2 framing a host can negotiate
// (docs/DEVICE.md "v2 framing"). Plain C++ with no library beyond <stdint.h>/<stddef.h>, so the same
// file is compiled by avr-gcc for the ATmega2560 and by the host compiler for unit tests.
//
// Byte-driven and clock-free except for the v2 fallback timer: the owner feeds every received byte
// with the time in ms, and when onByte() says a reply is due it calls buildReply(), which writes the
// v1 sensor packet, the v2 offer or the v2 sensor frame the mode calls for.
#include <stddef.h>
#include <stdint.h>

namespace armfw {

constexpr uint8_t kMotors = 9;            ///< motors a packet carries (3×3 grid, ARMADILLO.md §1)
constexpr uint8_t kChannels = 9;          ///< ax ay az gx gy gz mx my mz
constexpr uint16_t kMaxCount = 4095;      ///< 12-bit sample full scale

// v1 (the thesis): 14-byte sensor packet ending in nibble 0x0, 5-byte motor packet ending in 0x8.
constexpr uint8_t kV1SensorSize = 14;
constexpr uint8_t kV1MotorSize = 5;
constexpr uint8_t kMotorEndNibble = 0x8;

// v2: negotiated, CRC-16/CCITT-FALSE protected, sequence numbered, device-timestamped.
/// host → device "ARMv2" = 41 52 4D 76 32. No byte has low nibble 8, so (a) a waiting v1 device ignores
/// it and one in step reads a bad packet and waits, and (b) it can never occur inside a valid v1 motor
/// stream, where every fifth byte has low nibble 8.
constexpr uint8_t kQuerySize = 5;
constexpr uint8_t kOfferSize = 14;        ///< device → host, answers the resync that follows a query
constexpr uint8_t kV2MotorSize = 9;       ///< C3 seq L1L2 L3L4 L5L6 L7L8 L9|flags crcH crcL
constexpr uint8_t kV2SensorSize = 21;     ///< 3C seq t2 t1 t0 [13.5 bytes of samples|status] crcH crcL
constexpr uint8_t kV2MotorSync = 0xC3;
constexpr uint8_t kV2SensorSync = 0x3C;
constexpr uint8_t kV2Version = 2;
constexpr uint8_t kOfferEndByte = 0x5F;   ///< low nibble F: a v1 host would reject the frame
/// The host → device v2 motor frame flag "leave v2": the device answers this last frame, then waits in v1.
constexpr uint8_t kV2FlagLeave = 0x1;
/// v2 without a good frame this long ⇒ back to v1, waiting for 0x8 (a v1 host connected, or the host left).
constexpr uint16_t kV2FallbackMs = 200;

/// Status nibble of a v2 sensor frame (low nibble of its 19th byte).
enum StatusBits : uint8_t {
    kStatusWatchdog = 0x1,    ///< the 50 ms link watchdog switched every motor off since the last frame
    kStatusHeatLimit = 0x2,   ///< the firmware's heat limit is holding at least one motor at its rating
    kStatusSensorError = 0x4, ///< the last I2C read failed (samples are the last good ones)
};

extern const uint8_t kQuery[kQuerySize];

/// CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no reflection, no final xor); check("123456789") = 0x29B1.
uint16_t crc16(const uint8_t* data, size_t n, uint16_t crc = 0xFFFF);

/// Nine 12-bit samples MSB first (ax ay az gx gy gz mx my mz) into 13.5 bytes; the low nibble of
/// out[13] is `lastNibble`. Counts above 4095 are clamped (never wrapped).
void packSamples(const uint16_t counts[kChannels], uint8_t lastNibble, uint8_t out[14]);
void unpackSamples(const uint8_t in[14], uint16_t counts[kChannels]);
void encodeV1Sensor(const uint16_t counts[kChannels], uint8_t out[kV1SensorSize]);
void encodeOffer(uint16_t sensorRateHz, uint8_t out[kOfferSize]);
/// timeUs: the device's sample time, 24 bits kept (wraps every 16.8 s; the host unwraps).
void encodeV2Sensor(uint8_t seq, uint32_t timeUs, const uint16_t counts[kChannels], uint8_t status,
                    uint8_t out[kV2SensorSize]);
/// Host side helper (tests, the simavr loop): levels 0..15 (clamped) into a v2 motor frame.
void encodeV2Motor(uint8_t seq, const uint8_t levels[kMotors], uint8_t flags, uint8_t out[kV2MotorSize]);

/// What the device link reports per byte.
enum class LinkEvent : uint8_t {
    None,        ///< byte stored (or skipped), nothing to do
    Motor,       ///< a good motor packet/frame: levels() changed; a reply is due
    Resynced,    ///< v1: a byte with low nibble 0x8 ended the wait; a reply is due, levels unchanged
    BadPacket,   ///< v1: 5 bytes whose end nibble is not 0x8; now waiting for 0x8
    BadFrame,    ///< v2: a sync byte whose frame failed its CRC; rescanning
};

class DeviceLink {
public:
    enum class Mode : uint8_t { V1, V2 };

    DeviceLink() { reset(); }
    /// Power-up: v1, waiting for a byte whose low nibble is 0x8 (the host connects), levels all 0.
    void reset();
    LinkEvent onByte(uint8_t byte, uint32_t nowMs);
    /// Timers (v2 → v1 fallback). Call regularly with the same clock as onByte().
    void tick(uint32_t nowMs);
    /// Writes the reply due after Motor/Resynced; returns its length (0 when none is due).
    /// counts: the latest sample; timeUs: when it was taken; status: StatusBits.
    uint8_t buildReply(const uint16_t counts[kChannels], uint32_t timeUs, uint8_t status, uint16_t sensorRateHz,
                       uint8_t* out, uint8_t capacity);
    bool replyDue() const { return replyDue_; }

    Mode mode() const { return mode_; }
    bool waitingForResync() const { return waiting_; }
    const uint8_t* levels() const { return levels_; }
    uint8_t lastHostSeq() const { return hostSeq_; }
    // Counters (wrap at 2^16; for diagnostics).
    uint16_t badPackets() const { return badPackets_; }
    uint16_t badFrames() const { return badFrames_; }
    uint16_t seqGaps() const { return seqGaps_; }   ///< v2: host frames missing between good ones

private:
    LinkEvent onV1(uint8_t byte);
    LinkEvent onV2(uint8_t byte, uint32_t nowMs);

    Mode mode_ = Mode::V1;
    bool waiting_ = true;
    bool offerPending_ = false;
    bool leavePending_ = false;
    bool replyDue_ = false;
    bool haveHostSeq_ = false;
    uint8_t buf_[kV2MotorSize] = {};
    uint8_t fill_ = 0;
    uint8_t levels_[kMotors] = {};
    uint8_t queryMatch_ = 0;
    uint32_t lastGoodMs_ = 0;
    uint8_t hostSeq_ = 0;
    uint8_t seq_ = 0;
    uint16_t badPackets_ = 0, badFrames_ = 0, seqGaps_ = 0;
};

} // namespace armfw
