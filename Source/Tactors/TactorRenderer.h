#pragma once
// The motor grid as audio (issue 33, docs/TACTORS.md): motor levels → one audio channel per
// tactor, for rigs whose actuators are driven by a sound card (Syntacts amplifiers, voice-coil
// tactors, LRAs behind small amplifiers). The one renderer behind `render --tactile-wav`, the
// live tactor output of `armadillo play` (ALSA or JACK) and, later, the plugin's Tactors bus.
//
// Convention (docs/FORMATS.md, after Syntacts: Pezent et al., IEEE Trans. Haptics 2020):
// channel k drives tactor k; a level L is a carrier of peak amplitude L/15 of full scale (times the
// channel's calibration gain, ≤ 1), whatever the model. The models differ in the carrier:
//   erm         the vibration of a spinning mass: frequency rising linearly with the level
//               (a DC motor's speed follows its voltage), following it with the mass's spin-up
//               time constant;
//   lra         a sine at the actuator's resonance (170 Hz); a stop ends with a braking pulse (the
//               drive in antiphase, at most the rated level, about one period) so the mass stops
//               at once instead of ringing down; the engine's jump-start spike is the overdrive;
//   voice-coil  a fixed carrier of 40…400 Hz (250 Hz: the skin's Pacinian peak).
//
// Safety where the actuator is: what a channel carries (the level, or a braking pulse) passes a
// SafetyStage of the tactile engine's parameters last, per channel, at every level change. For a
// level stream that came out of the engine's own safety stage with the same times, the guard is a
// fixed point (same history, same decisions): it only ever acts on what the renderer adds.
//
// Threads: prepare() allocates; setLevels(), render() and allOff() allocate, lock and throw
// nothing (tested under the RealtimeGuard), so the plugin can call them per block on its audio
// thread and `play`'s output calls them on the sound card's or JACK's thread.
#include "Core/Biquad.h"
#include "Core/Csv.h"
#include "Core/Types.h"
#include "Core/Wav.h"
#include "Tactile/TactileEngine.h"
#include <array>
#include <string>
#include <string_view>

namespace armadillo::tactors {

inline constexpr int kMaxChannels = core::kMaxMotors; ///< 16: a 16-output interface, or 12 motors + spare

enum class TactorModel { Erm, Lra, VoiceCoil };
const char* modelName(TactorModel m) noexcept;   ///< "erm", "lra", "voice-coil"
bool parseModel(std::string_view text, TactorModel& out) noexcept;
inline constexpr const char* kModelNames = "erm, lra, voice-coil";

/// The carrier of each model (Hz, s). Ranges are checked by validate().
struct TactorParams {
    TactorModel model = TactorModel::Erm;
    double ermStartHz = 100.0;     ///< Hz at level 0+ (the mass just turning); 40…ermFullHz
    double ermFullHz = 250.0;      ///< Hz at level 15 (full drive)
    double ermSpinTime = 0.030;    ///< s: time constant of the mass's speed following the drive (0…0.2)
    double lraHz = 170.0;          ///< Hz: the LRA's resonance (40…400)
    double lraBrakeTime = 0.006;   ///< s: antiphase braking pulse after a stop (0 = none, ≤ 0.02)
    double voiceCoilHz = 250.0;    ///< Hz: the voice coil's carrier (40…400)
    /// voice-coil only: a scene with a sound of its own hands it over (setSound): the carrier is
    /// that sound band-limited to what skin feels (soundLowHz…soundHighHz, 2nd-order Butterworth
    /// each side) and normalised by its own peak envelope, so the cymbal is felt as its own
    /// waveform while a level still sets the peak (level/15), and no more power than a sine of
    /// that peak. Where the sound is silent (its 5 ms envelope below −80 dBFS) the fixed
    /// voiceCoilHz carrier takes over.
    bool voiceCoilSound = false;
    double soundLowHz = 40.0;      ///< 20…soundHighHz
    double soundHighHz = 400.0;    ///< soundLowHz…1000
};
inline constexpr TactorParams kDefaultTactorParams {};
/// InputError(source, 0, field, why) for a value out of range or a carrier at or above half
/// the sample rate.
void validate(const TactorParams& params, double sampleRate, const std::string& source);
/// The carrier of `model` at `level` once settled (Hz): the documented law of each model.
double carrierHz(const TactorParams& params, double level) noexcept;

/// Which motor each channel plays: channel c (0-based) plays motor index motor[c] (0-based;
/// -1 = a silent channel).
struct ChannelMap {
    std::array<int, kMaxChannels> motor {};
    int channels = 0;
    /// Channel k = motor k for `motors` motors (9, or 12 with the back motors).
    static ChannelMap identity(int motors) noexcept;
};
/// "1,2,3,…": one entry per channel, each a motor number 1..motors or "-" for a silent channel,
/// ranges allowed ("1-9", "10-12,-,-"). InputError("--tactor-map", 0, "", why) otherwise.
ChannelMap parseChannelMap(std::string_view text, int motors);
/// The map in the syntax parseChannelMap reads ("1-9" style ranges are written out: "1,2,…").
std::string channelMapText(const ChannelMap& map);

/// A calibration gain per channel (0…1; channel 1 first): rigs whose tactors differ attenuate the
/// strong ones to match the weakest (whose amplifier is turned up). Gains never raise a channel
/// above level/15 of full scale, so the safety bounds on the signal hold whatever the file says.
struct TactorGains {
    std::array<float, kMaxChannels> gain {};
    int count = 0;          ///< channels the file named (the rest are 1)
    std::string source;     ///< the file ("" = none)
    TactorGains() noexcept { gain.fill(1.0f); }
};
/// The gain file (docs/TACTORS.md): {"armadillo": "tactor-gains", "version": 1, "gain": [g1, g2, …]}
/// with 1…16 numbers in 0…1. InputError naming the file and line of what is wrong.
TactorGains parseTactorGains(std::string_view json, const std::string& source);
/// Reads and parses a gain file; IoError when it cannot be read.
TactorGains loadTactorGains(const std::string& path);

/// A rig as the app and the plugin keep it (docs/TACTORS.md): the model's name, the channel map's
/// text ("" = channel k plays motor k) and a gain file ("" = none), resolved for `motors` motors
/// (9, or 12 with the back motors) and at most `channels` output channels (0 = no limit). The
/// command line builds the same three from its options (Cli/TactorOptions.cpp).
struct TactorSetup {
    TactorParams params {};
    ChannelMap map {};
    TactorGains gains {};
};
/// InputError naming what is wrong (an unknown model, a bad map, more map channels than
/// `channels`, a gain file out of range or naming more channels than the map); IoError when the
/// gain file cannot be read.
TactorSetup resolveTactorSetup(std::string_view model, std::string_view mapText, const std::string& gainFile, int motors, int channels);

class TactorRenderer {
public:
    /// Not real-time: checks the settings (InputError), sizes the guard, clears all state.
    /// The gains must not name more channels than the map has (InputError naming the gain file).
    void prepare(const TactorParams& params, const ChannelMap& map, const TactorGains& gains, double sampleRate,
                 const tactile::SafetyParams& safety = tactile::kDefaultSafetyParams);
    /// New motor levels from now on; `dt` s since the previous call (the time the previous levels
    /// were on; the control step's dt). Real-time.
    void setLevels(const core::MotorLevels& levels, double dt) noexcept;
    /// Every channel silent from now on (stop, a stalled source); the guard's heat history stays.
    void allOff() noexcept;
    /// Every channel silent until the next setLevels() (a stalled source); the guard keeps charging
    /// what it last let through until then (conservative). Real-time.
    void mute() noexcept;
    /// Writes `n` samples into each of channels() buffers (overwriting). Real-time.
    void render(float* const* out, int n) noexcept;
    /// The scene's own sound (mono) for the next render(): its first `n` samples are the carrier
    /// of the next `n` rendered (voice-coil with voiceCoilSound; ignored otherwise). Not given,
    /// or shorter than a render: silence there (the fixed carrier takes over once the envelope
    /// has decayed). The pointer is used by that render() only. Real-time.
    void setSound(const float* mono, int n) noexcept
    {
        sound_ = mono;
        soundLeft_ = mono != nullptr ? std::max(0, n) : 0;
    }
    /// Whether the carrier is the scene's sound (voice-coil with voiceCoilSound).
    bool usesSound() const noexcept { return params_.model == TactorModel::VoiceCoil && params_.voiceCoilSound; }

    int channels() const noexcept { return map_.channels; }
    double sampleRate() const noexcept { return sampleRate_; }
    const ChannelMap& map() const noexcept { return map_; }
    const TactorParams& params() const noexcept { return params_; }
    /// What each channel carries now, as a level (the guard's output: the level, or the braking
    /// pulse's), channel 0 first.
    const core::MotorLevels& channelLevels() const noexcept { return guard_.lastOutput(); }
    /// How many channel levels the guard has lowered since prepare() (0 on an engine's levels).
    std::uint64_t limited() const noexcept { return limited_; }

private:
    struct Channel {
        double phase = 0.0;        ///< rad, continuous
        double hz = 0.0;           ///< the carrier's frequency now (erm: slewing)
        double targetHz = 0.0;
        float amplitude = 0.0f;    ///< peak of the drive (gain applied)
        float brakeAmplitude = 0.0f;
        int brakeLeft = 0;         ///< samples of braking pulse still to play
        std::uint8_t level = 0;    ///< the motor level asked last (before the guard)
    };
    TactorParams params_ {};
    ChannelMap map_ {};
    TactorGains gains_ {};
    double sampleRate_ = 48000.0;
    double slew_ = 1.0;            ///< erm: per-sample share of the way to the target frequency
    int brakeSamples_ = 0;
    int ratedLevel_ = core::kRatedLevel;
    std::array<Channel, kMaxChannels> ch_ {};
    tactile::SafetyStage guard_;
    std::uint64_t limited_ = 0;
    // The scene's sound as the carrier (usesSound()).
    core::Biquad highPass_, lowPass_;
    double envelope_ = 0.0, release_ = 0.0, fallbackPhase_ = 0.0, meanSquare_ = 0.0, powerSlew_ = 1.0, recent_ = 0.0, fastRelease_ = 0.0;
    const float* sound_ = nullptr;
    int soundLeft_ = 0;
    static constexpr int kCarrierBlock = 256;
    std::array<float, kCarrierBlock> carrier_ {};
    void renderWithSound(float* const* out, int n) noexcept;
};

/// The offline entry point (`render --tactile-wav`): rows of levels, each held until the next
/// row's time (the last one row-period more, or 5 ms), rendered by `renderer` (prepared) from the
/// first row's time on. A row starts at the first sample at or after its time; the renderer sees
/// each row's dt as the live output does, so a file and a live channel carry the same samples.
/// `sound` (mono, sample 0 = the first row's time, at the renderer's rate): the scene's own sound
/// for a voice-coil renderer with voiceCoilSound (`render --tactor-sound`); null = none.
core::AudioBuffer renderTactileRows(const std::vector<core::TactileRow>& rows, TactorRenderer& renderer, const std::vector<float>* sound = nullptr);

} // namespace armadillo::tactors
