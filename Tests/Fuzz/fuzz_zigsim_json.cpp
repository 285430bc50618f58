// ZIG SIM's JSON mode (Osc/OscDialects.h decodeZigSimJson) and its ISO time stamps.
#include "FuzzTarget.h"
#include "Osc/OscDialects.h"

ARMADILLO_FUZZ_TARGET(zigsim_json)
{
    using namespace armadillo::osc;
    const auto text = armadillo::fuzz::text(data, size);
    SensorReading readings[8];
    double senderSeconds = 0.0;
    const char* why = nullptr;
    (void)decodeZigSimJson(text, readings, 8, senderSeconds, &why);
    (void)decodeZigSimJson(text, readings, 1, senderSeconds, &why);
    (void)parseIsoTimestamp(text);
}
