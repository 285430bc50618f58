// Positions for walking navigation over UDP (Navigation/OscPositionSource.h): /armadillo/position,
// ZIG SIM's gps in OSC and in JSON — the datagram decoder the position source runs.
#include "FuzzTarget.h"
#include "Navigation/OscPositionSource.h"

ARMADILLO_FUZZ_TARGET(position)
{
    armadillo::navigation::PositionFix fix;
    bool rejected = false;
    (void)armadillo::navigation::decodePositionDatagram(data, size, fix, rejected);
}
