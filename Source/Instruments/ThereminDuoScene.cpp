// "theremin-duo": a theremin played with both arms (docs/STAGE.md, thesis §5.2: "a second forearm
// controller on the other arm ... interact with the environment with both arms").
// - Right arm (ControlInput::arm): pitch from elevation, as the theremin (§3.5.1): semitones
//   e = range · (sin(el) − sin(−45°)) / (sin 45° − sin(−45°)) above `base`; volume from azimuth
//   relative to where the scene was entered (the theremin's quarter cosine, ±60°).
// - Left arm (ControlInput::leftArm): timbre from elevation (−45° a pure sine … +45° bright:
//   harmonic h at brightness^(h−1)/h, 8 harmonics), range from roll (−90° one octave … +90° three
//   octaves), articulation from its height: below −60° (the arm hanging) the note is stopped
//   (a 30 ms release), above it sounds.
// - With one arm the left arm's defaults hold: brightness 0.3, two octaves, sounding.
// - Tactile: on the right arm the pitch's place in the range (8 steps elbow → wrist, soft at the
//   rated level, the theremin's fret order); on the left arm (when worn) the brightness as the
//   level of the middle row (soft).
// Audio thread: additive oscillator, every target smoothed per sample; no allocation or lock.
#include "Instruments/Dsp.h"
#include "Instruments/Frets.h"
#include "Instruments/ParameterSet.h"
#include "Instruments/Scenes.h"
#include "Instruments/Theremin.h"
#include "Tactile/Patterns.h"
#include <algorithm>
#include <atomic>
#include <cmath>

namespace armadillo::instruments {
namespace {

enum DuoIndex : int { kBase, kLevel };

std::vector<core::ParamSpec> duoSpecs()
{
    return {
        {"theremin-duo.base", "Lowest pitch", 55.0f, 880.0f, 220.0f, "Hz", {}},
        {"theremin-duo.level", "Level", 0.0f, 1.0f, 0.4f, "", {}},
    };
}

constexpr int kHarmonics = 8;
constexpr double kDefaultBrightness = 0.3;
constexpr double kDefaultRange = 24.0;
constexpr double kStopBelowDeg = -60.0;

double sinDeg(double d) { return std::sin(d * 3.14159265358979323846 / 180.0); }

class ThereminDuoScene final : public core::Scene {
public:
    ThereminDuoScene() : params_(duoSpecs()) {}
    std::string_view name() const override { return "theremin-duo"; }
    std::vector<core::ParamSpec> parameters() const override { return params_.specs(); }
    void setParameter(int index, float value) noexcept override { params_.set(index, value); }
    bool producesAudio() const override { return true; }

    void prepare(const core::SceneConfig& config) override
    {
        fs_ = config.sampleRate > 0.0 ? config.sampleRate : 48000.0;
        pitch_.setTime(0.015, fs_);
        gain_.setTime(0.010, fs_);
        bright_.setTime(0.020, fs_);
        pitch_.value = params_.get(kBase);
        gain_.value = 0.0;
        bright_.value = kDefaultBrightness;
        phase_ = 0.0;
        reset();
    }

    void reset() override
    {
        entered_ = false;
        lastStep_ = -1;
        lastLeftLevel_ = -1.0f;
    }

    void control(const core::ControlInput& in, core::SceneOutput& out) override
    {
        if (!in.arm.valid) {
            gainTarget_.store(0.0);
            return;
        }
        const core::Pose& right = in.arm.features.pose;
        if (!entered_) {
            entered_ = true;
            entryAzimuth_ = right.azimuthDeg;
        }
        double brightness = kDefaultBrightness, range = kDefaultRange;
        bool sounding = true;
        if (in.leftArm.valid) {
            const core::Pose& left = in.leftArm.features.pose;
            brightness = std::clamp((left.elevationDeg + 45.0) / 90.0, 0.0, 1.0);
            range = 12.0 + 24.0 * std::clamp((left.rollDeg + 90.0) / 180.0, 0.0, 1.0);
            sounding = left.elevationDeg > kStopBelowDeg;
        }
        const double x = (sinDeg(std::clamp(right.elevationDeg, -90.0, 90.0)) - sinDeg(-45.0)) / (sinDeg(45.0) - sinDeg(-45.0));
        const double semitones = range * x;
        pitchTarget_.store(params_.get(kBase) * std::exp2(semitones / 12.0));
        const double volume = thereminVolume(core::wrapDeg180(right.azimuthDeg - entryAzimuth_), 60.0);
        gainTarget_.store(sounding ? volume : 0.0);
        brightTarget_.store(brightness);

        // Right arm: the pitch's place in the range, 8 steps (fret order: elbow → wrist).
        const int step = std::clamp(static_cast<int>(std::floor(8.0 * std::clamp(x, 0.0, 0.999))), 0, 7);
        if (step != lastStep_) {
            out.motors.clearLevels();
            lastStep_ = step;
        }
        out.motors.setSoftLevel(fretMotor(step), sounding && volume > 0.05 ? static_cast<float>(core::kRatedLevel) : 0.0f);
        // Left arm (when worn): brightness as the middle row's level.
        if (out.leftMotors) {
            const auto level = static_cast<float>(std::round(core::kRatedLevel * brightness * 2.0) / 2.0);
            if (level != lastLeftLevel_) {
                for (int c = 0; c < 3; ++c) out.leftMotors->setSoftLevel(core::motorIndex(1, c), level);
                lastLeftLevel_ = level;
            }
        }
    }

    void renderAudio(float* left, float* right, int n) noexcept override
    {
        const double pitchTarget = pitchTarget_.load(), gainTarget = gainTarget_.load(), brightTarget = brightTarget_.load();
        const double level = params_.get(kLevel);
        if (gainTarget <= 0.0 && gain_.value < 1e-6) return;   // silent: adds nothing
        for (int i = 0; i < n; ++i) {
            const double f = pitch_.next(pitchTarget);
            const double g = gain_.next(gainTarget);
            const double b = bright_.next(brightTarget);
            phase_ = dsp::wrapPhase(phase_ + f / fs_);
            double y = 0.0, norm = 0.0, a = 1.0;
            for (int h = 1; h <= kHarmonics; ++h) {
                if (h * f > 0.45 * fs_) break;
                const double amp = a / h;
                y += amp * dsp::SineTable::at(h * phase_);
                norm += amp;
                a *= b;
            }
            const auto v = static_cast<float>(level * g * y / std::max(norm, 1e-9));
            left[i] += v;
            right[i] += v;
        }
    }

private:
    ParameterSet params_;
    double fs_ = 48000.0;
    dsp::OnePole pitch_ {}, gain_ {}, bright_ {};
    double phase_ = 0.0;
    std::atomic<double> pitchTarget_ {220.0}, gainTarget_ {0.0}, brightTarget_ {kDefaultBrightness};
    bool entered_ = false;
    double entryAzimuth_ = 0.0;
    int lastStep_ = -1;
    float lastLeftLevel_ = -1.0f;
};

} // namespace

std::unique_ptr<core::Scene> makeThereminDuoScene() { return std::make_unique<ThereminDuoScene>(); }

} // namespace armadillo::instruments
