// The OSC sensor input as the receiver thread runs it (Osc/OscInput.h OscSampleMerger): a
// sequence of datagrams (OSC or ZIG SIM JSON) from one or two senders, dialect detection or a
// given dialect, the held readings sampled between datagrams. Input: a byte choosing the dialect,
// then datagrams, each a 16-bit length (little-endian) and its bytes.
#include "FuzzTarget.h"
#include "Osc/OscInput.h"

namespace {
void imuSink(void* context, const armadillo::core::ImuSample&) { ++*static_cast<int*>(context); }
void orientationSink(void* context, double, const Eigen::Quaterniond&) { ++*static_cast<int*>(context); }
} // namespace

ARMADILLO_FUZZ_TARGET(osc_merger)
{
    using namespace armadillo::osc;
    armadillo::fuzz::Bytes in(data, size);
    const std::uint8_t mode = in.byte();
    OscInputOptions options;
    options.format = static_cast<OscFormat>(mode % kOscFormatCount);
    OscSampleMerger merger(options);
    int delivered = 0;
    merger.setSinks(imuSink, orientationSink, &delivered);
    double now = 1.0;
    const double step = 0.001 * (1 + ((mode >> 3) & 15));
    while (in.size() > 0) {
        std::size_t n = in.byte();
        n |= static_cast<std::size_t>(in.byte()) << 8;
        n = std::min(n, in.size());
        const std::uint64_t sender = (n & 1) && (mode & 0x80) ? 2 : 1;
        merger.handleDatagram(in.data(), n, now, sender, sender == 1 ? "127.0.0.1:9000" : "127.0.0.2:9000");
        for (std::size_t i = 0; i < n; ++i) (void)in.byte();
        now += step;
        merger.tick(now);
    }
    merger.tick(now + 3.0);
    (void)merger.stats();
    (void)merger.deviceName();
    (void)merger.mount();
    (void)merger.heard();
    (void)merger.rates();
}
