#pragma once
// The device side of the thesis link (thesis §2.5.3), as the forearm's firmware ran it: read a
// 5-byte motor packet; if its last nibble is 0x8 apply it and answer with a sensor packet; if
// not, wait for any byte whose low nibble is 0x8 and answer that. At power-up the device waits
// for the host (the host is the one that connects). Byte-driven, no clock.
#include "Link/Packets.h"
#include <cstdint>

namespace armadillo::link {

class DeviceProtocol {
public:
    enum class Event : std::uint8_t {
        None,          ///< byte stored, nothing to do yet
        MotorPacket,   ///< a good motor packet: levels() updated; answer with a sensor packet
        Resynced,      ///< a 0x8 byte while waiting: answer with a sensor packet (levels unchanged)
        BadPacket,     ///< a motor packet with a wrong end nibble: now waiting for 0x8
    };

    /// Feeds one byte from the host.
    Event onByte(std::uint8_t byte) noexcept;
    /// Power-up state: waiting for a 0x8 byte.
    void reset() noexcept { waiting_ = true; fill_ = 0; }

    const ProtocolLevels& levels() const noexcept { return levels_; }
    bool waitingForResync() const noexcept { return waiting_; }
    std::uint64_t badPackets() const noexcept { return badPackets_; }

private:
    MotorPacketBytes buffer_ {};
    std::size_t fill_ = 0;
    bool waiting_ = true;
    ProtocolLevels levels_ {};
    std::uint64_t badPackets_ = 0;
};

} // namespace armadillo::link
