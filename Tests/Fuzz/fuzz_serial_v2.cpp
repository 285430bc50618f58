// The link's v2 framing (Link/FramingV2.h): negotiation with what claims to be a board (offer,
// v1 answer or garbage), then sync hunting, CRC, sequence gaps and clock unwrapping of sensor
// frames; the frame decoders on every window of the input.
#include "FuzzTarget.h"
#include "Link/FramingV2.h"

ARMADILLO_FUZZ_TARGET(serial_v2)
{
    using namespace armadillo::link;
    armadillo::fuzz::Bytes in(data, size);
    const std::uint8_t mode = in.byte();
    FramingV2Host host;
    std::vector<std::uint8_t> out;
    std::vector<SensorFrameV2> frames;
    host.startNegotiation(out);
    ProtocolLevels levels {};
    for (std::size_t i = 0; i < in.size(); ++i) {
        host.receive(in.data()[i], frames);
        if (mode & 1 && i % 64 == 63) host.dropPartialFrame();
        if (host.mode() == FramingV2Host::Mode::V2 && i % 21 == 0) host.encodeMotor(levels, out);
    }
    if (host.hasV1Answer()) (void)host.v1Answer();
    host.fallBackToV1();

    OfferV2 offer;
    SensorFrameV2 frame;
    std::uint8_t seq = 0, flags = 0;
    for (std::size_t i = 0; i + kV2OfferSize <= in.size(); ++i) (void)decodeOfferV2(in.data() + i, offer);
    for (std::size_t i = 0; i + kV2SensorFrameSize <= in.size(); ++i) (void)decodeSensorFrameV2(in.data() + i, frame);
    for (std::size_t i = 0; i + kV2MotorFrameSize <= in.size(); ++i) (void)decodeMotorFrameV2(in.data() + i, seq, levels, flags);
    (void)crc16Ccitt(in.data(), in.size());
}
