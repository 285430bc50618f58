// Learning for the mapping editors: a destination from the next MIDI message (MIDI learn) and a
// source's range from the arm's movement. Real-time; no state beyond what the caller holds.
#include "Mapping/Mapper.h"
#include <cmath>

namespace armadillo::mapping {

bool learnDestination(const std::uint8_t* bytes, int size, DestinationSpec& out) noexcept
{
    if (bytes == nullptr || size < 1) return false;
    const int status = bytes[0];
    if (status < 0x80 || status >= 0xF0) return false;
    const int type = status & 0xF0;
    DestinationSpec d;
    d.channel = (status & 0x0F) + 1;
    switch (type) {
    case 0xB0:
        if (size < 3) return false;
        d.kind = DestinationKind::Cc7;
        d.number = bytes[1] & 0x7F;
        if (d.number < 32 && size >= 6 && bytes[3] == status && bytes[4] == d.number + 32) d.kind = DestinationKind::Cc14;
        break;
    case 0xE0:
        if (size < 3) return false;
        d.kind = DestinationKind::PitchBend;
        break;
    case 0xD0:
        if (size < 2) return false;
        d.kind = DestinationKind::ChannelPressure;
        break;
    case 0x90:
        if (size < 3 || bytes[2] == 0) return false;
        d.kind = DestinationKind::Notes;
        d.number = bytes[1] & 0x7F;
        break;
    case 0xC0:
        if (size < 2) return false;
        d.kind = DestinationKind::ProgramChange;
        d.number = bytes[1] & 0x7F;
        break;
    default: return false;
    }
    out = d;
    return true;
}

void RangeLearner::add(double v) noexcept
{
    if (!std::isfinite(v)) return;
    if (count == 0 || v < lo) lo = v;
    if (count == 0 || v > hi) hi = v;
    ++count;
}

bool RangeLearner::range(double& outLo, double& outHi) const noexcept
{
    if (count < 2 || !(hi > lo)) return false;
    outLo = lo;
    outHi = hi;
    return true;
}

} // namespace armadillo::mapping
