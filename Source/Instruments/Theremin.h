#pragma once
// The fretted theremin (thesis §3.5): a sine whose pitch follows elevation and whose volume
// follows azimuth, with tactile frets. The scene itself is made by makeThereminScene().
#include <cmath>

namespace armadillo::instruments {

/// Volume from azimuth: full at the reference heading (where the scene was entered), a quarter
/// cosine down to silence at ±width degrees. deltaDeg is the wrapped heading difference.
inline double thereminVolume(double deltaDeg, double widthDeg) noexcept
{
    const double d = std::fabs(deltaDeg);
    if (!(widthDeg > 0.0) || d >= widthDeg) return 0.0;
    return std::cos(0.5 * 3.14159265358979323846 * d / widthDeg);
}

/// Parameter ids of the theremin scene (stable: hosts automate them).
namespace thereminParam {
inline constexpr const char* kBase = "theremin.base";             ///< Hz at the bottom elevation (220)
inline constexpr const char* kRange = "theremin.range";           ///< semitones bottom→top (12)
inline constexpr const char* kBottom = "theremin.bottom";         ///< deg, elevation of base (−45)
inline constexpr const char* kTop = "theremin.top";               ///< deg, elevation of base+range (+45)
inline constexpr const char* kVolumeWidth = "theremin.volumeWidth"; ///< deg either side to silence (60)
inline constexpr const char* kLevel = "theremin.level";           ///< output peak 0..1 (0.5)
inline constexpr const char* kGlide = "theremin.glide";           ///< ms, pitch smoothing time (20)
inline constexpr const char* kSnap = "theremin.snap";             ///< %, pull toward scale notes (0)
inline constexpr const char* kScale = "theremin.scale";           ///< choice, fretScaleNames() (major)
inline constexpr const char* kRoot = "theremin.root";             ///< choice, pitchClassNames() (A)
inline constexpr const char* kFretAdjust = "theremin.fretAdjust"; ///< %, approach adjustment (1)
inline constexpr const char* kFretLevel = "theremin.fretLevel";   ///< motor level 0..15 (5)
} // namespace thereminParam

} // namespace armadillo::instruments
