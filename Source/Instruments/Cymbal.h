#pragma once
// The virtual crash cymbal (thesis §3.6): the gesture detector, the fragment bank and the
// scene's extra entry point for user audio. The scene itself is made by makeCymbalScene().
#include "Core/Scene.h"
#include "Core/Wav.h"
#include "Tactile/Hysteresis.h"
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace armadillo::instruments {

/// Strike / touch detection at the cymbal's surface (thesis §3.6.1). The cymbal lies below the
/// surface elevation. Entering it is a strike when the arm had been raised above `armDeg` and
/// comes down faster than `strikeSpeedDegPerS`; any other entry is a touch (it damps a ringing
/// cymbal and never strikes).
struct CymbalGestureParams {
    double surfaceDeg = 0.0;            ///< deg, elevation of the cymbal's surface
    double surfaceBandDeg = 2.0;        ///< deg, hysteresis half-width around the surface
    double armDeg = 5.0;                ///< deg above the surface the arm must reach before a strike
    double strikeSpeedDegPerS = 150.0;  ///< deg/s, slowest downward crossing that strikes
    double speedHoldS = 0.04;           ///< s, the crossing speed is the peak over about this window
};
inline constexpr CymbalGestureParams kDefaultCymbalGesture {};

class CymbalGesture {
public:
    enum class Event { None, Strike, Touch };
    struct Result {
        Event event = Event::None;
        double speedDegPerS = 0.0;   ///< downward elevation speed at the crossing (≥ 0)
        bool inside = false;         ///< below the surface (after hysteresis)
    };

    void setParams(const CymbalGestureParams& p) noexcept;
    /// One control update: elevation in deg, dt in s since the previous one.
    Result update(double elevationDeg, double dt) noexcept;
    void reset() noexcept;
    bool inside() const noexcept { return inside_.on(); }

private:
    CymbalGestureParams p_ {};
    tactile::Hysteresis inside_ {-2.0, 2.0}; ///< downward boundary: on below surface − band
    bool armed_ = false;
    bool havePrevious_ = false;
    double previousDeg_ = 0.0;
    double peakDownSpeed_ = 0.0;      ///< deg/s, decaying peak hold
};

/// Loudness of a strike, 0.35..1, from its speed: the floor keeps the gentlest strike audible.
double cymbalStrikeGain(double speedDegPerS, double strikeSpeedDegPerS) noexcept;

/// The crash sounds (thesis §3.6.2.1): ~4.5 s noise fragments from wind-like (low, gusting) to
/// glass-like (high, with sparse bright pings), and optionally a user recording to cut from.
struct CrashBank {
    static constexpr double kFragmentSeconds = 4.5;
    std::vector<std::vector<float>> fragments;   ///< mono, RMS-normalised, index 0 = darkest
    std::vector<float> user;                     ///< mono user audio at the bank's rate (may be empty)
    double sampleRate = 48000.0;
};
/// Builds the noise bank (not real-time: allocates ~10 MB at 48 kHz).
CrashBank buildCrashBank(double sampleRateHz, std::uint64_t seed, int fragmentCount = 10);
/// Mixes to mono, resamples to the rate (libsamplerate, band-limited) and normalises RMS like the
/// bank's fragments. InputError if the resampler refuses the rates.
std::vector<float> prepareUserAudio(const core::AudioBuffer& audio, double sampleRateHz);

/// Parameter ids of the cymbal scene.
namespace cymbalParam {
inline constexpr const char* kStrikeSpeed = "cymbal.strikeSpeed"; ///< deg/s (150)
inline constexpr const char* kArm = "cymbal.arm";                 ///< deg above the surface to arm a strike (5)
inline constexpr const char* kSurface = "cymbal.surface";         ///< deg, elevation of the surface (0)
inline constexpr const char* kLevel = "cymbal.level";             ///< output gain 0..1 (0.7)
inline constexpr const char* kDamp = "cymbal.damp";               ///< s, damping fade (0.4)
inline constexpr const char* kIdle = "cymbal.idle";               ///< motor level inside, 0..15 (1)
inline constexpr const char* kBrush = "cymbal.brush";             ///< motor levels per rad/s of movement (3)
inline constexpr const char* kTail = "cymbal.tail";               ///< FM tail level 0..1 (0.5)
inline constexpr const char* kFileMix = "cymbal.fileMix";         ///< chance a fragment comes from user audio, % (50)
} // namespace cymbalParam

/// The cymbal scene with its one extra entry point: a recording to cut fragments from.
class CymbalInstrument : public core::Scene {
public:
    /// Not real-time: call before prepare() (prepare resamples it to the audio rate).
    virtual void setUserAudio(const core::AudioBuffer& audio) = 0;
    /// readWav + setUserAudio; throws InputError for a bad file.
    void loadUserAudio(const std::string& wavPath) { setUserAudio(core::readWav(wavPath)); }
};
std::unique_ptr<CymbalInstrument> makeCymbalInstrument();

} // namespace armadillo::instruments
