#pragma once
// Basic vocabulary shared by every module. SI units inside the core (STYLE.md convention 2).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>

namespace armadillo::core {

/// Motors the protocol can address (thesis §2.3: the board drives 16). k = 1..16 in the docs,
/// index k-1 in code. 0..8 = the 3×3 grid, 9..11 = optional back motors, 12..15 spare.
inline constexpr int kMaxMotors = 16;
inline constexpr int kGridMotors = 9;
inline constexpr int kBackMotors = 3;
inline constexpr int kMaxLevel = 15;        ///< 4-bit PWM (thesis §3.2.1)
inline constexpr int kRatedLevel = 5;       ///< duty 0.33 of 9 V = the motors' 3 V rating (thesis §3.2.2)

/// One motor packet's worth of levels, 0..15 each. Only the tactile safety stage produces these.
using MotorLevels = std::array<std::uint8_t, kMaxMotors>;

/// Grid index of (row, col): row 0 = wrist, 1 = middle, 2 = elbow; col 0 = left, 1 = underside,
/// 2 = right, as drawn for the right arm (ARMADILLO.md §1). Motor number k = index + 1.
constexpr int motorIndex(int row, int col) noexcept { return 3 * row + col; }

enum class ArmSide : std::uint8_t { Right, Left };   ///< which arm wears the device; Left mirrors columns

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kStandardGravity = 9.80665;   ///< m/s²
inline constexpr double kPi = 3.14159265358979323846;
constexpr double degToRad(double d) noexcept { return d * kPi / 180.0; }
constexpr double radToDeg(double r) noexcept { return r * 180.0 / kPi; }

/// One calibrated inertial sample in the device frame (x toward the hand, y out of the board's
/// face, z = x × y). Any vector may be all-NaN when the source does not provide it.
struct ImuSample {
    double t = 0.0;                                   ///< s
    Eigen::Vector3d gyro {kNaN, kNaN, kNaN};          ///< rad/s
    Eigen::Vector3d accel {kNaN, kNaN, kNaN};         ///< m/s² (specific force: +g up at rest)
    Eigen::Vector3d mag {kNaN, kNaN, kNaN};           ///< any consistent unit (direction matters)
};

/// Exit codes of the `armadillo` command line (INTERFACES.md).
enum ExitCode : int { kExitOk = 0, kExitFailure = 1, kExitUsage = 2, kExitBadInput = 3, kExitIo = 4 };

} // namespace armadillo::core
