#include "SensorScale.h"

namespace armfw {

uint16_t scaleToCount(int32_t value, int32_t q, uint8_t shift)
{
    const int32_t half = static_cast<int32_t>(1) << (shift - 1);
    const int32_t scaled = value * q;
    // Round half away from zero with an arithmetic shift on the magnitude (portable for negatives).
    const int32_t mag = scaled < 0 ? -scaled : scaled;
    int32_t r = (mag + half) >> shift;
    if (scaled < 0) r = -r;
    const int32_t c = 2048 + r;
    return static_cast<uint16_t>(c < 0 ? 0 : (c > 4095 ? 4095 : c));
}

void magScales(const uint8_t asa[3], int32_t scaleQ16[3])
{
    // kMagQ8 · (ASA + 128) / 256 in Q8 = kMagQ8 · (ASA + 128) in Q16.
    for (uint8_t i = 0; i < 3; ++i) scaleQ16[i] = kMagQ8 * (static_cast<int32_t>(asa[i]) + 128);
}

void toCounts(const ImuRaw& raw, const int32_t magScaleQ16[3], uint16_t counts[kChannels])
{
    // device (x, y, z) = MPU (x, z, −y)
    counts[0] = scaleToCount(raw.accel[0], kAccelQ16, 16);
    counts[1] = scaleToCount(raw.accel[2], kAccelQ16, 16);
    counts[2] = scaleToCount(-static_cast<int32_t>(raw.accel[1]), kAccelQ16, 16);
    counts[3] = scaleToCount(raw.gyro[0], kGyroQ16, 16);
    counts[4] = scaleToCount(raw.gyro[2], kGyroQ16, 16);
    counts[5] = scaleToCount(-static_cast<int32_t>(raw.gyro[1]), kGyroQ16, 16);
    // device (x, y, z) = AK (y, −z, −x); |value| ≤ 32768 and scale ≤ 786·383 ⇒ |product| < 2^33:
    // too big for int32, so shift the scale first (Q16 → Q10 keeps 0.1 % precision).
    counts[6] = scaleToCount(raw.mag[1], magScaleQ16[1] >> 6, 10);
    counts[7] = scaleToCount(-static_cast<int32_t>(raw.mag[2]), magScaleQ16[2] >> 6, 10);
    counts[8] = scaleToCount(-static_cast<int32_t>(raw.mag[0]), magScaleQ16[0] >> 6, 10);
}

} // namespace armfw
