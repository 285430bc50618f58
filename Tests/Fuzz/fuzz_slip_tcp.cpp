// Stream framing of OSC: SLIP (Osc/Slip.h, the NGIMU's serial and USB link) and the TCP splitter
// (Osc/OscStream.h, ZIG SIM's unframed TCP: JSON objects and OSC bundles back to back), each
// unit cut from the stream decoded as the input does. Input: a byte with the split points' seed,
// then the stream.
#include "FuzzTarget.h"
#include "Osc/Osc.h"
#include "Osc/OscStream.h"
#include "Osc/Slip.h"

namespace {
void decodeUnit(const std::uint8_t* unit, std::size_t size)
{
    const char* error = nullptr;
    (void)armadillo::osc::decodeOscPacket(unit, size, [](void*, const armadillo::osc::OscMessage&) {}, nullptr, &error);
}
} // namespace

ARMADILLO_FUZZ_TARGET(slip_tcp)
{
    using namespace armadillo::osc;
    armadillo::fuzz::Bytes in(data, size);
    const std::size_t chunk = 1 + in.byte() % 37;   // the stream arrives in pieces of this size
    SlipDecoder slip(1024);
    OscStreamSplitter splitter(4096);
    std::size_t units = 0;
    for (std::size_t at = 0; at < in.size(); at += chunk) {
        const std::size_t n = std::min(chunk, in.size() - at);
        slip.feed(in.data() + at, n, [&](const std::uint8_t* packet, std::size_t packetSize) {
            decodeUnit(packet, packetSize);
            const auto again = slipEncode(packet, packetSize);
            ++units;
            (void)again;
        });
        splitter.feed(in.data() + at, n, [](void* context, const std::uint8_t* unit, std::size_t unitSize) {
            decodeUnit(unit, unitSize);
            ++*static_cast<std::size_t*>(context);
        }, &units);
    }
    (void)slip.badPackets();
    (void)splitter.overflows();
}
