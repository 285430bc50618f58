#pragma once
// MPU-9250 (accelerometer, gyroscope) and AK8963 (magnetometer) 16-bit readings → the nine 12-bit
// counts of a sensor packet, in the device frame of INTERFACES.md and scaled so that the host's
// default calibration (Calibration.h: zero at 2048; ±5 g, ±600 °/s, ±2 field units full scale)
// reads them in SI units before the user calibrates.
//
// Mounting (docs/HARDWARE.md): the MPU-9250 breakout lies flat on the board, component side up,
// its x arrow toward the hand. Device frame: x toward the hand, y out of the board's face, z = x × y.
// So device (x, y, z) = MPU (x, z, −y). The AK8963 inside the package has its own axes
// (datasheet: x_mag = y_mpu, y_mag = x_mpu, z_mag = −z_mpu), so device (x, y, z) = AK (y, −z, −x).
//
// Scales (integer Q16/Q8 multipliers, exact to < 0.1 %):
//  - accelerometer at ±8 g, 4096 LSB/g: counts/LSB = 2047 / (5 · 4096)
//  - gyroscope at ±1000 °/s, 32.8 LSB/(°/s): counts/LSB = 2047 / (600 · 32.8)
//  - magnetometer 16-bit, 0.15 µT/LSB, 1 field unit := 50 µT (a typical Earth field):
//    counts/LSB = 0.15 · 2047 / (2 · 50), times the chip's factory sensitivity adjustment
//    (ASA + 128) / 256.
// Readings past the 12-bit range saturate at 0 or 4095 (never wrap).
#include <stdint.h>
#include "Protocol.h"

namespace armfw {

constexpr int32_t kAccelQ16 = 6550;   ///< round(2047 / 20480 · 65536)
constexpr int32_t kGyroQ16 = 6817;    ///< round(2047 / 19680 · 65536)
constexpr int32_t kMagQ8 = 786;       ///< round(0.15 · 2047 / 100 · 256)

/// One reading of the IMU in its own axes (register order, already big-endian-decoded).
struct ImuRaw {
    int16_t accel[3];   ///< MPU x y z, LSB
    int16_t gyro[3];    ///< MPU x y z, LSB
    int16_t mag[3];     ///< AK8963 x y z, LSB
};

/// The magnetometer multipliers with the factory adjustment ASA (AK8963 registers 0x10..0x12) folded in.
void magScales(const uint8_t asa[3], int32_t scaleQ16[3]);
/// counts in packet order ax ay az gx gy gz mx my mz.
void toCounts(const ImuRaw& raw, const int32_t magScaleQ16[3], uint16_t counts[kChannels]);
/// 2048 + (value · q >> shift), rounded to nearest, clamped to 0..4095.
uint16_t scaleToCount(int32_t value, int32_t q, uint8_t shift);

} // namespace armfw
