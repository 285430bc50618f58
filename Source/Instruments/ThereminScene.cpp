// The fretted theremin scene (thesis §3.5). Control thread (real-time, Core/Scene.h): elevation →
// pitch, azimuth → volume, pitch → felt fret. Audio thread: one sine, frequency and amplitude smoothed per sample so
// 200 Hz control steps never reach the output as zipper noise.
#include "Core/Pose.h"
#include "Instruments/Dsp.h"
#include "Instruments/Frets.h"
#include "Instruments/ParameterSet.h"
#include "Instruments/Scenes.h"
#include "Instruments/Theremin.h"
#include <atomic>
#include <cmath>
#include <limits>

namespace armadillo::instruments {
namespace {

enum ThereminIndex : int { kBase, kRange, kBottom, kTop, kVolumeWidth, kLevel, kGlide, kSnap, kScale, kRoot, kFretAdjust, kFretLevel };

std::vector<core::ParamSpec> thereminSpecs()
{
    return {
        {thereminParam::kBase, "Base frequency", 27.5f, 1760.0f, 220.0f, "Hz", {}},
        {thereminParam::kRange, "Range", 1.0f, 48.0f, 12.0f, "semitones", {}},
        {thereminParam::kBottom, "Bottom elevation", -90.0f, 89.0f, -45.0f, "deg", {}},
        {thereminParam::kTop, "Top elevation", -89.0f, 90.0f, 45.0f, "deg", {}},
        {thereminParam::kVolumeWidth, "Volume width", 5.0f, 180.0f, 60.0f, "deg", {}},
        {thereminParam::kLevel, "Level", 0.0f, 1.0f, 0.5f, "", {}},
        {thereminParam::kGlide, "Glide", 0.0f, 1000.0f, 20.0f, "ms", {}},
        {thereminParam::kSnap, "Pitch snapping", 0.0f, 100.0f, 0.0f, "%", {}},
        {thereminParam::kScale, "Scale", 0.0f, static_cast<float>(fretScaleNames().size() - 1), 0.0f, "", fretScaleNames()},
        {thereminParam::kRoot, "Root", 0.0f, 11.0f, 0.0f, "", pitchClassNames()},
        {thereminParam::kFretAdjust, "Fret approach adjustment", 0.0f, 2.5f, 1.0f, "%", {}},
        {thereminParam::kFretLevel, "Fret vibration level", 0.0f, 15.0f, 5.0f, "", {}},
    };
}

/// What the fret layout depends on; recomputed (control thread) only when one of these changes.
struct FretLayout {
    PitchMapParams map {};
    FretScale scale = FretScale::Major;
    int root = 0;
    double adjust = 0.01;   ///< fraction
    bool operator==(const FretLayout& o) const noexcept
    {
        return map.baseHz == o.map.baseHz && map.rangeSemitones == o.map.rangeSemitones
            && map.bottomElevationDeg == o.map.bottomElevationDeg && map.topElevationDeg == o.map.topElevationDeg
            && scale == o.scale && root == o.root && adjust == o.adjust;
    }
};

class ThereminScene final : public core::Scene {
public:
    ThereminScene() : params_(thereminSpecs()) {}

    std::string_view name() const override { return "theremin"; }
    std::vector<core::ParamSpec> parameters() const override { return params_.specs(); }
    bool producesAudio() const override { return true; }
    void setParameter(int index, float value) noexcept override { params_.set(index, value); }

    void prepare(const core::SceneConfig& config) override
    {
        sampleRate_ = config.sampleRate > 0.0 ? config.sampleRate : 48000.0;
        phase_ = 0.0;
        increment_.value = 0.0;
        amplitude_.value = 0.0;
        amplitude_.setTime(0.010, sampleRate_);   // 10 ms: fast enough to play, slow enough not to click
        targetHz_.store(0.0, std::memory_order_relaxed);
        targetAmplitude_.store(0.0, std::memory_order_relaxed);
        haveLayout_ = false;
        reset();
    }

    void reset() override
    {
        haveReference_ = false;
        frets_.reset();
        clearPending_ = true;   // the canvas is only reachable from control(): clear there
    }

    void control(const core::ControlInput& in, core::SceneOutput& out) override
    {
        const FretLayout layout = currentLayout();
        if (!haveLayout_ || !(layout == layout_)) {
            layout_ = layout;
            haveLayout_ = true;
            // Fixed-size lists: automating scale, root, base or range must not allocate here.
            FretList hz = fretSemitonesFixed(layout.map, layout.scale, layout.root);
            for (int i = 0; i < hz.count; ++i)
                hz.values[static_cast<std::size_t>(i)] = frequencyForSemitones(layout.map, hz.values[static_cast<std::size_t>(i)]);
            frets_.configure(hz, layout.adjust);
        }

        if (clearPending_) {
            out.motors.clearLevels();
            shownFret_ = -1;
            lastEmittedFret_ = -1;
            clearPending_ = false;
        }
        const core::ArmFeatures& f = in.arm.features;
        if (!in.arm.valid || !std::isfinite(f.axis.y()) || !std::isfinite(f.pose.azimuthDeg)) {
            targetAmplitude_.store(0.0, std::memory_order_relaxed);
            showFret(-1, out);
            values_.pitch = std::numeric_limits<float>::quiet_NaN();
            return;
        }

        const double axisY = std::clamp(f.axis.y(), -1.0, 1.0);
        // Clamped so that any parameter combination (e.g. bottom = top) stays a playable pitch.
        const double semis = std::clamp(semitonesForAxisY(layout.map, axisY), -120.0, 120.0);
        const double controllerHz = frequencyForSemitones(layout.map, semis);
        const double snap = params_.get(kSnap) / 100.0;
        const double playedHz = std::clamp(frequencyForSemitones(layout.map, snapToScale(semis, layout.map, layout.scale, layout.root, snap)),
                                           kMinHz, std::min(kMaxHz, 0.45 * sampleRate_));

        if (!haveReference_) {
            referenceAzimuthDeg_ = f.pose.azimuthDeg;
            haveReference_ = true;
        }
        const double volume = thereminVolume(core::wrapDeg180(f.pose.azimuthDeg - referenceAzimuthDeg_), params_.get(kVolumeWidth));

        targetHz_.store(playedHz, std::memory_order_relaxed);
        targetAmplitude_.store(volume * params_.get(kLevel), std::memory_order_relaxed);
        values_.pitch = static_cast<float>(69.0 + 12.0 * std::log2(playedHz / 440.0));

        // Frets follow the controller's pitch (where the arm is), not the snapped sound.
        const int fret = frets_.update(controllerHz);
        showFret(fret, out);
        if (fret >= 0) values_.fret = static_cast<float>(fret);
        if (fret != lastEmittedFret_ && fret >= 0) {
            out.events.emit("fret", static_cast<float>(fret));
            lastEmittedFret_ = fret;
        }
    }

    /// The sounding pitch (MIDI note number) and the latest fret, for mappings (Core/Scene.h).
    core::SceneValues values() const noexcept override { return values_; }

    void renderAudio(float* left, float* right, int numSamples) noexcept override
    {
        const double targetAmp = targetAmplitude_.load(std::memory_order_relaxed);
        const double targetInc = targetHz_.load(std::memory_order_relaxed) / sampleRate_;
        if (targetAmp <= 0.0 && amplitude_.value <= 0.0) return;   // silent: adds nothing
        // A note that starts from silence starts at its pitch; glide only between sounding pitches.
        if (amplitude_.value <= 1e-6) increment_.value = targetInc;
        increment_.setTime(params_.get(kGlide) * 1e-3, sampleRate_);
        double phase = phase_;
        for (int i = 0; i < numSamples; ++i) {
            const double inc = increment_.next(targetInc);
            const double amp = amplitude_.next(targetAmp);
            const auto s = static_cast<float>(amp * dsp::SineTable::at(phase));
            phase = dsp::wrapPhase(phase + inc);
            if (left) left[i] += s;
            if (right) right[i] += s;
        }
        phase_ = phase;
        if (targetAmp <= 0.0 && amplitude_.value < 1e-6) amplitude_.value = 0.0;
    }

private:
    FretLayout currentLayout() const noexcept
    {
        FretLayout l;
        l.map.baseHz = params_.get(kBase);
        l.map.rangeSemitones = params_.get(kRange);
        l.map.bottomElevationDeg = params_.get(kBottom);
        l.map.topElevationDeg = params_.get(kTop);
        l.scale = static_cast<FretScale>(static_cast<int>(params_.get(kScale)));
        l.root = static_cast<int>(params_.get(kRoot));
        l.adjust = params_.get(kFretAdjust) / 100.0;
        return l;
    }

    void showFret(int fret, core::SceneOutput& out)
    {
        const float level = params_.get(kFretLevel);
        if (fret == shownFret_ && level == shownLevel_) return;
        if (shownFret_ >= 0 && fret != shownFret_) out.motors.setLevel(fretMotor(shownFret_), 0.0f);
        if (fret >= 0) out.motors.setLevel(fretMotor(fret), level);
        shownFret_ = fret;
        shownLevel_ = level;
    }

    static constexpr double kMinHz = 5.0, kMaxHz = 20000.0;   ///< played pitch limits
    ParameterSet params_;
    double sampleRate_ = 48000.0;

    // Control thread state.
    FretLayout layout_ {};
    bool haveLayout_ = false;
    FretTracker frets_ {};
    int shownFret_ = -1;
    float shownLevel_ = -1.0f;
    int lastEmittedFret_ = -1;
    bool clearPending_ = true;
    bool haveReference_ = false;
    double referenceAzimuthDeg_ = 0.0;
    core::SceneValues values_ {};

    // Control → audio: latest targets (single words, lock-free).
    std::atomic<double> targetHz_ {0.0};
    std::atomic<double> targetAmplitude_ {0.0};
    static_assert(std::atomic<double>::is_always_lock_free, "targets must cross threads without locks");

    // Audio thread state.
    double phase_ = 0.0;         ///< cycles
    dsp::OnePole increment_ {};  ///< cycles per sample
    dsp::OnePole amplitude_ {};  ///< linear gain
};

} // namespace

std::unique_ptr<core::Scene> makeThereminScene() { return std::make_unique<ThereminScene>(); }

} // namespace armadillo::instruments
