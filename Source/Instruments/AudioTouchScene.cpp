// "audio-touch": whatever audio comes in, felt on the arm (what haptic music products do).
// Three frequency bands, one motor row each — lows (kick, < 90 Hz) on the elbow row, the bass
// and mid range (120 Hz–1 kHz) on the middle row, highs (> 4 kHz: cymbals, hi-hats) on the wrist
// row; each band's loudness sets its row's level (soft: the envelope is a swell, never a
// jump-start spike), and each band's transients are short accents on its row. Everything goes
// through the tactile engine's shaping and safety stage like every other scene.
//
// Audio thread (processInput): band filters (48 dB/octave), per band a level envelope (5 ms
// attack, 40 ms release) and a fast/slow pair for transients (fast 1 ms / 40 ms, slow 150 ms); a
// transient is the fast envelope rising (by 1 dB within a 2.5 ms hop) while 6 dB over the slow
// one and 6 dB over the sensitivity floor, at most one per 80 ms. Results cross to control() through atomics. Fixed state, no allocation, lock or throw.
#include "Instruments/ParameterSet.h"
#include "Instruments/Scenes.h"
#include "Tactile/Patterns.h"
#include <array>
#include <atomic>
#include <cmath>

namespace armadillo {
namespace {

enum AudioTouchIndex : int { kIntensity, kSensitivity, kAccents };

std::vector<ParamSpec> audioTouchSpecs()
{
    return {
        {"audio-touch.intensity", "Intensity", 0.0f, 100.0f, 80.0f, "%", {}},
        {"audio-touch.sensitivity", "Sensitivity (quietest sound felt)", -80.0f, -20.0f, -40.0f, "dBFS", {}},
        {"audio-touch.accents", "Beats and hits", 0.0f, 100.0f, 60.0f, "%", {}},
    };
}

/// RBJ biquad (transposed direct form II), double state.
struct Biquad {
    double b0 = 1, b1 = 0, b2 = 0, a1 = 0, a2 = 0, z1 = 0, z2 = 0;
    static Biquad make(bool highPass, double hz, double fs)
    {
        const double w = 2.0 * kPi * hz / fs, c = std::cos(w), alpha = std::sin(w) / (2.0 * 0.7071067811865476);
        const double a0 = 1.0 + alpha;
        Biquad q;
        q.b0 = (highPass ? (1.0 + c) / 2.0 : (1.0 - c) / 2.0) / a0;
        q.b1 = (highPass ? -(1.0 + c) : (1.0 - c)) / a0;
        q.b2 = q.b0;
        q.a1 = -2.0 * c / a0;
        q.a2 = (1.0 - alpha) / a0;
        return q;
    }
    double operator()(double x) noexcept
    {
        const double y = b0 * x + z1;
        z1 = b1 * x - a1 * y + z2;
        z2 = b2 * x - a2 * y;
        return y;
    }
};

constexpr int kBands = 3;
/// Row of each band: lows at the elbow, the middle band in the middle, highs at the wrist.
constexpr int kBandRow[kBands] = {2, 1, 0};

class AudioTouchScene final : public Scene {
public:
    AudioTouchScene() : params_(audioTouchSpecs()) {}
    std::string_view name() const override { return "audio-touch"; }
    std::vector<ParamSpec> parameters() const override { return params_.specs(); }
    void setParameter(int index, float value) noexcept override { params_.set(index, value); }
    bool listensToAudio() const override { return true; }

    void prepare(const SceneConfig& config) override
    {
        const double fs = config.sampleRate > 0.0 ? config.sampleRate : 48000.0;
        fs_ = fs;
        // Four cascaded 2nd-order sections per edge (48 dB/octave): a kick and a bass line a
        // fifth apart land on different rows.
        for (auto& q : low_) q = Biquad::make(false, 90.0, fs);
        for (auto& q : midHp_) q = Biquad::make(true, 120.0, fs);
        for (auto& q : midLp_) q = Biquad::make(false, 1000.0, fs);
        for (auto& q : high_) q = Biquad::make(true, 4000.0, fs);
        auto coef = [fs](double seconds) { return 1.0 - std::exp(-1.0 / (fs * seconds)); };
        levelAttack_ = coef(0.005);
        levelRelease_ = coef(0.040);
        fastAttack_ = coef(0.001);
        fastRelease_ = coef(0.040);
        slow_ = coef(0.150);
        hop_ = std::max(1, static_cast<int>(fs * 0.0025));
        refractoryHops_ = static_cast<int>(0.080 / 0.0025);
        for (auto& b : band_) b = BandState {};
        for (auto& a : pubLevel_) a.store(0.0f);
        for (auto& a : pubHits_) a.store(0u);
        for (auto& a : pubHitStrength_) a.store(0.0f);
        seenHits_.fill(0u);
        hopFill_ = 0;
        clearPending_ = true;
    }

    void reset() override
    {
        clearPending_ = true;
        for (int b = 0; b < kBands; ++b) seenHits_[static_cast<std::size_t>(b)] = pubHits_[static_cast<std::size_t>(b)].load();
    }

    void processInput(const float* const* in, int channels, int n) noexcept override
    {
        if (!in || channels < 1 || n <= 0) return;
        const double scale = 1.0 / channels;
        const double floor = std::pow(10.0, params_.get(kSensitivity) / 10.0);   // power
        for (int i = 0; i < n; ++i) {
            double x = 0.0;
            for (int c = 0; c < channels; ++c)
                if (in[c]) x += static_cast<double>(in[c][i]);
            x *= scale;
            if (!std::isfinite(x)) x = 0.0;
            double lo = x, mid = x, hi = x;
            for (auto& q : low_) lo = q(lo);
            for (auto& q : midHp_) mid = q(mid);
            for (auto& q : midLp_) mid = q(mid);
            for (auto& q : high_) hi = q(hi);
            const double y[kBands] = {lo, mid, hi};
            for (int b = 0; b < kBands; ++b) {
                BandState& s = band_[static_cast<std::size_t>(b)];
                const double p = y[b] * y[b];
                s.level += (p - s.level) * (p > s.level ? levelAttack_ : levelRelease_);
                s.fast += (p - s.fast) * (p > s.fast ? fastAttack_ : fastRelease_);
                s.slow += (p - s.slow) * slow_;
            }
            if (++hopFill_ < hop_) continue;
            hopFill_ = 0;
            for (int b = 0; b < kBands; ++b) {
                BandState& s = band_[static_cast<std::size_t>(b)];
                pubLevel_[static_cast<std::size_t>(b)].store(static_cast<float>(s.level), std::memory_order_relaxed);
                if (s.refractory > 0) --s.refractory;
                const double ratio = s.fast / std::max(s.slow, 1e-20);
                // 2× the amplitude (mean square ×4 ≈ 6 dB) marks the attack; the fast envelope
                // must clear the band's floor by 6 dB too.
                const bool rising = s.fast > 1.25 * s.fastBefore;   // an attack, not a tail
                s.fastBefore = s.fast;
                if (s.refractory == 0 && rising && ratio > 4.0 && s.fast > 4.0 * floor) {
                    s.refractory = refractoryHops_;
                    const double strength = std::clamp((10.0 * std::log10(ratio) - 6.0) / 12.0, 0.0, 1.0);
                    pubHitStrength_[static_cast<std::size_t>(b)].store(static_cast<float>(strength), std::memory_order_relaxed);
                    pubHits_[static_cast<std::size_t>(b)].fetch_add(1u, std::memory_order_release);
                }
            }
        }
    }

    void control(const ControlInput& /*in*/, SceneOutput& out) override
    {
        if (clearPending_) {
            out.motors.clearLevels();
            for (int b = 0; b < kBands; ++b) out.motors.stopVoice(b);
            clearPending_ = false;
        }
        const double intensity = params_.get(kIntensity) / 100.0;
        const double floorDb = params_.get(kSensitivity);
        const double accents = params_.get(kAccents) / 100.0;
        for (int b = 0; b < kBands; ++b) {
            const auto bi = static_cast<std::size_t>(b);
            // Loudness → level: the band's envelope from the sensitivity floor to 30 dB above it,
            // onto 0 .. the rated level × intensity (sustained touch never runs above the rating).
            const double db = 10.0 * std::log10(std::max(static_cast<double>(pubLevel_[bi].load(std::memory_order_relaxed)), 1e-20));
            const double x = std::clamp((db - floorDb) / 30.0, 0.0, 1.0);
            const auto level = static_cast<float>(kRatedLevel * intensity * x);
            for (int col = 0; col < 3; ++col) out.motors.setSoftLevel(motorIndex(kBandRow[b], col), level);
            // Transients → a short accent on the row: 25 ms, shorter than the jump-start spike,
            // so it plays at its own level (rating + up to 6 levels with `accents`).
            const unsigned hits = pubHits_[bi].load(std::memory_order_acquire);
            if (hits != seenHits_[bi]) {
                seenHits_[bi] = hits;
                if (accents > 0.0) {
                    PatternRequest accent;
                    accent.kind = PatternKind::Accent;
                    accent.motors = motors::row(kBandRow[b]);
                    accent.level = static_cast<float>(std::min(15.0, kRatedLevel + 1.0 + 6.0 * accents * (0.5 + 0.5 * static_cast<double>(pubHitStrength_[bi].load()))));
                    accent.duration = 0.025;
                    accent.voice = b;
                    out.motors.trigger(accent);
                }
            }
        }
    }

private:
    struct BandState {
        double level = 0.0, fast = 0.0, slow = 0.0;   ///< mean-square envelopes
        double fastBefore = 0.0;                      ///< `fast` at the previous hop
        int refractory = 0;                           ///< hops until the next transient may count
    };

    ParameterSet params_;
    double fs_ = 48000.0;
    std::array<Biquad, 4> low_ {}, midHp_ {}, midLp_ {}, high_ {};
    double levelAttack_ = 0, levelRelease_ = 0, fastAttack_ = 0, fastRelease_ = 0, slow_ = 0;
    int hop_ = 120, hopFill_ = 0, refractoryHops_ = 32;
    std::array<BandState, kBands> band_ {};
    std::array<std::atomic<float>, kBands> pubLevel_ {};
    std::array<std::atomic<unsigned>, kBands> pubHits_ {};
    std::array<std::atomic<float>, kBands> pubHitStrength_ {};
    std::array<unsigned, kBands> seenHits_ {};   ///< control thread
    bool clearPending_ = true;
};

} // namespace

std::unique_ptr<Scene> makeAudioTouchScene() { return std::make_unique<AudioTouchScene>(); }

} // namespace armadillo
