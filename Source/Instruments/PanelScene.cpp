// The virtual control panel (thesis §3.4): 18 knobs in two levels (30° above and below the
// horizon; in between the last level holds), nine positions dialled by horizontal movement and
// laid out like a phone keypad on the 3×3 motors. The knob under the arm pulses — fading in on
// the upper level, fading out on the lower — a level change jolts, a quick roll selects: a
// "select" event (knob 0..17) and the knob's sample (here a short synthesised tone per knob).
#include "Core/Pose.h"
#include "Core/SpscQueue.h"
#include "Instruments/ArmMotion.h"
#include "Instruments/Dsp.h"
#include "Instruments/ParameterSet.h"
#include "Instruments/QuickRoll.h"
#include "Instruments/Scenes.h"
#include "Tactile/Hysteresis.h"
#include <cmath>

namespace armadillo::instruments {
namespace {

enum PanelIndex : int { kWidth, kLevelAngle, kRollRate, kMotorLevel, kVolume };

std::vector<core::ParamSpec> panelSpecs()
{
    return {
        {"panel.width", "Knob width", 5.0f, 40.0f, 15.0f, "deg", {}},
        {"panel.levelAngle", "Level elevation", 10.0f, 60.0f, 30.0f, "deg", {}},
        {"panel.rollRate", "Select roll rate", 1.0f, 10.0f, 3.0f, "rad/s", {}},
        {"panel.motorLevel", "Knob pulse level", 0.0f, 15.0f, 5.0f, "", {}},
        {"panel.volume", "Sample volume", 0.0f, 1.0f, 0.5f, "", {}},
    };
}

/// Knob → sample pitch: A minor pentatonic upward from A3, lower level first.
double knobFrequencyHz(int knob)
{
    static constexpr int steps[] = {0, 3, 5, 7, 10};
    return 220.0 * std::exp2((12.0 * (knob / 5) + steps[knob % 5]) / 12.0);
}

class PanelScene final : public core::Scene {
public:
    PanelScene() : params_(panelSpecs()) {}
    std::string_view name() const override { return "panel"; }
    std::vector<core::ParamSpec> parameters() const override { return params_.specs(); }
    void setParameter(int index, float value) noexcept override { params_.set(index, value); }
    bool producesAudio() const override { return true; }

    void prepare(const core::SceneConfig& config) override
    {
        sampleRate_ = config.sampleRate > 0.0 ? config.sampleRate : 48000.0;
        int drop;
        while (selections_.pop(drop)) {}
        blipAmplitude_ = 0.0;
        decayMul_ = std::exp(-1.0 / (0.35 * sampleRate_));
        reset();
    }

    void reset() override
    {
        haveReference_ = false;
        knob_ = -1;
        values_ = {};   // no knob under the arm, none selected
        upperKnown_ = false;
        roll_.reset();
        motion_.reset();
    }

    void control(const core::ControlInput& in, core::SceneOutput& out) override
    {
        clock_ += in.dt;
        if (!in.arm.valid) return;
        const core::Pose& pose = in.arm.features.pose;
        const Eigen::Vector3d omega = motion_.update(in.arm, in.dt);

        // Level: hysteresis between ±levelAngle; the band in between keeps the last level.
        const double angle = params_.get(kLevelAngle);
        upper_.setThresholds(angle, -angle);
        if (!upperKnown_) {
            upper_.reset(pose.elevationDeg >= 0.0);
            upperKnown_ = true;
        }
        const bool wasUpper = upper_.on();
        const bool upper = upper_.update(pose.elevationDeg);
        if (upper != wasUpper) {
            core::PatternRequest jolt;
            jolt.kind = core::PatternKind::Jolt;
            jolt.level = 10.0f;
            jolt.duration = 0.1;
            jolt.voice = 1;
            out.motors.trigger(jolt);
            out.events.emit("level", upper ? 1.0f : 0.0f);
        }

        // Dial: nine positions across the heading where the scene was entered (the middle one).
        if (!haveReference_) {
            referenceAzimuth_ = pose.azimuthDeg;
            haveReference_ = true;
        }
        const double width = params_.get(kWidth);
        const double offset = core::wrapDeg180(pose.azimuthDeg - referenceAzimuth_) / width + 4.5; // in knob widths
        int knob = knob_;
        // Sector hysteresis: leave the current knob only 10% of a width past its edge.
        if (knob < 0 || offset < knob - 0.1 || offset > knob + 1.1) knob = std::clamp(static_cast<int>(std::floor(offset)), 0, 8);
        const bool knobChanged = knob != knob_ || upper != wasUpper;
        knob_ = knob;
        values_.panelKnob = static_cast<float>(knob + (upper ? 0 : 9));   // the knob a roll would select now
        values_.panelLevel = upper ? 1.0f : 0.0f;

        // The knob under the arm pulses, fading in (upper) or out (lower), every 0.5 s.
        if (knobChanged || clock_ >= nextPulse_) {
            core::PatternRequest pulse;
            pulse.kind = upper ? core::PatternKind::FadeInPulse : core::PatternKind::FadeOutPulse;
            pulse.motors = static_cast<std::uint16_t>(1u << knob);   // keypad order = motor order
            pulse.level = static_cast<float>(params_.get(kMotorLevel));
            pulse.duration = 0.35;
            pulse.voice = 0;
            pulse.soft = true;   // fades both ways: the rise or the fall is the point, no spike
            out.motors.trigger(pulse);
            nextPulse_ = clock_ + 0.5;
        }

        QuickRollParams rp;
        rp.enterRate = params_.get(kRollRate);
        rp.exitRate = rp.enterRate / 3.0;
        if (roll_.update(omega, rp)) {
            const int selected = knob + (upper ? 0 : 9);
            out.events.emit("select", static_cast<float>(selected));
            values_.panelSelected = static_cast<float>(selected);
            core::PatternRequest accent;
            accent.kind = core::PatternKind::Accent;
            accent.motors = static_cast<std::uint16_t>(1u << knob);
            accent.level = 12.0f;
            accent.voice = 2;
            out.motors.trigger(accent);
            selections_.push(selected);
        }
    }

    /// The panel's state for mappings (Core/Scene.h SceneValues: panel.knob, panel.level,
    /// panel.selected): the panel as a remote (docs/MAPPING.md, docs/MQTT.md).
    core::SceneValues values() const noexcept override { return values_; }

    void renderAudio(float* left, float* right, int numSamples) noexcept override
    {
        int knob;
        while (selections_.pop(knob)) {
            blipIncrement_ = knobFrequencyHz(knob) / sampleRate_;
            blipPhase_ = 0.0;
            blipAmplitude_ = params_.get(kVolume);
        }
        if (blipAmplitude_ <= 0.0) return;
        for (int i = 0; i < numSamples; ++i) {
            // A plucked tone: fundamental and a quieter octave, exponential decay.
            const double s = blipAmplitude_ * (dsp::SineTable::at(blipPhase_) + 0.3 * dsp::SineTable::at(2.0 * blipPhase_)) / 1.3;
            blipPhase_ = dsp::wrapPhase(blipPhase_ + blipIncrement_);
            blipAmplitude_ *= decayMul_;
            if (left) left[i] += static_cast<float>(s);
            if (right) right[i] += static_cast<float>(s);
        }
        if (blipAmplitude_ < 1e-5) blipAmplitude_ = 0.0;
    }

private:
    ParameterSet params_;
    double sampleRate_ = 48000.0;
    // Control thread.
    ArmMotion motion_ {};
    QuickRoll roll_ {};
    tactile::Hysteresis upper_ {30.0, -30.0};
    bool upperKnown_ = false;
    bool haveReference_ = false;
    double referenceAzimuth_ = 0.0;
    int knob_ = -1;
    core::SceneValues values_ {};
    double clock_ = 0.0, nextPulse_ = 0.0;
    // Control → audio.
    core::SpscQueue<int, 16> selections_;
    // Audio thread.
    double blipPhase_ = 0.0, blipIncrement_ = 0.0, blipAmplitude_ = 0.0, decayMul_ = 0.0;
};

} // namespace

std::unique_ptr<core::Scene> makePanelScene() { return std::make_unique<PanelScene>(); }

} // namespace armadillo::instruments
