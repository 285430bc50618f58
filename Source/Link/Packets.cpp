#include "Link/Packets.h"
#include <algorithm>

namespace armadillo::link {

SensorPacketBytes encodeSensorPacket(const SensorCounts& counts) noexcept
{
    SensorPacketBytes out {};
    // Nine 12-bit samples, MSB first: bit position p of the stream is bit (7 − p % 8) of byte p / 8.
    // Two samples fill three bytes exactly; the ninth fills 1.5 bytes, then the end nibble.
    for (int pair = 0; pair < 4; ++pair) {
        const unsigned a = counts[static_cast<std::size_t>(2 * pair)] & 0x0FFFu;
        const unsigned b = counts[static_cast<std::size_t>(2 * pair + 1)] & 0x0FFFu;
        const std::size_t o = static_cast<std::size_t>(3 * pair);
        out[o] = static_cast<std::uint8_t>(a >> 4);
        out[o + 1] = static_cast<std::uint8_t>(((a & 0x0Fu) << 4) | (b >> 8));
        out[o + 2] = static_cast<std::uint8_t>(b & 0xFFu);
    }
    const unsigned last = counts[8] & 0x0FFFu;
    out[12] = static_cast<std::uint8_t>(last >> 4);
    out[13] = static_cast<std::uint8_t>(((last & 0x0Fu) << 4) | kSensorEndNibble);
    return out;
}

bool decodeSensorPacket(const std::uint8_t* bytes, SensorCounts& counts) noexcept
{
    for (int pair = 0; pair < 4; ++pair) {
        const std::size_t o = static_cast<std::size_t>(3 * pair);
        counts[static_cast<std::size_t>(2 * pair)] =
            static_cast<std::uint16_t>((unsigned(bytes[o]) << 4) | (unsigned(bytes[o + 1]) >> 4));
        counts[static_cast<std::size_t>(2 * pair + 1)] =
            static_cast<std::uint16_t>(((unsigned(bytes[o + 1]) & 0x0Fu) << 8) | unsigned(bytes[o + 2]));
    }
    counts[8] = static_cast<std::uint16_t>((unsigned(bytes[12]) << 4) | (unsigned(bytes[13]) >> 4));
    return sensorPacketEndOk(bytes[13]);
}

MotorPacketBytes encodeMotorPacket(const ProtocolLevels& levels) noexcept
{
    auto nib = [&](int i) { return static_cast<unsigned>(std::min<unsigned>(levels[static_cast<std::size_t>(i)], 15u)); };
    MotorPacketBytes out {};
    for (int i = 0; i < 4; ++i) out[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>((nib(2 * i) << 4) | nib(2 * i + 1));
    out[4] = static_cast<std::uint8_t>((nib(8) << 4) | kMotorEndNibble);
    return out;
}

MotorPacketBytes encodeMotorPacket(const core::MotorLevels& levels) noexcept
{
    ProtocolLevels p {};
    std::copy_n(levels.begin(), kProtocolMotors, p.begin());
    return encodeMotorPacket(p);
}

bool decodeMotorPacket(const std::uint8_t* bytes, ProtocolLevels& levels) noexcept
{
    for (int i = 0; i < 4; ++i) {
        levels[static_cast<std::size_t>(2 * i)] = static_cast<std::uint8_t>(bytes[i] >> 4);
        levels[static_cast<std::size_t>(2 * i + 1)] = static_cast<std::uint8_t>(bytes[i] & 0x0F);
    }
    levels[8] = static_cast<std::uint8_t>(bytes[4] >> 4);
    return motorPacketEndOk(bytes[4]);
}

} // namespace armadillo::link
