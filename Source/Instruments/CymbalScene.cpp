// The virtual crash cymbal scene (thesis §3.6). Control thread: strike / damp / brush gestures,
// tactile environment, per-strike random choices (seeded, so renders repeat). Audio thread:
// up to two crash voices, each a pair of noise fragments forced into a crash envelope, then an
// FM tail whose modulation index and harmonicity follow movement inside the cymbal.
#include "Core/SpscQueue.h"
#include "Instruments/ArmMotion.h"
#include "Instruments/Cymbal.h"
#include "Instruments/Dsp.h"
#include "Instruments/ParameterSet.h"
#include "Instruments/Scenes.h"
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

namespace armadillo::instruments {
namespace {

enum CymbalIndex : int { kStrikeSpeed, kArm, kSurface, kLevel, kDamp, kIdle, kBrush, kTail, kFileMix };

std::vector<core::ParamSpec> cymbalSpecs()
{
    return {
        {cymbalParam::kStrikeSpeed, "Strike speed", 30.0f, 1000.0f, 150.0f, "deg/s", {}},
        {cymbalParam::kArm, "Raise to arm", 0.0f, 60.0f, 5.0f, "deg", {}},
        {cymbalParam::kSurface, "Surface elevation", -60.0f, 60.0f, 0.0f, "deg", {}},
        {cymbalParam::kLevel, "Level", 0.0f, 1.0f, 0.7f, "", {}},
        {cymbalParam::kDamp, "Damping time", 0.05f, 3.0f, 0.4f, "s", {}},
        {cymbalParam::kIdle, "Idle vibration", 0.0f, 5.0f, 1.0f, "", {}},
        {cymbalParam::kBrush, "Movement vibration", 0.0f, 10.0f, 3.0f, "levels per rad/s", {}},
        {cymbalParam::kTail, "FM tail level", 0.0f, 1.0f, 0.5f, "", {}},
        {cymbalParam::kFileMix, "User audio share", 0.0f, 100.0f, 50.0f, "%", {}},
    };
}

/// Control → audio: one strike or one damp. Trivially copyable (crosses in an SpscQueue).
struct CymbalCommand {
    enum Type : int { Strike, Damp } type = Strike;
    double gain = 1.0;            ///< strike loudness 0..1
    int fragmentA = 0;            ///< bank index (screened, crash-like)
    int fragmentB = 0;            ///< bank index, or −1 = the user's audio
    double offsetA = 0.0;         ///< samples into the source
    double offsetB = 0.0;
    double rateA = 1.0;           ///< playback rate (varispeed)
    double rateB = 1.0;
    double panA = 0.5;            ///< 0 = left, 1 = right
    double panB = 0.5;
    double carrierHz = 300.0;     ///< FM tail carrier
    double harmonicity = 1.4;     ///< modulator / carrier frequency ratio
    double index = 2.0;           ///< FM (phase-modulation) index, radians
    double dampSeconds = 0.4;     ///< damp: time to fall 60 dB
};

/// Crash envelope of thesis Fig. 3-31 (its shape did not survive extraction; this is the
/// classic crash shape): a 2 ms attack, a fast drop (τ 0.18 s) into a long decay (τ 1.3 s),
/// faded out over the fragment's last 0.5 s.
struct CrashEnvelopeParams {
    double attackS = 0.002;
    double fastTauS = 0.18;
    double slowTauS = 1.3;
    double fastShare = 0.55;
    double lengthS = 4.0;
    double fadeS = 0.5;
    double tailRiseTauS = 0.8;    ///< the FM tail swells in as the crash dies away
    double tailDecayTauS = 2.5;
    double tailShare = 0.35;      ///< tail peak relative to the crash's
};
inline constexpr CrashEnvelopeParams kCrashEnvelope {};

struct FragmentReader {
    const float* data = nullptr;
    std::size_t length = 0;
    double position = 0.0;   ///< samples
    double rate = 1.0;       ///< samples per output sample
    double gainL = 0.0, gainR = 0.0;

    double next() noexcept
    {
        if (!data || position >= static_cast<double>(length - 1)) return 0.0;
        const auto k = static_cast<std::size_t>(position);
        const double frac = position - static_cast<double>(k);
        const double a = data[k], b = data[k + 1];
        position += rate;
        return a + frac * (b - a);
    }
};

struct CrashVoice {
    bool active = false;
    FragmentReader a {}, b {};
    double gain = 0.0;
    long age = 0, length = 0, fadeStart = 0;       ///< samples
    double attack = 0.0, attackStep = 1.0;
    double fast = 0.0, fastMul = 0.0, slow = 0.0, slowMul = 0.0;
    double riseState = 1.0, riseMul = 0.0, tailDecay = 0.0, tailDecayMul = 0.0, tailGain = 0.0;
    double carrierPhaseL = 0.0, carrierPhaseR = 0.0, modPhase = 0.0, lfoPhase = 0.0;
    double carrierInc = 0.0, lfoInc = 0.0;         ///< cycles per sample
    double harmonicity = 1.4, index = 2.0;
    dsp::OnePole indexSmooth {}, harmonicitySmooth {};
    double damp = 1.0, dampMul = 1.0;
};

constexpr int kVoices = 2;
/// Output scale: two fragments, the tail and an overlapping older voice at full level and the
/// hardest strike stay inside full scale (property-tested).
constexpr double kHeadroom = 0.75;

class CymbalScene final : public CymbalInstrument {
public:
    CymbalScene() : params_(cymbalSpecs()) {}

    std::string_view name() const override { return "cymbal"; }
    std::vector<core::ParamSpec> parameters() const override { return params_.specs(); }
    bool producesAudio() const override { return true; }
    void setParameter(int index, float value) noexcept override { params_.set(index, value); }
    void setUserAudio(const core::AudioBuffer& audio) override { userSource_ = audio; }

    void prepare(const core::SceneConfig& config) override
    {
        sampleRate_ = config.sampleRate > 0.0 ? config.sampleRate : 48000.0;
        if (!config.audioFile.empty()) userSource_ = core::readWav(config.audioFile); // InputError names a bad file
        bank_ = buildCrashBank(sampleRate_, config.seed);
        bank_.user = prepareUserAudio(userSource_, sampleRate_);
        rng_.seed(config.seed);
        CymbalCommand drop;
        while (commands_.pop(drop)) {}
        for (auto& v : voices_) v = CrashVoice {};
        indexBoost_.store(0.0, std::memory_order_relaxed);
        harmonicityShift_.store(0.0, std::memory_order_relaxed);
        reset();
    }

    void reset() override
    {
        gesture_.reset();
        motion_.reset();
        ringingUntil_ = -1.0;
        std::fill(shown_.begin(), shown_.end(), 0.0f);
        gearOn_ = false;
        gearLevel_ = 0.0f;
        clearOnNextControl_ = true;
    }

    void control(const core::ControlInput& in, core::SceneOutput& out) override
    {
        const double dt = std::clamp(in.dt, 1e-4, 0.1);
        clock_ += dt;
        if (clearOnNextControl_) {
            out.motors.clearLevels();
            out.motors.stopVoice(kGearVoice);
            clearOnNextControl_ = false;
        }
        if (!in.arm.valid) {
            leaveInside(out);
            indexBoost_.store(0.0, std::memory_order_relaxed);
            return;
        }

        CymbalGestureParams gp;
        gp.surfaceDeg = params_.get(kSurface);
        gp.armDeg = params_.get(kArm);
        gp.strikeSpeedDegPerS = params_.get(kStrikeSpeed);
        gesture_.setParams(gp);

        const Eigen::Quaterniond q = in.arm.q.normalized();
        const Eigen::Vector3d axis = q * Eigen::Vector3d::UnitX();
        const double elevationDeg = core::radToDeg(std::asin(std::clamp(axis.y(), -1.0, 1.0)));
        const Eigen::Vector3d omega = angularVelocityEarth(in.arm, q, dt);
        const CymbalGesture::Result g = gesture_.update(elevationDeg, dt);

        if (g.event == CymbalGesture::Event::Strike) strike(g.speedDegPerS, out);
        else if (g.event == CymbalGesture::Event::Touch && clock_ < ringingUntil_) damp(g.speedDegPerS, out);

        if (g.inside) insideFeedback(q, omega, out);
        else leaveInside(out);
    }

    /// The latest strike's speed (deg/s, 0 before any), for mappings (Core/Scene.h).
    core::SceneValues values() const noexcept override { return values_; }

    void renderAudio(float* left, float* right, int numSamples) noexcept override
    {
        CymbalCommand c;
        while (commands_.pop(c)) apply(c);
        const double boost = indexBoost_.load(std::memory_order_relaxed);
        const double shift = harmonicityShift_.load(std::memory_order_relaxed);
        const auto level = static_cast<double>(params_.get(kLevel));
        for (auto& v : voices_)
            if (v.active) renderVoice(v, left, right, numSamples, level, boost, shift);
    }

private:
    core::SceneValues values_ {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::quiet_NaN(), 0.0f}; // control thread: strike 0 before any
    static constexpr int kStrikeVoice = 0, kDampVoice = 1, kGearVoice = 2;
    static constexpr double kRingSeconds = 10.0;   ///< how long a touch still counts as damping

    Eigen::Vector3d angularVelocityEarth(const core::ArmState& arm, const Eigen::Quaterniond& q, double dt)
    {
        return q * motion_.update(arm, dt);
    }

    void strike(double speedDegPerS, core::SceneOutput& out)
    {
        const double gain = cymbalStrikeGain(speedDegPerS, params_.get(kStrikeSpeed));
        CymbalCommand c;
        c.type = CymbalCommand::Strike;
        c.gain = gain;
        const int n = static_cast<int>(bank_.fragments.size());
        const double fs = sampleRate_;
        const double playS = kCrashEnvelope.lengthS;
        // Fragment A: from the brighter half, screened to have a crash-like attack (thesis
        // §3.6.2.1); fragment B: anything, or a cut from the user's audio.
        c.fragmentA = n / 2 + rng_.below(n - n / 2);
        c.rateA = rng_.uniform(0.92, 1.08);
        c.offsetA = rng_.uniform() * std::max(0.0, CrashBank::kFragmentSeconds * fs - playS * c.rateA * fs - 2.0);
        const bool fromUser = !bank_.user.empty() && rng_.uniform() * 100.0 < params_.get(kFileMix);
        c.rateB = rng_.uniform(0.85, 1.15);
        if (fromUser) {
            c.rateB = 1.0;   // the user's recording keeps its own pitch; only the cut varies
            c.fragmentB = -1;
            c.offsetB = rng_.uniform() * std::max(0.0, static_cast<double>(bank_.user.size()) - playS * c.rateB * fs - 2.0);
        } else {
            c.fragmentB = rng_.below(n);
            c.offsetB = rng_.uniform() * std::max(0.0, CrashBank::kFragmentSeconds * fs - playS * c.rateB * fs - 2.0);
        }
        c.panA = rng_.uniform(0.25, 0.75);
        c.panB = 1.0 - c.panA;
        // Metallic FM: inharmonic ratios (thesis §3.6.2.2, after Roads).
        static constexpr double kRatios[] = {1.19, 1.41, 1.73, 2.76, 3.14, 3.53};
        c.carrierHz = rng_.uniform(180.0, 520.0);
        c.harmonicity = kRatios[rng_.below(6)] * rng_.uniform(0.98, 1.02);
        c.index = rng_.uniform(1.5, 4.0);
        commands_.push(c);

        core::PatternRequest jolt;
        jolt.kind = core::PatternKind::Jolt;
        jolt.motors = 0x01FF;
        jolt.level = static_cast<float>(6.0 + 9.0 * gain);
        jolt.duration = 0.12;
        jolt.voice = kStrikeVoice;
        out.motors.trigger(jolt);
        out.events.emit("strike", static_cast<float>(speedDegPerS));
        values_.strike = static_cast<float>(speedDegPerS);
        ringingUntil_ = clock_ + kRingSeconds;
    }

    void damp(double speedDegPerS, core::SceneOutput& out)
    {
        CymbalCommand c;
        c.type = CymbalCommand::Damp;
        c.dampSeconds = params_.get(kDamp);
        commands_.push(c);
        // The soft fading vibration in every motor, over the same time as the sound's fade.
        core::PatternRequest fade;
        fade.kind = core::PatternKind::FadeOutPulse;
        fade.motors = 0x01FF;
        fade.level = 4.0f;
        fade.duration = c.dampSeconds;
        fade.voice = kDampVoice;
        fade.soft = true;   // a gentle touch: never the jump-start spike
        out.motors.trigger(fade);
        out.events.emit("damp", static_cast<float>(speedDegPerS));
        ringingUntil_ = -1.0;
    }

    /// Inside the cymbal (thesis §3.6.1): idle vibration everywhere; movement adds vibration
    /// ∝ |ω| on the side the flux picks; when the board's face leads (moving up with the palm
    /// down) the pulling alternation instead, because no motor sits under the board.
    void insideFeedback(const Eigen::Quaterniond& q, const Eigen::Vector3d& omega, core::SceneOutput& out)
    {
        const double idle = params_.get(kIdle);
        const double speed = omega.norm();   // rad/s
        const double fluxFace = (q * Eigen::Vector3d::UnitY()).dot(omega);
        const double fluxEdge = (q * Eigen::Vector3d::UnitZ()).dot(omega);
        const bool moving = movingHysteresis_.update(speed);
        const double share = std::fabs(fluxFace) / (std::fabs(fluxFace) + std::fabs(fluxEdge) + 1e-9);
        const bool sideLeads = sideHysteresis_.update(share);   // thumb / fifth finger vs palm / face
        const auto moveLevel = static_cast<float>(std::min(15.0, idle + params_.get(kBrush) * speed));

        std::array<float, core::kGridMotors> target {};
        target.fill(static_cast<float>(idle));
        bool gear = false;
        if (moving) {
            if (sideLeads) {
                // Rotation about the face normal sweeps the edges: + leads with the thumb side
                // (column 0 on the right arm), − with the fifth finger (column 2).
                target[static_cast<std::size_t>(core::motorIndex(1, fluxFace > 0.0 ? 0 : 2))] = moveLevel;
            } else if (fluxEdge < 0.0) {
                target[static_cast<std::size_t>(core::motorIndex(1, 1))] = moveLevel; // palm leads
            } else {
                gear = true;                                                      // face leads
            }
        }
        for (int m = 0; m < core::kGridMotors; ++m) setShown(m, target[static_cast<std::size_t>(m)], out);

        if (gear && (!gearOn_ || std::fabs(moveLevel - gearLevel_) > 1.5f)) {
            core::PatternRequest pull;
            pull.kind = core::PatternKind::GearPull;
            pull.motors = 0x01FF;
            pull.level = moveLevel;
            pull.duration = -1.0;
            pull.rate = 8.0;
            pull.voice = kGearVoice;
            out.motors.trigger(pull);
            gearLevel_ = moveLevel;
        } else if (!gear && gearOn_) {
            out.motors.stopVoice(kGearVoice);
        }
        gearOn_ = gear;

        // Movement modulates the tail: faster → richer (index), direction → harmonicity.
        const double brush = std::clamp(speed / 3.0, 0.0, 1.0);
        indexBoost_.store(4.0 * brush, std::memory_order_relaxed);
        harmonicityShift_.store(0.35 * std::clamp(fluxFace / 3.0, -1.0, 1.0), std::memory_order_relaxed);
    }

    void leaveInside(core::SceneOutput& out)
    {
        // Above the surface nothing is felt (thesis: the arm is not "inside" the instrument).
        for (int m = 0; m < core::kGridMotors; ++m) setShown(m, 0.0f, out);
        if (gearOn_) out.motors.stopVoice(kGearVoice);
        gearOn_ = false;
        indexBoost_.store(0.0, std::memory_order_relaxed);
        harmonicityShift_.store(0.0, std::memory_order_relaxed);
    }

    void setShown(int motor, float level, core::SceneOutput& out)
    {
        auto& s = shown_[static_cast<std::size_t>(motor)];
        if (s == level) return;
        // The idle vibration is a gentle background (entering by a touch must not kick all nine
        // motors); only the brushing movement on top of it asks for a fast start.
        if (level <= static_cast<float>(params_.get(kIdle)) + 1e-3f) out.motors.setSoftLevel(motor, level);
        else out.motors.setLevel(motor, level);
        s = level;
    }

    // ---- audio thread ------------------------------------------------------------------------

    void apply(const CymbalCommand& c) noexcept
    {
        if (c.type == CymbalCommand::Damp) {
            const double mul = std::exp(std::log(1e-3) / (std::max(c.dampSeconds, 0.01) * sampleRate_));
            for (auto& v : voices_)
                if (v.active) v.dampMul = std::min(v.dampMul, mul);
            return;
        }
        // A new strike: the older voice gets out of the way in ~50 ms (no click, no pile-up).
        const double stealMul = std::exp(std::log(1e-3) / (0.05 * sampleRate_));
        CrashVoice* slot = &voices_[0];
        for (auto& v : voices_) {
            if (v.active) v.dampMul = std::min(v.dampMul, stealMul);
            else slot = &v;
        }
        if (slot->active) {   // both busy: take the older one
            slot = voices_[0].age >= voices_[1].age ? &voices_[0] : &voices_[1];
        }
        startVoice(*slot, c);
    }

    void startVoice(CrashVoice& v, const CymbalCommand& c) noexcept
    {
        const double fs = sampleRate_;
        const CrashEnvelopeParams& e = kCrashEnvelope;
        v = CrashVoice {};
        v.active = true;
        const auto& fa = bank_.fragments[static_cast<std::size_t>(std::clamp(c.fragmentA, 0, static_cast<int>(bank_.fragments.size()) - 1))];
        v.a = {fa.data(), fa.size(), c.offsetA, c.rateA, std::cos(0.5 * core::kPi * c.panA), std::sin(0.5 * core::kPi * c.panA)};
        const std::vector<float>& fb = c.fragmentB < 0 && !bank_.user.empty()
            ? bank_.user
            : bank_.fragments[static_cast<std::size_t>(std::clamp(c.fragmentB, 0, static_cast<int>(bank_.fragments.size()) - 1))];
        v.b = {fb.data(), fb.size(), c.offsetB, c.rateB, 0.8 * std::cos(0.5 * core::kPi * c.panB), 0.8 * std::sin(0.5 * core::kPi * c.panB)};
        v.gain = c.gain;
        v.length = static_cast<long>(e.lengthS * fs);
        v.fadeStart = static_cast<long>((e.lengthS - e.fadeS) * fs);
        v.attackStep = 1.0 / std::max(1.0, e.attackS * fs);
        v.fast = e.fastShare;
        v.fastMul = std::exp(-1.0 / (e.fastTauS * fs));
        v.slow = 1.0 - e.fastShare;
        v.slowMul = std::exp(-1.0 / (e.slowTauS * fs));
        v.riseState = 1.0;
        v.riseMul = std::exp(-1.0 / (e.tailRiseTauS * fs));
        v.tailDecay = 1.0;
        v.tailDecayMul = std::exp(-1.0 / (e.tailDecayTauS * fs));
        v.carrierInc = c.carrierHz / fs;
        v.lfoInc = 0.37 / fs;   // slow wobble: the tail moves even when the arm does not
        v.harmonicity = c.harmonicity;
        v.index = c.index;
        v.indexSmooth.setTime(0.03, fs);
        v.indexSmooth.value = c.index;
        v.harmonicitySmooth.setTime(0.05, fs);
        v.harmonicitySmooth.value = c.harmonicity;
    }

    void renderVoice(CrashVoice& voice, float* left, float* right, int numSamples, double level, double boost, double shift) noexcept
    {
        // Work on a local copy: the compiler keeps it in registers instead of storing every
        // field back through the reference after each output sample (it cannot prove that the
        // output pointers do not alias the voice).
        CrashVoice v = voice;
        const CrashEnvelopeParams& e = kCrashEnvelope;
        const double tailLevel = static_cast<double>(params_.get(kTail)) * e.tailShare;
        const double fadeDen = static_cast<double>(std::max(1L, v.length - v.fadeStart));
        const double detune = 1.003;   // right carrier: a slow beating gives the tail width
        constexpr double kInvTwoPi = 1.0 / dsp::kTwoPi;
        for (int i = 0; i < numSamples; ++i) {
            double l = 0.0, r = 0.0;
            if (v.age < v.length) {
                v.attack = std::min(1.0, v.attack + v.attackStep);
                double env = v.attack * (v.fast + v.slow);
                if (v.age > v.fadeStart) env *= static_cast<double>(v.length - v.age) / fadeDen;
                v.fast *= v.fastMul;
                v.slow *= v.slowMul;
                const double sa = v.a.next();
                const double sb = v.b.next();
                l += env * (sa * v.a.gainL + sb * v.b.gainL);
                r += env * (sa * v.a.gainR + sb * v.b.gainR);
            }
            const double tailEnv = (1.0 - v.riseState) * v.tailDecay * tailLevel;
            v.riseState *= v.riseMul;
            v.tailDecay *= v.tailDecayMul;
            if (tailEnv > 1e-7) {
                const double lfo = dsp::SineTable::at(v.lfoPhase);
                v.lfoPhase = dsp::wrapPhase(v.lfoPhase + v.lfoInc);
                const double index = v.indexSmooth.next(v.index * (1.0 + 0.3 * lfo) + boost);
                const double h = v.harmonicitySmooth.next(v.harmonicity + shift);
                const double mod = dsp::SineTable::at(v.modPhase) * index * kInvTwoPi;   // cycles
                v.modPhase = dsp::wrapPhase(v.modPhase + v.carrierInc * h);
                l += tailEnv * dsp::SineTable::at(v.carrierPhaseL + mod);
                r += tailEnv * dsp::SineTable::at(v.carrierPhaseR + mod);
                v.carrierPhaseL = dsp::wrapPhase(v.carrierPhaseL + v.carrierInc);
                v.carrierPhaseR = dsp::wrapPhase(v.carrierPhaseR + v.carrierInc * detune);
            }
            const double g = kHeadroom * v.gain * level * v.damp;
            v.damp = dsp::flushTiny(v.damp * v.dampMul);
            if (left) left[i] += static_cast<float>(g * l);
            if (right) right[i] += static_cast<float>(g * r);
            ++v.age;
        }
        const double remaining = v.damp * std::max(v.age < v.length ? 1.0 : 0.0, v.tailDecay * tailLevel);
        if (remaining < 1e-5) v.active = false;
        voice = v;
    }

    ParameterSet params_;
    core::AudioBuffer userSource_ {};
    CrashBank bank_ {};
    double sampleRate_ = 48000.0;

    // Control thread.
    dsp::Random rng_ {1};
    CymbalGesture gesture_ {};
    tactile::Hysteresis movingHysteresis_ {0.4, 0.2}; ///< rad/s: moving inside vs still
    tactile::Hysteresis sideHysteresis_ {0.55, 0.45}; ///< share of |flux| about the face normal
    std::array<float, core::kGridMotors> shown_ {};
    bool gearOn_ = false;
    float gearLevel_ = 0.0f;
    bool clearOnNextControl_ = true;
    ArmMotion motion_ {};
    double clock_ = 0.0;          ///< s, sum of dt
    double ringingUntil_ = -1.0;  ///< s on clock_

    // Control → audio.
    core::SpscQueue<CymbalCommand, 32> commands_;
    std::atomic<double> indexBoost_ {0.0};        ///< added FM index, radians
    std::atomic<double> harmonicityShift_ {0.0};  ///< added to the harmonicity ratio

    // Audio thread.
    std::array<CrashVoice, kVoices> voices_ {};
};

} // namespace

std::unique_ptr<CymbalInstrument> makeCymbalInstrument() { return std::make_unique<CymbalScene>(); }
std::unique_ptr<core::Scene> makeCymbalScene() { return makeCymbalInstrument(); }

} // namespace armadillo::instruments
