// "layered-keyboard" (thesis §5.2): the arm plays over a real instrument. A piano (any pitched
// instrument) is heard through the audio input; the notes just played are found and captured
// (Instruments/LayeredKeyboard.h); the space above the keyboard becomes a virtual keyboard made
// of them:
// - below `bottom` elevation the hands are on the real keys: the scene is silent;
// - from `bottom` to `top` the captured layers lie one above the other in capture order, each in
//   an equal band of elevation (±1.5° hysteresis at the edges): the oldest lowest, the newest
//   highest; a change of layer cross-fades in 30 ms;
// - azimuth, relative to where the arm entered the space, shifts the layer's pitch (±`shift`
//   semitones at ±60°), roll opens a low-pass filter (−90° → 300 Hz, +90° → 12 kHz), and the
//   layer sustains as a granular stream (90 ms Hann grains, two overlapping) that walks through
//   the captured note `stretch` times slower than it was played, with `spread` of random grain
//   positions;
// - the tactile display shows the layer under the hand: the layer's motor (the fret order of the
//   theremin, elbow → wrist as the layers rise) held soft at the rated level, a point when the
//   hand enters a layer, and a short accent on the wrist row when a note is captured.
// With MIDI input (an instrument that has it: processMidi, `render --midi-in`), from its first
// note-on the notes come from MIDI — exact pitches, chords as played — while the sound of each
// layer is still sampled from the audio input (NoteListener, "MIDI input").
// Captured notes leave as gestures "captured-note" (value = MIDI note number) in capture order,
// a change of layer as "layer" (value = layer index).
//
// Threads: processInput() and renderAudio() run on the audio thread (the listener's slots are
// theirs alone); control() reads what they publish through atomics and an SPSC queue, and
// publishes its targets through atomics.
#include "Core/SpscQueue.h"
#include "Instruments/Dsp.h"
#include "Instruments/Frets.h"
#include "Instruments/LayeredKeyboard.h"
#include "Instruments/ParameterSet.h"
#include "Instruments/Scenes.h"
#include "Tactile/Patterns.h"
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>

namespace armadillo::instruments {
namespace {

enum LayeredIndex : int { kBottom, kTop, kShift, kStretch, kSpread, kVolume, kNotes, kSensitivity, kCapture, kPhraseGap };

std::vector<core::ParamSpec> layeredSpecs()
{
    return {
        {"layered-keyboard.bottom", "Lowest layer (elevation)", -30.0f, 40.0f, 0.0f, "deg", {}},
        {"layered-keyboard.top", "Highest layer (elevation)", 10.0f, 80.0f, 60.0f, "deg", {}},
        {"layered-keyboard.shift", "Pitch shift at ±60° azimuth", 0.0f, 24.0f, 12.0f, "semitones", {}},
        {"layered-keyboard.stretch", "Time stretch", 1.0f, 16.0f, 4.0f, "x", {}},
        {"layered-keyboard.spread", "Granular spread", 0.0f, 100.0f, 10.0f, "%", {}},
        {"layered-keyboard.volume", "Volume", 0.0f, 100.0f, 80.0f, "%", {}},
        {"layered-keyboard.notes", "Notes per onset (polyphony)", 1.0f, 4.0f, 4.0f, "", {}},
        {"layered-keyboard.sensitivity", "Sensitivity (quietest note heard)", -80.0f, -20.0f, -50.0f, "dBFS", {}},
        {"layered-keyboard.capture", "Capture", 0.0f, 1.0f, 0.0f, "", {"listen", "hold"}},
        {"layered-keyboard.phrase-gap", "Silence that ends a phrase", 0.5f, 30.0f, 3.0f, "s", {}},
    };
}

constexpr double kGrainSeconds = 0.09;
constexpr double kFadeSeconds = 0.03;
constexpr double kHysteresisDeg = 1.5;

/// One granular stream over one captured slot: two Hann grains half a grain apart (their windows
/// sum to 1), each reading the slot at `rate` with linear interpolation.
struct GrainPlayer {
    int slot = -1;
    std::uint32_t generation = 0;
    double head = 0.0;            ///< samples into the slot: where the next grain starts (before jitter)
    double gain = 0.0;            ///< current fade gain 0..1
    bool active = false;          ///< fading in/holding (false: fading out)
    std::array<double, 2> pos {}; ///< read position of each grain, samples
    std::array<int, 2> age {};    ///< samples into each grain
    int grainLength = 4320;
    double period = 0.0;          ///< samples of one period of the layer's first note (0: unknown)

    void start(int s, std::uint32_t gen, double fs, int midiNote)
    {
        slot = s;
        period = midiNote > 0 ? fs / (440.0 * std::exp2((midiNote - 69) / 12.0)) : 0.0;
        generation = gen;
        head = 0.04 * fs;   // past the attack (the hammer): the layer is the note's body
        grainLength = std::max(16, static_cast<int>(kGrainSeconds * fs));
        age = {grainLength, grainLength / 2};   // the first grain starts now, the second half a grain later
        pos = {head, head};
        active = true;
    }
};

struct CaptureRecord {
    std::array<int, kMaxChordNotes> notes {};
    int count = 0;
    int layerIndex = 0;
};

class LayeredKeyboardScene final : public core::Scene {
public:
    LayeredKeyboardScene() : params_(layeredSpecs()) {}
    std::string_view name() const override { return "layered-keyboard"; }
    std::vector<core::ParamSpec> parameters() const override { return params_.specs(); }
    void setParameter(int index, float value) noexcept override { params_.set(index, value); }
    bool listensToAudio() const override { return true; }
    bool listensToMidi() const override { return true; }

    void processMidi(const core::MidiNoteEvent* events, int count) noexcept override
    {
        if (!events) return;
        const std::int64_t base = listener_.samplesProcessed();   // the block's first sample (called before processInput)
        for (int i = 0; i < count; ++i)
            if (events[i].velocity > 0) {
                listener_.noteOn(base + std::max(0, events[i].offset), events[i].note);
                midi_ = true;
            }
    }
    bool producesAudio() const override { return true; }

    void prepare(const core::SceneConfig& config) override
    {
        fs_ = config.sampleRate > 0.0 ? config.sampleRate : 48000.0;
        listener_.prepare(fs_);
        mono_.assign(8192, 0.0f);
        random_.seed(config.seed * 0x9E3779B97F4A7C15ull + 28);
        fadeStep_ = 1.0 / (kFadeSeconds * fs_);
        shiftSmooth_.setTime(0.02, fs_);
        cutoffSmooth_.setTime(0.02, fs_);
        shiftSmooth_.value = 0.0;
        cutoffSmooth_.value = 12000.0;
        filter_.setup(12000.0, 0.7071, fs_);
        for (auto& p : players_) p = GrainPlayer {};
        midi_ = false;
        published_.store(0u);
        targetLayer_.store(-1);
        resetControl();
    }

    void reset() override { resetControl(); }

    void processInput(const float* const* in, int channels, int n) noexcept override
    {
        if (!in || channels < 1 || n <= 0) return;
        ListenerSettings s;
        s.maxNotes = static_cast<int>(params_.get(kNotes));
        s.floorDb = params_.get(kSensitivity);
        s.phraseGap = params_.get(kPhraseGap);
        s.hold = params_.get(kCapture) >= 0.5;
        s.midi = midi_;
        for (int done = 0; done < n;) {
            const int m = std::min(n - done, static_cast<int>(mono_.size()));
            for (int i = 0; i < m; ++i) {
                float x = 0.0f;
                for (int c = 0; c < channels; ++c)
                    if (in[c]) x += in[c][done + i];
                mono_[static_cast<std::size_t>(i)] = x / static_cast<float>(channels);
            }
            const std::uint32_t phraseBefore = listener_.phrase();
            const int completed = listener_.process(mono_.data(), m, s);
            for (int k = completed; k > 0; --k) {
                const int index = listener_.layerCount() - k;
                const CapturedLayer& layer = listener_.layer(index);
                CaptureRecord r;
                r.notes = layer.notes;
                r.count = layer.noteCount;
                r.layerIndex = index;
                captures_.push(r);   // full: dropped (the log only; the layer itself is kept)
            }
            if (completed > 0 || listener_.phrase() != phraseBefore) publish();
            done += m;
        }
    }

    void control(const core::ControlInput& in, core::SceneOutput& out) override
    {
        if (clearPending_) {
            out.motors.clearLevels();
            out.motors.stopVoice(0);
            out.motors.stopVoice(1);
            clearPending_ = false;
        }
        CaptureRecord r;
        while (captures_.pop(r)) {
            for (int i = 0; i < r.count; ++i) out.events.emit("captured-note", static_cast<float>(r.notes[static_cast<std::size_t>(i)]));
            core::PatternRequest accent;
            accent.kind = core::PatternKind::Accent;
            accent.motors = tactile::motors::row(0);
            accent.level = static_cast<float>(core::kRatedLevel + 2);
            accent.duration = 0.025;
            accent.voice = 1;
            out.motors.trigger(accent);
        }
        if (!in.arm.valid) return;
        const core::Pose& pose = in.arm.features.pose;
        const std::uint32_t word = published_.load(std::memory_order_acquire);
        const int count = static_cast<int>(word & 0xFFu);
        const int first = static_cast<int>((word >> 8) & 0xFFu);
        const double bottom = params_.get(kBottom);
        const double top = std::max(params_.get(kTop), bottom + 5.0);
        const double el = pose.elevationDeg;

        int layer = -1;
        if (count > 0 && el >= bottom - (layer_ >= 0 ? kHysteresisDeg : 0.0)) {
            const double width = (top - bottom) / count;
            int index = std::clamp(static_cast<int>(std::floor((el - bottom) / width)), 0, count - 1);
            if (layer_ >= 0 && layer_ < count && index != layer_) {   // hysteresis at the band edges
                const double lo = bottom + layer_ * width - kHysteresisDeg, hi = bottom + (layer_ + 1) * width + kHysteresisDeg;
                if (el >= lo && el < hi) index = layer_;
            }
            layer = index;
        }
        if (layer >= 0 && layer_ < 0) entryAzimuth_ = pose.azimuthDeg;   // entering the space above the keys
        if (layer != layer_) {
            out.motors.clearLevels();
            if (layer >= 0) {
                out.events.emit("layer", static_cast<float>(layer));
                core::PatternRequest point;
                point.kind = core::PatternKind::Point;
                point.motors = tactile::motors::bit(fretMotor(std::min(layer, 7)));
                point.level = static_cast<float>(core::kRatedLevel + 3);
                point.duration = 0.06;
                point.voice = 0;
                out.motors.trigger(point);
            }
            layer_ = layer;
        }
        if (layer_ >= 0) out.motors.setSoftLevel(fretMotor(std::min(layer_, 7)), static_cast<float>(core::kRatedLevel));
        // Targets for the audio thread: which slot (−1 silence), pitch shift, filter.
        targetLayer_.store(layer_ >= 0 ? (first + layer_) % kMaxLayers : -1, std::memory_order_release);
        const double daz = std::clamp(core::wrapDeg180(pose.azimuthDeg - entryAzimuth_) / 60.0, -1.0, 1.0);
        shiftTarget_.store(daz * params_.get(kShift), std::memory_order_relaxed);
        const double roll = std::clamp(pose.rollDeg / 90.0, -1.0, 1.0);
        cutoffTarget_.store(300.0 * std::pow(40.0, 0.5 * (roll + 1.0)), std::memory_order_relaxed);   // 300 Hz … 12 kHz
    }

    void renderAudio(float* left, float* right, int n) noexcept override
    {
        // Which slot the hand is on; its slot generation tells whether the audio is still the one
        // the layer was captured with (a new phrase reuses slots).
        const int target = targetLayer_.load(std::memory_order_acquire);
        const int slot = target >= 0 && target < kMaxLayers ? target : -1;
        if (slot >= 0 && (current_ < 0 || !players_[static_cast<std::size_t>(current_)].active ||
                          players_[static_cast<std::size_t>(current_)].slot != slot)) {
            if (current_ >= 0) players_[static_cast<std::size_t>(current_)].active = false;   // fades out
            current_ = current_ == 0 ? 1 : 0;
            GrainPlayer& p = players_[static_cast<std::size_t>(current_)];
            const CapturedLayer& layer = listener_.slotLayer(slot);
            p.start(slot, listener_.slotGeneration(slot), fs_, layer.noteCount > 0 ? layer.notes[0] : 0);
            p.gain = 0.0;
        } else if (slot < 0 && current_ >= 0) {
            players_[static_cast<std::size_t>(current_)].active = false;
            current_ = -1;
        }
        for (auto& p : players_)   // a slot reopened under a player: it fades out
            if (p.slot >= 0 && p.generation != listener_.slotGeneration(p.slot)) p.active = false;
        if (players_[0].slot < 0 && players_[1].slot < 0) return;   // silent: adds nothing

        const double shiftTarget = shiftTarget_.load(std::memory_order_relaxed);
        const double cutoffTarget = cutoffTarget_.load(std::memory_order_relaxed);
        const double stretch = params_.get(kStretch);
        const double spread = params_.get(kSpread) / 100.0;
        const double volume = params_.get(kVolume) / 100.0;
        for (int i = 0; i < n; ++i) {
            const double rate = std::exp2(shiftSmooth_.next(shiftTarget) / 12.0);
            const double cutoff = cutoffSmooth_.next(cutoffTarget);
            if ((i & 31) == 0) filter_.setup(std::min(cutoff, 0.45 * fs_), 0.7071, fs_);
            double y = 0.0;
            for (auto& p : players_) {
                if (p.slot < 0) continue;
                p.gain = std::clamp(p.gain + (p.active ? fadeStep_ : -fadeStep_), 0.0, 1.0);
                if (!p.active && p.gain <= 0.0) {
                    p.slot = -1;
                    continue;
                }
                y += p.gain * grainSample(p, rate, stretch, spread);
            }
            const auto v = static_cast<float>(volume * filter_.process(y).low);
            left[i] += v;
            right[i] += v;
        }
    }

private:
    void resetControl()
    {
        layer_ = -1;
        entryAzimuth_ = 0.0;
        clearPending_ = true;
    }

    /// Publishes the layer list (audio thread): count | first << 8 | phrase << 16.
    void publish() noexcept
    {
        const int count = listener_.layerCount();
        const int first = count > 0 ? listener_.layer(0).slot : 0;
        published_.store(static_cast<std::uint32_t>(count) | (static_cast<std::uint32_t>(first) << 8) | ((listener_.phrase() & 0xFFu) << 16),
                         std::memory_order_release);
    }

    double grainSample(GrainPlayer& p, double rate, double stretch, double spread) noexcept
    {
        const float* audio = listener_.slotAudio(p.slot);
        const int length = listener_.slotLength(p.slot);
        const int g = p.grainLength;
        // The head walks through the note `stretch` times slower than real time, looping over
        // the body (40 ms after the onset to the end of what is captured).
        const double loopStart = std::min(0.04 * fs_, 0.5 * length);
        const double span = static_cast<double>(g) * rate + 2.0;
        const double loopEnd = std::max(loopStart + 1.0, static_cast<double>(length) - span);
        p.head += 1.0 / stretch;
        if (p.head >= loopEnd) p.head = loopStart + std::fmod(p.head - loopStart, std::max(1.0, loopEnd - loopStart));
        double y = 0.0;
        for (std::size_t k = 0; k < 2; ++k) {
            if (p.age[k] >= g) {   // a new grain: from the head, jittered by the spread …
                p.age[k] = 0;
                const double jitter = spread * random_.uniform(-1.0, 1.0) * 0.1 * fs_;
                const double last = std::max(0.0, static_cast<double>(length) - span);
                double at = p.head + jitter;
                // … moved by whole periods of the layer's (first) note to where the other grain
                // reads now, so the two overlap in phase (no beating, the pitch stays clean).
                const double other = p.pos[1 - k];
                if (p.period > 1.0 && p.age[1 - k] > 0) {
                    at = other + std::round((at - other) / p.period) * p.period;
                    while (at > last && at - p.period >= 0.0) at -= p.period;
                    while (at < 0.0 && at + p.period <= last) at += p.period;
                }
                p.pos[k] = std::clamp(at, 0.0, last);
            }
            const double w = 0.5 - 0.5 * std::cos(dsp::kTwoPi * p.age[k] / g);
            const double at = p.pos[k];
            const auto i0 = static_cast<int>(at);
            if (i0 >= 0 && i0 + 1 < length) {
                const double frac = at - i0, a = static_cast<double>(audio[i0]), b = static_cast<double>(audio[i0 + 1]);
                y += w * (a + frac * (b - a));
            }
            p.pos[k] += rate;
            ++p.age[k];
        }
        return y;
    }

    ParameterSet params_;
    double fs_ = 48000.0;
    NoteListener listener_;
    std::vector<float> mono_;
    bool midi_ = false;                              ///< audio thread: a MIDI note-on came (the notes come from MIDI from then on)
    dsp::Random random_ {1};
    double fadeStep_ = 0.001;
    std::array<GrainPlayer, 2> players_ {};
    int current_ = -1;                               ///< audio thread: the player fading in/holding
    dsp::OnePole shiftSmooth_ {}, cutoffSmooth_ {};
    dsp::StateVariableFilter filter_ {};
    core::SpscQueue<CaptureRecord, 64> captures_;   ///< audio → control: notes found
    std::atomic<std::uint32_t> published_ {0};       ///< audio → control: the layer list
    std::atomic<int> targetLayer_ {-1};              ///< control → audio: slot of the layer under the hand
    std::atomic<double> shiftTarget_ {0.0}, cutoffTarget_ {12000.0};
    int layer_ = -1;                                 ///< control: the layer under the hand (−1: on the keys)
    double entryAzimuth_ = 0.0;
    bool clearPending_ = true;
};

} // namespace

std::unique_ptr<core::Scene> makeLayeredKeyboardScene() { return std::make_unique<LayeredKeyboardScene>(); }

} // namespace armadillo::instruments
