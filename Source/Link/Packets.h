#pragma once
// The thesis link protocol, v1 (thesis §2.5.3, Table 2-2; ARMADILLO.md §2).
//
// Sensor packet, device → host, 14 bytes: nine 12-bit ADC samples packed most-significant-bit
// first in the order ax ay az gx gy gz mx my mz (108 bits), then the end nibble 0x0 in the low
// nibble of byte 13.
// Motor packet, host → device, 5 bytes: nine 4-bit PWM levels, motor 1 in the high nibble of
// byte 0, motor 2 in its low nibble, …, motor 9 in the high nibble of byte 4, whose low nibble
// is the end nibble 0x8.
#include "Core/Types.h"
#include <array>
#include <cstddef>
#include <cstdint>

namespace armadillo::link {

inline constexpr std::size_t kSensorPacketSize = 14;   ///< bytes
inline constexpr std::size_t kMotorPacketSize = 5;     ///< bytes
inline constexpr std::uint8_t kSensorEndNibble = 0x0;
inline constexpr std::uint8_t kMotorEndNibble = 0x8;
/// The byte a device out of step waits for (thesis §2.5.3: "a byte containing 0x8").
inline constexpr std::uint8_t kResyncByte = 0x08;
inline constexpr int kSensorChannels = 9;
inline constexpr int kProtocolMotors = 9;              ///< motors a v1 motor packet carries
inline constexpr std::uint16_t kMaxCount = 4095;       ///< 12-bit ADC full scale

/// Channel order inside a sensor packet.
enum SensorChannel : int { kAx = 0, kAy, kAz, kGx, kGy, kGz, kMx, kMy, kMz };

/// Raw 12-bit counts of one sensor packet, indexed by SensorChannel.
using SensorCounts = std::array<std::uint16_t, kSensorChannels>;
using SensorPacketBytes = std::array<std::uint8_t, kSensorPacketSize>;
using MotorPacketBytes = std::array<std::uint8_t, kMotorPacketSize>;
/// What the host sends to resync (HostLink.h): all nine motors off, then the end nibble 0x8. A
/// device in step applies "all off"; one out of step skips the zeros and syncs on the last byte.
inline constexpr MotorPacketBytes kResyncPacket {0x00, 0x00, 0x00, 0x00, kResyncByte};
/// The nine levels a v1 motor packet carries (motor k at index k−1), 0..15.
using ProtocolLevels = std::array<std::uint8_t, kProtocolMotors>;

/// Counts above 4095 are masked to their low 12 bits (the ADC cannot produce them).
SensorPacketBytes encodeSensorPacket(const SensorCounts& counts) noexcept;
/// Decodes 14 bytes. Returns false when the end nibble is not 0x0 (the counts are still decoded,
/// but must not be trusted).
bool decodeSensorPacket(const std::uint8_t* bytes, SensorCounts& counts) noexcept;
/// True when byte 13's low nibble is the sensor end nibble.
constexpr bool sensorPacketEndOk(std::uint8_t lastByte) noexcept { return (lastByte & 0x0F) == kSensorEndNibble; }

/// Motors 1..9 of `levels`; levels above 15 are clamped to 15 (never wrapped into a weak level).
MotorPacketBytes encodeMotorPacket(const core::MotorLevels& levels) noexcept;
MotorPacketBytes encodeMotorPacket(const ProtocolLevels& levels) noexcept;
/// Decodes 5 bytes. Returns false when the end nibble is not 0x8 (levels still decoded).
bool decodeMotorPacket(const std::uint8_t* bytes, ProtocolLevels& levels) noexcept;
constexpr bool motorPacketEndOk(std::uint8_t lastByte) noexcept { return (lastByte & 0x0F) == kMotorEndNibble; }

/// The lock-step theoretical update rate of a link: one update = 14 + 5 bytes of 10 bits
/// (8N1) on the wire. 57 600 baud ⇒ ≈ 303 updates/s.
constexpr double lockStepRate(double baud) noexcept
{
    return baud / (10.0 * static_cast<double>(kSensorPacketSize + kMotorPacketSize));
}

} // namespace armadillo::link
