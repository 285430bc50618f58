// OSC packets and bundles (Osc/Osc.h): the decoder with both sinks, every message through every
// dialect's reader (Osc/OscDialects.h) and the dialect detection, and a decoded message encoded back.
#include "FuzzTarget.h"
#include "Osc/Osc.h"
#include "Osc/OscDialects.h"

namespace {
void eachMessage(void*, const armadillo::osc::OscMessage& m)
{
    using namespace armadillo::osc;
    (void)detectOscFormat(m);
    for (int f = 1; f < kOscFormatCount; ++f) {
        SensorReading r;
        const char* why = nullptr;
        (void)decodeOscReading(static_cast<OscFormat>(f), m, r, &why);
    }
    double v = 0.0;
    for (int i = 0; i < m.count; ++i) (void)m.args[i].asNumber(v);
    std::uint8_t buffer[2048];
    (void)encodeOscMessage(m.address, m.args, static_cast<std::size_t>(m.count), buffer, sizeof buffer);
}
} // namespace

ARMADILLO_FUZZ_TARGET(osc_packet)
{
    using namespace armadillo::osc;
    const char* error = nullptr;
    (void)decodeOscPacket(data, size, eachMessage, nullptr, &error);
    std::string why;
    int messages = 0;
    (void)decodeOscPacket(data, size, [&](const OscMessage& m) { messages += m.count >= 0 ? 1 : 0; }, &why);
}
