#pragma once
// Counts → SI, once, at the edge (STYLE.md convention 2), and the thesis's calibration procedures
// (thesis §2.4; ARMADILLO.md §3). physical = cross · ((count − bias) ∘ scale) per sensor, in the
// device frame: bias in raw 12-bit counts, scale in SI units per count (m/s², rad/s, field
// units), cross the optional 3×3 cross-axis matrix (identity when absent).
#include "Core/Types.h"
#include "Link/Packets.h"
#include <Eigen/Core>
#include <string>
#include <string_view>

namespace armadillo::link {

struct SensorCalibration {
    Eigen::Vector3d bias {2048.0, 2048.0, 2048.0};   ///< counts
    Eigen::Vector3d scale {1.0, 1.0, 1.0};           ///< SI units per count (sign = axis direction)
    Eigen::Matrix3d cross = Eigen::Matrix3d::Identity();   ///< cross-axis terms, dimensionless

    Eigen::Vector3d apply(double cx, double cy, double cz) const noexcept;
    /// The counts (unrounded) that would produce `physical` — the simulator's model of the ADC.
    Eigen::Vector3d toCounts(const Eigen::Vector3d& physical) const noexcept;
};

struct Calibration {
    SensorCalibration accel, gyro, mag;
    std::string device;   ///< optional: which board this belongs to
    std::string date;     ///< optional: when it was made (ISO 8601)

    core::ImuSample apply(double t, const SensorCounts& counts) const noexcept;
};

/// Sensor ranges of the default calibration (and of the built-in simulator's ADC):
/// accelerometer ±5 g, gyroscope ±600 °/s, magnetometer ±2 field units (1 = the local field),
/// every zero at mid-scale 2048.
inline constexpr double kDefaultAccelRange = 5.0 * core::kStandardGravity; ///< m/s² at full scale
inline constexpr double kDefaultGyroRange = 600.0 * core::kPi / 180.0; ///< rad/s at full scale
inline constexpr double kDefaultMagRange = 2.0;                       ///< field units at full scale
Calibration defaultCalibration();

/// Parses the JSON of INTERFACES.md; throws InputError naming source, line and key.
Calibration parseCalibration(std::string_view json, const std::string& source);
/// Reads a file: IoError when unreadable, InputError when invalid.
Calibration loadCalibration(const std::string& path);
std::string calibrationToJson(const Calibration& calibration);
/// Atomic write (whole or nothing).
void saveCalibration(const std::string& path, const Calibration& calibration);

/// The thesis's calibration as a guided procedure (thesis §2.4). The app or CLI shows
/// instruction(), feeds every raw packet, and calls finishStep() when ready() (or skipStep() to
/// keep that part of the starting calibration). Steps:
///  1. GyroStill: keep still — gyro bias = mean counts (movement restarts the step).
///  2. AccelExtremes: point each axis down and up, holding each briefly — bias = midpoint of the
///     held extremes, scale to ±1 g.
///  3. MagHorizontal: hold level, turn a full circle; 4. MagVertical: turn through vertical
///     circles (the field dips, so only this finds the true extremes) — bias = midpoint, scale
///     to ±1 field unit.
///  5–7. GyroTurnX/Y/Z: one full turn about the named axis and stop — scale = 2π / ∫counts dt
///     (the thesis used a stepper jig at known rates; a turntable gives the same here).
class CalibrationProcedure {
public:
    enum class Step { GyroStill, AccelExtremes, MagHorizontal, MagVertical, GyroTurnX, GyroTurnY, GyroTurnZ, Done };

    struct Params {
        double stillSeconds = 3.0;          ///< s of stillness for the gyro bias
        double stillGyroLimit = 0.05;       ///< rad/s: more than this (start calibration) is movement
        double holdGyroLimit = 0.35;        ///< rad/s: accel extremes only count while this still
        double smoothingSeconds = 0.1;      ///< s: low-pass of accel/mag counts before extremes
        double minAccelSpanFraction = 0.8;  ///< each axis must span this fraction of ±1 g (start calibration)
        double minMagSpanFraction = 0.5;    ///< after both sweeps each axis must span this fraction of ±1 field unit
        double minHorizontalSpanFraction = 0.2;   ///< horizontal sweep: two axes span this (the field dips, so less)
        double maxStillRate = 1.0;          ///< rad/s (start calibration): above this nothing counts as still
        double turnAngle = 2.0 * core::kPi; ///< rad: the turn the gyro steps ask for
        double minTurnFraction = 0.5;       ///< the integrated turn must reach this fraction of turnAngle
    };

    explicit CalibrationProcedure(const Calibration& start = defaultCalibration());
    CalibrationProcedure(const Calibration& start, const Params& params);

    Step step() const noexcept { return step_; }
    static const char* stepName(Step s) noexcept;
    std::string instruction() const;
    /// 0..1 within the current step.
    double progress() const noexcept;
    bool ready() const noexcept;
    /// Feeds one raw packet (t in s, increasing).
    void feed(double t, const SensorCounts& counts);
    /// Applies the step's result and moves on. Throws InputError when !ready() (says why).
    void finishStep();
    void skipStep();
    const Calibration& result() const noexcept { return result_; }

private:
    void beginStep(Step s);
    Calibration result_;
    Params params_;
    Step step_ = Step::GyroStill;
    double stepStart_ = -1.0, lastT_ = -1.0;
    // GyroStill
    Eigen::Vector3d sum_ = Eigen::Vector3d::Zero();
    long count_ = 0;
    // Extremes
    Eigen::Vector3d smooth_ = Eigen::Vector3d::Zero();
    bool haveSmooth_ = false;
    Eigen::Vector3d min_, max_;
    // Turns
    Eigen::Vector3d integral_ = Eigen::Vector3d::Zero();   ///< count·s, bias removed
};

} // namespace armadillo::link
