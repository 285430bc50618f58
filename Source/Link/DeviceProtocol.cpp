#include "Link/DeviceProtocol.h"

namespace armadillo::link {

DeviceProtocol::Event DeviceProtocol::onByte(std::uint8_t byte) noexcept
{
    if (waiting_) {
        if (!motorPacketEndOk(byte)) return Event::None;
        waiting_ = false;
        fill_ = 0;
        return Event::Resynced;
    }
    buffer_[fill_++] = byte;
    if (fill_ < kMotorPacketSize) return Event::None;
    fill_ = 0;
    ProtocolLevels decoded {};
    if (!decodeMotorPacket(buffer_.data(), decoded)) {
        ++badPackets_;
        waiting_ = true;
        return Event::BadPacket;
    }
    levels_ = decoded;
    return Event::MotorPacket;
}

} // namespace armadillo::link
