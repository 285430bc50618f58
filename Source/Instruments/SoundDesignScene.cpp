// Gesture-based sound design (thesis §3.7): elevation and azimuth move through two sound
// parameters at a time; a quick roll selects the sound, "zooms in" (the next two parameters
// take over, the chosen ones stay) and a jolt confirms. After the last page the next roll starts
// a new sound from the first page. Every selection is an event ("select" = the page chosen,
// "param" values follow), so the session can be logged from the gesture stream.
#include "Core/Pose.h"
#include "Instruments/ArmMotion.h"
#include "Instruments/Dsp.h"
#include "Instruments/ParameterSet.h"
#include "Instruments/QuickRoll.h"
#include "Instruments/Scenes.h"
#include <array>
#include <atomic>
#include <cmath>

namespace armadillo::instruments {
namespace {

enum SoundDesignIndex : int { kLevel, kSpan, kRollRate };

std::vector<core::ParamSpec> soundDesignSpecs()
{
    return {
        {"sound-design.level", "Level", 0.0f, 1.0f, 0.3f, "", {}},
        {"sound-design.span", "Gesture span", 20.0f, 90.0f, 60.0f, "deg", {}},
        {"sound-design.rollRate", "Select roll rate", 1.0f, 10.0f, 3.0f, "rad/s", {}},
    };
}

/// The designed sound: an FM tone with vibrato and tremolo. Units in the comments.
struct FmSound {
    double pitchHz = 220.0;        ///< page 0, elevation: 110..880 Hz (log)
    double index = 1.0;            ///< page 0, azimuth: FM index 0..6 rad
    double harmonicity = 1.0;      ///< page 1, elevation: modulator/carrier 0.5..4
    double vibratoSemis = 0.0;     ///< page 1, azimuth: 0..1 semitone
    double tremoloHz = 0.0;        ///< page 2, elevation: 0..12 Hz amplitude pulsing
    double tremoloDepth = 0.0;     ///< page 2, azimuth: 0..1
};
constexpr int kPages = 3;

class SoundDesignScene final : public core::Scene {
public:
    SoundDesignScene() : params_(soundDesignSpecs()) {}
    std::string_view name() const override { return "sound-design"; }
    std::vector<core::ParamSpec> parameters() const override { return params_.specs(); }
    void setParameter(int index, float value) noexcept override { params_.set(index, value); }
    bool producesAudio() const override { return true; }

    void prepare(const core::SceneConfig& config) override
    {
        sampleRate_ = config.sampleRate > 0.0 ? config.sampleRate : 48000.0;
        for (auto* s : {&pitch_, &index_, &harmonicity_, &vibrato_, &tremoloHz_, &tremoloDepth_, &amplitude_})
            s->setTime(0.02, sampleRate_);
        publish(FmSound {}, 0.0);
        pitch_.value = 220.0;
        harmonicity_.value = 1.0;
        reset();
    }

    void reset() override
    {
        page_ = 0;
        chosen_ = FmSound {};
        haveReference_ = false;
        roll_.reset();
        motion_.reset();
    }

    void control(const core::ControlInput& in, core::SceneOutput& out) override
    {
        if (!in.arm.valid) {
            publish(chosen_, 0.0);
            return;
        }
        const core::Pose& pose = in.arm.features.pose;
        const Eigen::Vector3d omega = motion_.update(in.arm, in.dt);
        if (!haveReference_) {
            referenceAzimuth_ = pose.azimuthDeg;
            haveReference_ = true;
        }
        const double span = params_.get(kSpan);
        // u: elevation, v: azimuth offset, both 0..1 across ±span.
        const double u = std::clamp(0.5 + 0.5 * pose.elevationDeg / span, 0.0, 1.0);
        const double v = std::clamp(0.5 + 0.5 * core::wrapDeg180(pose.azimuthDeg - referenceAzimuth_) / span, 0.0, 1.0);
        FmSound sound = chosen_;
        switch (page_) {
        case 0:
            sound.pitchHz = 110.0 * std::exp2(3.0 * u);
            sound.index = 6.0 * v;
            break;
        case 1:
            sound.harmonicity = 0.5 + 3.5 * u;
            sound.vibratoSemis = v;
            break;
        default:
            sound.tremoloHz = 12.0 * u;
            sound.tremoloDepth = v;
            break;
        }
        publish(sound, params_.get(kLevel));

        QuickRollParams rp;
        rp.enterRate = params_.get(kRollRate);
        rp.exitRate = rp.enterRate / 3.0;
        if (roll_.update(omega, rp)) {
            out.events.emit("select", static_cast<float>(page_));
            out.events.emit("param", static_cast<float>(u));
            out.events.emit("param", static_cast<float>(v));
            core::PatternRequest jolt;
            jolt.kind = core::PatternKind::Jolt;
            jolt.level = 10.0f;
            jolt.duration = 0.1;
            out.motors.trigger(jolt);
            // Zoom in: keep what was chosen, move on to the next two parameters, re-centre the
            // heading so the new page starts from the middle. After the last page: a new sound.
            chosen_ = sound;
            page_ = (page_ + 1) % kPages;
            if (page_ == 0) chosen_ = FmSound {};
            referenceAzimuth_ = pose.azimuthDeg;
        }
    }

    void renderAudio(float* left, float* right, int numSamples) noexcept override
    {
        const double targetAmp = target_[6].load(std::memory_order_relaxed);
        if (targetAmp <= 0.0 && amplitude_.value <= 0.0) return;
        double t[6];
        for (int i = 0; i < 6; ++i) t[i] = target_[static_cast<std::size_t>(i)].load(std::memory_order_relaxed);
        constexpr double kInvTwoPi = 1.0 / dsp::kTwoPi;
        for (int i = 0; i < numSamples; ++i) {
            const double pitch = pitch_.next(t[0]);
            const double index = index_.next(t[1]);
            const double h = harmonicity_.next(t[2]);
            const double vib = vibrato_.next(t[3]);
            const double tremHz = tremoloHz_.next(t[4]);
            const double tremDepth = tremoloDepth_.next(t[5]);
            const double amp = amplitude_.next(targetAmp);
            const double f = pitch * (1.0 + 0.0578 * vib * dsp::SineTable::at(vibratoPhase_));   // ≈ 2^(vib·sin/12)
            vibratoPhase_ = dsp::wrapPhase(vibratoPhase_ + 5.5 / sampleRate_);
            tremoloPhase_ = dsp::wrapPhase(tremoloPhase_ + tremHz / sampleRate_);
            const double trem = 1.0 - tremDepth * (0.5 + 0.5 * dsp::SineTable::at(tremoloPhase_));
            const double mod = index * kInvTwoPi * dsp::SineTable::at(modPhase_);
            const double s = amp * trem * dsp::SineTable::at(carrierPhase_ + mod);
            carrierPhase_ = dsp::wrapPhase(carrierPhase_ + f / sampleRate_);
            modPhase_ = dsp::wrapPhase(modPhase_ + f * h / sampleRate_);
            if (left) left[i] += static_cast<float>(s);
            if (right) right[i] += static_cast<float>(s);
        }
        if (targetAmp <= 0.0 && amplitude_.value < 1e-6) amplitude_.value = 0.0;
    }

private:
    void publish(const FmSound& s, double amplitude) noexcept
    {
        const double values[7] = {s.pitchHz, s.index, s.harmonicity, s.vibratoSemis, s.tremoloHz, s.tremoloDepth, amplitude};
        for (std::size_t i = 0; i < 7; ++i) target_[i].store(values[i], std::memory_order_relaxed);
    }

    ParameterSet params_;
    double sampleRate_ = 48000.0;
    // Control thread.
    ArmMotion motion_ {};
    QuickRoll roll_ {};
    int page_ = 0;
    FmSound chosen_ {};
    bool haveReference_ = false;
    double referenceAzimuth_ = 0.0;
    // Control → audio: latest targets, one atomic each (smoothed per sample on the audio side).
    std::array<std::atomic<double>, 7> target_ {};
    // Audio thread.
    dsp::OnePole pitch_ {}, index_ {}, harmonicity_ {}, vibrato_ {}, tremoloHz_ {}, tremoloDepth_ {}, amplitude_ {};
    double carrierPhase_ = 0.0, modPhase_ = 0.0, vibratoPhase_ = 0.0, tremoloPhase_ = 0.0;
};

} // namespace

std::unique_ptr<core::Scene> makeSoundDesignScene() { return std::make_unique<SoundDesignScene>(); }

} // namespace armadillo::instruments
