// The thesis link, protocol v1 (Link/HostLink.h, Link/DeviceProtocol.h): bytes from the board
// into the host's lock-step framer (resync, silence rule, bad end nibbles), bytes from a host
// into the device side, and the packet decoders on every window of the input.
#include "FuzzTarget.h"
#include "Link/DeviceProtocol.h"
#include "Link/HostLink.h"
#include "Link/Packets.h"

namespace {
class Peer final : public armadillo::link::LinkPeer {
public:
    armadillo::core::MotorLevels onSensorPacket(const armadillo::link::SensorCounts& counts, double) override
    {
        armadillo::core::MotorLevels levels {};
        for (std::size_t i = 0; i < levels.size() && i < counts.size(); ++i) levels[i] = static_cast<float>(counts[i] % 16);
        return levels;
    }
    void send(const std::uint8_t*, std::size_t count) override { sent += count; }
    std::size_t sent = 0;
};
} // namespace

ARMADILLO_FUZZ_TARGET(serial_v1)
{
    using namespace armadillo::link;
    armadillo::fuzz::Bytes in(data, size);
    // First byte: the link's options and how fast bytes arrive (timing drives the silence rule).
    const std::uint8_t mode = in.byte();
    LinkConfig config;
    config.negotiateV2 = (mode & 1) != 0;
    config.adaptiveSilence = (mode & 2) != 0;
    HostLink host(config);
    Peer peer;
    double now = 0.0;
    host.reset(now);
    const double step = 0.0001 * (1 + (mode >> 2));   // 0.1 .. 6.4 ms per chunk
    const std::uint8_t* p = in.data();
    std::size_t left = in.size();
    while (left > 0) {
        const std::size_t chunk = std::min<std::size_t>(left, 1 + (p[0] % 19));
        host.receive(p, chunk, now, peer);
        now += step * static_cast<double>(chunk);
        host.poll(now, peer);
        if (host.reopenDue(now)) host.reset(now);
        p += chunk;
        left -= chunk;
    }
    host.poll(now + 1.0, peer);
    host.sendAllOff(now + 1.0, peer);

    DeviceProtocol device;
    for (std::size_t i = 0; i < in.size(); ++i) (void)device.onByte(in.data()[i]);

    SensorCounts counts {};
    ProtocolLevels levels {};
    for (std::size_t i = 0; i + kSensorPacketSize <= in.size(); ++i) {
        if (decodeSensorPacket(in.data() + i, counts)) (void)encodeSensorPacket(counts);
    }
    for (std::size_t i = 0; i + kMotorPacketSize <= in.size(); ++i) (void)decodeMotorPacket(in.data() + i, levels);
}
