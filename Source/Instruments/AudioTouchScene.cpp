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
//
// Stems felt apart (SceneConfig::stems): the input is then one mono channel per stem (drums,
// bass, other, vocals — the four stems of common source separators), and each stem has its own
// preset: its motors (disjoint sets covering the grid), its band (24 dB/octave edges), its level
// envelope, and accents or not (kStemPresets below; docs/INSTRUMENTS.md). Bass is felt at the
// elbow, the voice at the wrist, the beat along the underside, the rest in the middle — each
// apart, whatever the others do.
//
// The plugin's stems are its VST3 sidechain buses; it appends its main input after them (the
// channels from stems.size() on: the whole mix). `audio-touch.stems` chooses: `apart` (default)
// feels the stems on their own motors while any of them carries sound — when none has been over
// the sensitivity floor for 1 s and a main input comes after them, the main input is felt as the
// mixed input above (a host that enables the sidechains but routes nothing to them); `mixed`
// feels the main input (without one: the stems' sum) as one mix through the three bands.
#include "Core/Biquad.h"
#include "Core/Errors.h"
#include "Instruments/ParameterSet.h"
#include "Instruments/Scenes.h"
#include "Tactile/Patterns.h"
#include <array>
#include <atomic>
#include <cmath>

namespace armadillo::instruments {
namespace {

enum AudioTouchIndex : int { kIntensity, kSensitivity, kAccents, kStemsMode };
enum StemsMode : int { kStemsApart = 0, kStemsMixed = 1 };

std::vector<core::ParamSpec> audioTouchSpecs()
{
    return {
        {"audio-touch.intensity", "Intensity", 0.0f, 100.0f, 80.0f, "%", {}},
        {"audio-touch.sensitivity", "Sensitivity (quietest sound felt)", -80.0f, -20.0f, -40.0f, "dBFS", {}},
        {"audio-touch.accents", "Beats and hits", 0.0f, 100.0f, 60.0f, "%", {}},
        {"audio-touch.stems", "Stems", 0.0f, 1.0f, 0.0f, "", {"apart", "mixed"}},   // appended (issue 27)
    };
}

/// A stem's preset: where it is felt and how it is heard (docs/INSTRUMENTS.md, "Stems").
struct StemPreset {
    const char* name;
    std::uint16_t motors;     ///< bit i = motor index i (k = i + 1)
    double lowHz, highHz;     ///< band edges
    double attack, release;   ///< level envelope time constants, s
    bool accents;             ///< transients become accents on its motors
};
constexpr std::uint16_t bit(int k) { return static_cast<std::uint16_t>(1u << (k - 1)); }
constexpr StemPreset kStemPresets[] = {
    {"drums", static_cast<std::uint16_t>(bit(2) | bit(5) | bit(8)), 40.0, 8000.0, 0.002, 0.060, true},   // the underside, wrist to elbow
    {"bass", static_cast<std::uint16_t>(bit(7) | bit(9)), 30.0, 250.0, 0.010, 0.150, false},             // the elbow
    {"other", static_cast<std::uint16_t>(bit(4) | bit(6)), 150.0, 4000.0, 0.010, 0.200, false},          // the middle
    {"vocals", static_cast<std::uint16_t>(bit(1) | bit(3)), 100.0, 4000.0, 0.015, 0.250, false},         // the wrist
};
constexpr int kMaxStems = 8;

constexpr int kBands = 3;
/// Row of each band: lows at the elbow, the middle band in the middle, highs at the wrist.
constexpr int kBandRow[kBands] = {2, 1, 0};

class AudioTouchScene final : public core::Scene {
public:
    AudioTouchScene() : params_(audioTouchSpecs()) {}
    std::string_view name() const override { return "audio-touch"; }
    std::vector<core::ParamSpec> parameters() const override { return params_.specs(); }
    void setParameter(int index, float value) noexcept override { params_.set(index, value); }
    bool listensToAudio() const override { return true; }

    void prepare(const core::SceneConfig& config) override
    {
        const double fs = config.sampleRate > 0.0 ? config.sampleRate : 48000.0;
        fs_ = fs;
        // Four cascaded 2nd-order sections per edge (48 dB/octave): a kick and a bass line a
        // fifth apart land on different rows.
        for (auto& q : low_) q = core::Biquad::make(false, 90.0, fs);
        for (auto& q : midHp_) q = core::Biquad::make(true, 120.0, fs);
        for (auto& q : midLp_) q = core::Biquad::make(false, 1000.0, fs);
        for (auto& q : high_) q = core::Biquad::make(true, 4000.0, fs);
        auto coef = [fs](double seconds) { return 1.0 - std::exp(-1.0 / (fs * seconds)); };
        levelAttack_ = coef(0.005);
        levelRelease_ = coef(0.040);
        fastAttack_ = coef(0.001);
        fastRelease_ = coef(0.040);
        slow_ = coef(0.150);
        hop_ = std::max(1, static_cast<int>(fs * 0.0025));
        refractoryHops_ = static_cast<int>(0.080 / 0.0025);
        for (auto& b : band_) b = BandState {};
        if (config.stems.size() > static_cast<std::size_t>(kMaxStems))
            throw core::InputError("", 0, "stems", "at most " + std::to_string(kMaxStems) + " stems");
        stemCount_ = 0;
        for (const std::string& name : config.stems) {
            const StemPreset* preset = nullptr;
            for (const StemPreset& p : kStemPresets)
                if (name == p.name) preset = &p;
            if (!preset) throw core::InputError("", 0, "stem", "unknown stem '" + name + "' (presets: drums, bass, other, vocals)");
            Stem& st = stems_[static_cast<std::size_t>(stemCount_++)];
            st = Stem {};
            st.preset = preset;
            for (auto& q : st.hp) q = core::Biquad::make(true, preset->lowHz, fs);
            for (auto& q : st.lp) q = core::Biquad::make(false, std::min(preset->highHz, 0.45 * fs), fs);
            st.attack = coef(preset->attack);
            st.release = coef(preset->release);
        }
        for (auto& a : pubLevel_) a.store(0.0f);
        for (auto& a : pubHits_) a.store(0u);
        for (auto& a : pubHitStrength_) a.store(0.0f);
        seenHits_.fill(0u);
        for (auto& a : stemPubLevel_) a.store(0.0f);
        for (auto& a : stemPubHits_) a.store(0u);
        for (auto& a : stemPubStrength_) a.store(0.0f);
        stemSeenHits_.fill(0u);
        hopFill_ = 0;
        stemHopFill_ = 0;
        stemQuietHops_ = kStemQuietHops;
        stemsSounding_.store(false);
        mainHeard_.store(false);
        clearPending_ = true;
    }

    void reset() override
    {
        clearPending_ = true;
        for (int b = 0; b < kBands; ++b) seenHits_[static_cast<std::size_t>(b)] = pubHits_[static_cast<std::size_t>(b)].load();
        for (int k = 0; k < stemCount_; ++k) stemSeenHits_[static_cast<std::size_t>(k)] = stemPubHits_[static_cast<std::size_t>(k)].load();
    }

    void processInput(const float* const* in, int channels, int n) noexcept override
    {
        if (!in || channels < 1 || n <= 0) return;
        if (stemCount_ > 0) {
            // Stems first; what comes after them is the main input (the plugin's whole mix).
            const int mains = std::max(0, channels - stemCount_);
            mainHeard_.store(mains > 0, std::memory_order_relaxed);
            if (params_.get(kStemsMode) < 0.5) {
                processStems(in, std::min(channels, stemCount_), n);
                if (mains > 0) processMixed(in + stemCount_, mains, n, 1.0 / mains);   // the fallback's
            } else if (mains > 0) {
                processMixed(in + stemCount_, mains, n, 1.0 / mains);
            } else {
                processMixed(in, std::min(channels, stemCount_), n, 1.0);   // the stems' sum: the mix
            }
            return;
        }
        processMixed(in, channels, n, 1.0 / channels);
    }

    void control(const core::ControlInput& /*in*/, core::SceneOutput& out) override
    {
        if (clearPending_) {
            out.motors.clearLevels();
            for (int v = 0; v < std::max(kBands, stemCount_); ++v) out.motors.stopVoice(v);
            clearPending_ = false;
        }
        const double intensity = params_.get(kIntensity) / 100.0;
        const double floorDb = params_.get(kSensitivity);
        const double accents = params_.get(kAccents) / 100.0;
        const bool apart = stemCount_ > 0 && params_.get(kStemsMode) < 0.5
                           && (stemsSounding_.load(std::memory_order_relaxed) || !mainHeard_.load(std::memory_order_relaxed));
        if (apart) {
            for (int b = 0; b < kBands; ++b) seenHits_[static_cast<std::size_t>(b)] = pubHits_[static_cast<std::size_t>(b)].load();
            controlStems(out, intensity, floorDb, accents);
            return;
        }
        for (int k = 0; k < stemCount_; ++k) stemSeenHits_[static_cast<std::size_t>(k)] = stemPubHits_[static_cast<std::size_t>(k)].load();
        controlMixed(out, intensity, floorDb, accents);
    }

private:
    /// The mixed input: `channels` channels from `in`, summed and scaled by `scale`, through the
    /// three bands.
    void processMixed(const float* const* in, int channels, int n, double scale) noexcept
    {
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

    void controlMixed(core::SceneOutput& out, double intensity, double floorDb, double accents)
    {
        for (int b = 0; b < kBands; ++b) {
            const auto bi = static_cast<std::size_t>(b);
            // Loudness → level: the band's envelope from the sensitivity floor to 30 dB above it,
            // onto 0 .. the rated level × intensity (sustained touch never runs above the rating).
            const double db = 10.0 * std::log10(std::max(static_cast<double>(pubLevel_[bi].load(std::memory_order_relaxed)), 1e-20));
            const double x = std::clamp((db - floorDb) / 30.0, 0.0, 1.0);
            const auto level = static_cast<float>(core::kRatedLevel * intensity * x);
            for (int col = 0; col < 3; ++col) out.motors.setSoftLevel(core::motorIndex(kBandRow[b], col), level);
            // Transients → a short accent on the row: 25 ms, shorter than the jump-start spike,
            // so it plays at its own level (rating + up to 6 levels with `accents`).
            const unsigned hits = pubHits_[bi].load(std::memory_order_acquire);
            if (hits != seenHits_[bi]) {
                seenHits_[bi] = hits;
                if (accents > 0.0) {
                    core::PatternRequest accent;
                    accent.kind = core::PatternKind::Accent;
                    accent.motors = tactile::motors::row(kBandRow[b]);
                    accent.level = static_cast<float>(std::min(15.0, core::kRatedLevel + 1.0 + 6.0 * accents * (0.5 + 0.5 * static_cast<double>(pubHitStrength_[bi].load()))));
                    accent.duration = 0.025;
                    accent.voice = b;
                    out.motors.trigger(accent);
                }
            }
        }
    }

    /// Stems: each channel its own band, envelopes and transients (the mixed path's rules).
    void processStems(const float* const* in, int channels, int n) noexcept
    {
        const double floor = std::pow(10.0, params_.get(kSensitivity) / 10.0);   // power
        for (int i = 0; i < n; ++i) {
            for (int k = 0; k < stemCount_; ++k) {
                Stem& st = stems_[static_cast<std::size_t>(k)];
                double x = k < channels && in[k] ? static_cast<double>(in[k][i]) : 0.0;
                if (!std::isfinite(x)) x = 0.0;
                for (auto& q : st.hp) x = q(x);
                for (auto& q : st.lp) x = q(x);
                const double p = x * x;
                BandState& b = st.band;
                b.level += (p - b.level) * (p > b.level ? st.attack : st.release);
                b.fast += (p - b.fast) * (p > b.fast ? fastAttack_ : fastRelease_);
                b.slow += (p - b.slow) * slow_;
            }
            if (++stemHopFill_ < hop_) continue;
            stemHopFill_ = 0;
            bool sounding = false;
            for (int k = 0; k < stemCount_; ++k) sounding = sounding || stems_[static_cast<std::size_t>(k)].band.level > floor;
            stemQuietHops_ = sounding ? 0 : std::min(stemQuietHops_ + 1, kStemQuietHops);
            stemsSounding_.store(stemQuietHops_ < kStemQuietHops, std::memory_order_relaxed);
            for (int k = 0; k < stemCount_; ++k) {
                const auto ki = static_cast<std::size_t>(k);
                BandState& b = stems_[ki].band;
                stemPubLevel_[ki].store(static_cast<float>(b.level), std::memory_order_relaxed);
                if (b.refractory > 0) --b.refractory;
                const double ratio = b.fast / std::max(b.slow, 1e-20);
                const bool rising = b.fast > 1.25 * b.fastBefore;
                b.fastBefore = b.fast;
                if (stems_[ki].preset->accents && b.refractory == 0 && rising && ratio > 4.0 && b.fast > 4.0 * floor) {
                    b.refractory = refractoryHops_;
                    const double strength = std::clamp((10.0 * std::log10(ratio) - 6.0) / 12.0, 0.0, 1.0);
                    stemPubStrength_[ki].store(static_cast<float>(strength), std::memory_order_relaxed);
                    stemPubHits_[ki].fetch_add(1u, std::memory_order_release);
                }
            }
        }
    }

    void controlStems(core::SceneOutput& out, double intensity, double floorDb, double accents)
    {
        std::array<float, core::kMaxMotors> level {};
        for (int k = 0; k < stemCount_; ++k) {
            const auto ki = static_cast<std::size_t>(k);
            const StemPreset& preset = *stems_[ki].preset;
            const double db = 10.0 * std::log10(std::max(static_cast<double>(stemPubLevel_[ki].load(std::memory_order_relaxed)), 1e-20));
            const double x = std::clamp((db - floorDb) / 30.0, 0.0, 1.0);
            const auto l = static_cast<float>(core::kRatedLevel * intensity * x);
            for (int m = 0; m < core::kMaxMotors; ++m)
                if (preset.motors & (1u << m)) level[static_cast<std::size_t>(m)] = std::max(level[static_cast<std::size_t>(m)], l);
            const unsigned hits = stemPubHits_[ki].load(std::memory_order_acquire);
            if (hits != stemSeenHits_[ki]) {
                stemSeenHits_[ki] = hits;
                if (accents > 0.0) {
                    core::PatternRequest accent;
                    accent.kind = core::PatternKind::Accent;
                    accent.motors = preset.motors;
                    accent.level = static_cast<float>(std::min(15.0, core::kRatedLevel + 1.0 + 6.0 * accents * (0.5 + 0.5 * static_cast<double>(stemPubStrength_[ki].load()))));
                    accent.duration = 0.025;
                    accent.voice = k;
                    out.motors.trigger(accent);
                }
            }
        }
        for (int m = 0; m < core::kGridMotors; ++m) out.motors.setSoftLevel(m, level[static_cast<std::size_t>(m)]);
    }

    struct BandState {
        double level = 0.0, fast = 0.0, slow = 0.0;   ///< mean-square envelopes
        double fastBefore = 0.0;                      ///< `fast` at the previous hop
        int refractory = 0;                           ///< hops until the next transient may count
    };

    ParameterSet params_;
    double fs_ = 48000.0;
    std::array<core::Biquad, 4> low_ {}, midHp_ {}, midLp_ {}, high_ {};
    double levelAttack_ = 0, levelRelease_ = 0, fastAttack_ = 0, fastRelease_ = 0, slow_ = 0;
    int hop_ = 120, hopFill_ = 0, refractoryHops_ = 32;
    int stemHopFill_ = 0;
    /// Hops (2.5 ms) the stems have all been under the floor, up to 1 s's worth (audio thread).
    static constexpr int kStemQuietHops = 400;
    int stemQuietHops_ = kStemQuietHops;
    std::atomic<bool> stemsSounding_ {false};   ///< a stem over the floor within the last second
    std::atomic<bool> mainHeard_ {false};       ///< the input carries a main input after the stems
    std::array<BandState, kBands> band_ {};
    std::array<std::atomic<float>, kBands> pubLevel_ {};
    std::array<std::atomic<unsigned>, kBands> pubHits_ {};
    std::array<std::atomic<float>, kBands> pubHitStrength_ {};
    std::array<unsigned, kBands> seenHits_ {};   ///< control thread
    bool clearPending_ = true;

    struct Stem {
        const StemPreset* preset = nullptr;
        std::array<core::Biquad, 2> hp {}, lp {}; ///< 24 dB/octave edges
        double attack = 0, release = 0;
        BandState band {};
    };
    int stemCount_ = 0;
    std::array<Stem, kMaxStems> stems_ {};
    std::array<std::atomic<float>, kMaxStems> stemPubLevel_ {};
    std::array<std::atomic<unsigned>, kMaxStems> stemPubHits_ {};
    std::array<std::atomic<float>, kMaxStems> stemPubStrength_ {};
    std::array<unsigned, kMaxStems> stemSeenHits_ {};   ///< control thread
};

} // namespace

std::unique_ptr<core::Scene> makeAudioTouchScene() { return std::make_unique<AudioTouchScene>(); }

} // namespace armadillo::instruments
