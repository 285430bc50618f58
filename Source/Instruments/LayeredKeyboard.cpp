#include "Instruments/LayeredKeyboard.h"
#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace armadillo::instruments {

namespace {
constexpr double kPiD = 3.14159265358979323846;
constexpr int kHarmonics = 8;
constexpr double kFundamentalShare = 0.2;   ///< the fundamental's peak vs the candidate's strongest harmonic
constexpr double kNextNoteShare = 0.3;      ///< a further note's salience vs the first one's
constexpr double kTonalShare = 0.12;        ///< the first note's partials vs all peak amplitude

double midiToHz(int midi) { return 440.0 * std::pow(2.0, (midi - 69) / 12.0); }
} // namespace

void Fft::prepare(int size)
{
    if (size < 2 || (size & (size - 1)) != 0) throw std::invalid_argument("FFT size must be a power of two");
    n_ = size;
    int bits = 0;
    while ((1 << bits) < size) ++bits;
    bitReversed_.assign(static_cast<std::size_t>(size), 0);
    for (int i = 0; i < size; ++i) {
        int r = 0;
        for (int b = 0; b < bits; ++b)
            if (i & (1 << b)) r |= 1 << (bits - 1 - b);
        bitReversed_[static_cast<std::size_t>(i)] = r;
    }
    twiddles_.resize(static_cast<std::size_t>(size / 2));
    for (int k = 0; k < size / 2; ++k)
        twiddles_[static_cast<std::size_t>(k)] = std::complex<float>(static_cast<float>(std::cos(2.0 * kPiD * k / size)),
                                                                     static_cast<float>(-std::sin(2.0 * kPiD * k / size)));
}

void Fft::forward(std::complex<float>* x) const noexcept
{
    for (int i = 0; i < n_; ++i) {
        const int r = bitReversed_[static_cast<std::size_t>(i)];
        if (r > i) std::swap(x[i], x[r]);
    }
    for (int len = 2; len <= n_; len <<= 1) {
        const int half = len / 2, step = n_ / len;
        for (int start = 0; start < n_; start += len) {
            for (int k = 0; k < half; ++k) {
                const std::complex<float> w = twiddles_[static_cast<std::size_t>(k * step)];
                const std::complex<float> a = x[start + k];
                const std::complex<float> b = x[start + k + half] * w;
                x[start + k] = a + b;
                x[start + k + half] = a - b;
            }
        }
    }
}

std::string noteName(int midi)
{
    static const char* const kNames[12] = {"C", "C#", "D", "D#", "E", "F", "F#", "G", "G#", "A", "A#", "B"};
    const int pc = ((midi % 12) + 12) % 12;
    const int octave = (midi - pc) / 12 - 1;
    return std::string(kNames[pc]) + std::to_string(octave);
}

void NoteListener::prepare(double sampleRate)
{
    fs_ = sampleRate > 0.0 ? sampleRate : 48000.0;
    // N ≈ 85 ms: 4096 at 44.1/48 kHz (10.7 Hz bins), the same duration at other rates.
    int n = 1024;
    while (n < 16384 && n < 0.085 * fs_ * 0.75) n <<= 1;
    fft_.prepare(n);
    hop_ = n / 8;
    window_.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) window_[static_cast<std::size_t>(i)] = static_cast<float>(0.5 - 0.5 * std::cos(2.0 * kPiD * i / n));
    work_.assign(static_cast<std::size_t>(n), {});
    before_.assign(static_cast<std::size_t>(n / 2), 0.0f);
    after_.assign(static_cast<std::size_t>(n / 2), 0.0f);
    current_.assign(static_cast<std::size_t>(n / 2), 0.0f);
    previous_.assign(static_cast<std::size_t>(n / 2), 0.0f);
    history_.assign(static_cast<std::size_t>(4 * n), 0.0f);   // 4N: a power of two
    slotFrames_ = static_cast<std::size_t>(kSlotSeconds * fs_);
    slots_.assign(slotFrames_ * kMaxLayers, 0.0f);
    clear();
}

void NoteListener::clear()
{
    std::fill(history_.begin(), history_.end(), 0.0f);
    written_ = 0;
    std::fill(current_.begin(), current_.end(), 0.0f);
    std::fill(previous_.begin(), previous_.end(), 0.0f);
    lastFlux_ = lastRise_ = 0.0;
    lastLoud_ = false;
    hopFill_ = 0;
    refractory_ = 0;
    pendingHops_ = -1;
    lastOnset_ = -1;
    slotLength_.fill(0);
    recordingSlot_ = -1;
    first_ = layerCount_ = nextSlot_ = 0;
    open_ = CapturedLayer {};
    midiHead_ = midiCount_ = 0;
    midiOpen_ = false;
    ++phrase_;
}

void NoteListener::noteOn(std::int64_t at, int note) noexcept
{
    if (midiCount_ == kMidiQueue || note < 0 || note > 127) {
        ++midiDropped_;
        return;
    }
    const int i = (midiHead_ + midiCount_) % kMidiQueue;
    midiAt_[static_cast<std::size_t>(i)] = std::max<std::int64_t>(at, 0);
    midiNote_[static_cast<std::size_t>(i)] = note;
    ++midiCount_;
}

void NoteListener::completeMidiLayer(int& completed) noexcept
{
    midiOpen_ = false;
    layers_[static_cast<std::size_t>(open_.slot)] = open_;
    ++layerCount_;
    ++completed;
}

void NoteListener::midiNote(std::int64_t at, int note, const ListenerSettings& s, int& completed) noexcept
{
    if (s.hold) return;
    const int maxNotes = std::clamp(s.maxNotes, 1, kMaxChordNotes);
    const auto chord = static_cast<std::int64_t>(kMidiChordSeconds * fs_);
    if (midiOpen_ && at - midiOpenAt_ < chord) {   // one more note of the chord
        for (int k = 0; k < open_.noteCount; ++k)
            if (open_.notes[static_cast<std::size_t>(k)] == note) return;
        if (open_.noteCount < maxNotes) open_.notes[static_cast<std::size_t>(open_.noteCount++)] = note;
        return;
    }
    if (midiOpen_) completeMidiLayer(completed);
    if (pendingHops_ > 0) {   // an audio onset still waiting for its analysis (before MIDI took over): dropped
        pendingHops_ = -1;
        if (recordingSlot_ == open_.slot) recordingSlot_ = -1;
        slotLength_[static_cast<std::size_t>(open_.slot)] = 0;
    }
    onOnset(at, s);
    open_.notes[0] = note;
    open_.noteCount = 1;
    midiOpen_ = true;
    midiOpenAt_ = at;
}

const CapturedLayer& NoteListener::layer(int index) const noexcept
{
    const int i = std::clamp(index, 0, kMaxLayers - 1);
    return layers_[static_cast<std::size_t>((first_ + i) % kMaxLayers)];
}

void NoteListener::spectrumEndingAt(std::int64_t endSample, float* magnitude) noexcept
{
    const int n = fft_.size();
    const auto mask = static_cast<std::int64_t>(history_.size()) - 1;
    for (int i = 0; i < n; ++i) {
        const std::int64_t at = endSample - n + i;
        const float x = at >= 0 && at < written_ ? history_[static_cast<std::size_t>(at & mask)] : 0.0f;
        work_[static_cast<std::size_t>(i)] = {x * window_[static_cast<std::size_t>(i)], 0.0f};
    }
    fft_.forward(work_.data());
    for (int k = 0; k < n / 2; ++k) magnitude[k] = std::abs(work_[static_cast<std::size_t>(k)]);
}

int NoteListener::findNotes(const float* mag, const ListenerSettings& s, int* notes) noexcept
{
    const int n = fft_.size(), bins = n / 2;
    const double binHz = fs_ / n;
    // A sine of amplitude A under a Hann window of N points peaks at A·N/4: amplitudes below are
    // in full-scale units.
    const double toAmplitude = 4.0 / n;
    const double floorAmp = std::pow(10.0, s.floorDb / 20.0);
    int count = 0;
    double total = 0.0;
    for (int k = 2; k + 1 < bins && count < kMaxPeaks; ++k) {
        const double m = mag[k];
        if (!(m > static_cast<double>(mag[k - 1]) && m >= static_cast<double>(mag[k + 1])) || m * toAmplitude < 0.5 * floorAmp) continue;
        // Frequency: the vertex of a parabola through the log magnitudes of the bin and its
        // neighbours, when both are a real part of the lobe (a difference spectrum can have a
        // neighbour cut to 0). Amplitude: the bin's own (at most 1.4 dB low under Hann).
        double delta = 0.0;
        const auto lm = static_cast<double>(mag[k - 1]), rm = static_cast<double>(mag[k + 1]);
        if (lm > 0.05 * m && rm > 0.05 * m) {
            const double l = std::log(lm), c = std::log(m), r = std::log(rm);
            const double den = l - 2.0 * c + r;
            if (den < 0.0) delta = std::clamp(0.5 * (l - r) / den, -0.5, 0.5);
        }
        peaks_[static_cast<std::size_t>(count++)] = {(k + delta) * binHz, m * toAmplitude};
        total += peaks_[static_cast<std::size_t>(count - 1)].amplitude;
    }
    // The strongest peak within 35 cents (at least half a bin) of hz (its index, −1 none).
    auto match = [&](double hz) {
        const double tolerance = std::max(35.0 / 1200.0, std::log2(1.0 + 0.5 * binHz / hz));
        int best = -1;
        for (int i = 0; i < count; ++i) {
            const Peak& p = peaks_[static_cast<std::size_t>(i)];
            if (p.amplitude <= 0.0 || std::fabs(std::log2(p.hz / hz)) > tolerance) continue;
            if (best < 0 || p.amplitude > peaks_[static_cast<std::size_t>(best)].amplitude) best = i;
        }
        return best;
    };
    const int lowNote = std::clamp(s.lowNote, 21, 108), highNote = std::clamp(s.highNote, lowNote, 108);
    const int maxNotes = std::clamp(s.maxNotes, 1, kMaxChordNotes);
    int found = 0;
    double firstSalience = 0.0;
    while (found < maxNotes) {
        int best = -1;
        double bestSalience = 0.0;
        for (int m = lowNote; m <= highNote; ++m) {
            const double f0 = midiToHz(m);
            double salience = 0.0, strongest = 0.0, sum = 0.0, fundamental = 0.0;
            for (int h = 1; h <= kHarmonics && h * f0 < 0.45 * fs_; ++h) {
                const int i = match(h * f0);
                if (i < 0) continue;
                const double a = peaks_[static_cast<std::size_t>(i)].amplitude;
                if (h == 1) fundamental = a;
                salience += a / h;
                sum += a;
                strongest = std::max(strongest, a);
            }
            if (fundamental < floorAmp || fundamental < kFundamentalShare * strongest) continue;
            if (found == 0 && sum < kTonalShare * total) continue;
            if (salience > bestSalience) {
                bestSalience = salience;
                best = m;
            }
        }
        if (best < 0) break;
        if (found == 0) firstSalience = bestSalience;
        else if (bestSalience < kNextNoteShare * firstSalience) break;
        notes[found++] = best;
        // Its partials leave the list. A partial it shares with another note (C4's fifth partial
        // is E6's fundamental) keeps what stands out of the note's smooth spectral envelope: the
        // part above the mean of its neighbouring partials (spectral smoothness).
        const double f0 = midiToHz(best);
        std::array<int, kHarmonics + 2> at {};
        std::array<double, kHarmonics + 2> amp {};
        at.fill(-1);
        for (int h = 1; h <= kHarmonics && h * f0 < 0.45 * fs_; ++h) {
            at[static_cast<std::size_t>(h)] = match(h * f0);
            if (at[static_cast<std::size_t>(h)] >= 0) amp[static_cast<std::size_t>(h)] = peaks_[static_cast<std::size_t>(at[static_cast<std::size_t>(h)])].amplitude;
        }
        for (int h = 1; h <= kHarmonics; ++h) {
            const int i = at[static_cast<std::size_t>(h)];
            if (i < 0) continue;
            const double a = amp[static_cast<std::size_t>(h)];
            const double smooth = h == 1 ? a : 0.5 * (amp[static_cast<std::size_t>(h - 1)] + amp[static_cast<std::size_t>(h + 1)]);
            peaks_[static_cast<std::size_t>(i)].amplitude = a - std::min(a, smooth);
        }
    }
    return found;
}

void NoteListener::onOnset(std::int64_t onsetSample, const ListenerSettings& s) noexcept
{
    if (lastOnset_ >= 0 && static_cast<double>(onsetSample - lastOnset_) > s.phraseGap * fs_) {
        // A new phrase: the previous phrase's layers are forgotten.
        first_ = layerCount_ = 0;
        nextSlot_ = 0;
        ++phrase_;
    }
    lastOnset_ = onsetSample;
    // What was ringing just before (the window ending one hop before the onset hop).
    spectrumEndingAt(onsetSample - hop_, before_.data());
    // The next slot; when all are layers, the oldest layer gives its slot up.
    int slot = (first_ + layerCount_) % kMaxLayers;
    if (layerCount_ == kMaxLayers) {
        slot = first_;
        first_ = (first_ + 1) % kMaxLayers;
        --layerCount_;
    }
    ++slotGeneration_[static_cast<std::size_t>(slot)];
    recordingSlot_ = slot;
    // Copy from one hop before the onset up to now out of the history.
    const std::int64_t from = std::max<std::int64_t>(0, onsetSample - hop_);
    const auto mask = static_cast<std::int64_t>(history_.size()) - 1;
    float* dst = slots_.data() + static_cast<std::size_t>(slot) * slotFrames_;
    int len = 0;
    for (std::int64_t at = from; at < written_ && static_cast<std::size_t>(len) < slotFrames_; ++at)
        dst[len++] = history_[static_cast<std::size_t>(at & mask)];
    slotLength_[static_cast<std::size_t>(slot)] = len;
    open_ = CapturedLayer {};
    open_.slot = slot;
    open_.onsetSeconds = static_cast<double>(onsetSample) / fs_;
}

void NoteListener::analyse(const ListenerSettings& s, int& completed, std::int64_t endSample) noexcept
{
    spectrumEndingAt(endSample, after_.data());
    for (std::size_t k = 0; k < after_.size(); ++k) after_[k] = std::max(0.0f, after_[k] - before_[k]);
    open_.noteCount = findNotes(after_.data(), s, open_.notes.data());
    if (open_.noteCount == 0) {   // a knock, a pedal, a cough: no layer
        if (recordingSlot_ == open_.slot) recordingSlot_ = -1;
        slotLength_[static_cast<std::size_t>(open_.slot)] = 0;
        return;
    }
    layers_[static_cast<std::size_t>(open_.slot)] = open_;
    // Layers stay in capture order: slot = (first_ + index) % kMaxLayers.
    ++layerCount_;
    ++completed;
}

int NoteListener::process(const float* mono, int n, const ListenerSettings& s) noexcept
{
    if (!mono || n <= 0 || fft_.size() == 0) return 0;
    int completed = 0;
    const auto mask = static_cast<std::int64_t>(history_.size()) - 1;
    const double floorAmp = std::pow(10.0, s.floorDb / 20.0);
    for (int i = 0; i < n; ++i) {
        float x = mono[i];
        if (!std::isfinite(x)) x = 0.0f;
        history_[static_cast<std::size_t>(written_ & mask)] = x;
        ++written_;
        if (recordingSlot_ >= 0) {
            int& len = slotLength_[static_cast<std::size_t>(recordingSlot_)];
            if (static_cast<std::size_t>(len) < slotFrames_) slots_[static_cast<std::size_t>(recordingSlot_) * slotFrames_ + static_cast<std::size_t>(len++)] = x;
            else recordingSlot_ = -1;
        }
        // MIDI note-ons whose sample has now been heard, and the chord window of the open one.
        while (midiCount_ > 0 && midiAt_[static_cast<std::size_t>(midiHead_)] < written_) {
            const std::int64_t at = midiAt_[static_cast<std::size_t>(midiHead_)];
            const int note = midiNote_[static_cast<std::size_t>(midiHead_)];
            midiHead_ = (midiHead_ + 1) % kMidiQueue;
            --midiCount_;
            if (s.midi) midiNote(at, note, s, completed);
        }
        if (midiOpen_ && written_ - midiOpenAt_ >= static_cast<std::int64_t>(kMidiChordSeconds * fs_)) completeMidiLayer(completed);
        if (++hopFill_ < hop_) continue;
        hopFill_ = 0;
        if (refractory_ > 0) --refractory_;
        if (pendingHops_ > 0 && --pendingHops_ == 0) {
            pendingHops_ = -1;
            analyse(s, completed, written_);
        }
        // Spectral flux of this hop (bins of 50 Hz … 8 kHz).
        spectrumEndingAt(written_, current_.data());
        const double binHz = fs_ / fft_.size();
        const int lo = std::max(1, static_cast<int>(50.0 / binHz)), hi = std::min(static_cast<int>(current_.size()) - 1, static_cast<int>(8000.0 / binHz));
        double rise = 0.0, sum = 0.0;
        for (int k = lo; k <= hi; ++k) {
            const auto c = static_cast<double>(current_[static_cast<std::size_t>(k)]), p = static_cast<double>(previous_[static_cast<std::size_t>(k)]);
            rise += std::max(0.0, c - p);
            sum += p;
        }
        current_.swap(previous_);   // (swapping vectors exchanges pointers: no allocation)
        const double flux = rise / std::max(sum, 1e-9);
        const bool loud = rise * 4.0 / fft_.size() > floorAmp;
        // The rise peaked at the previous hop (the note filled half the window there), and it was
        // a large share of what sounded before.
        const bool onset = refractory_ == 0 && lastLoud_ && lastFlux_ > kOnsetFlux && rise <= lastRise_;
        lastFlux_ = flux;
        lastRise_ = rise;
        lastLoud_ = loud;
        if (onset && !s.hold && !s.midi) {
            refractory_ = kRefractoryHops;
            const std::int64_t at = std::max<std::int64_t>(0, written_ - hop_ - fft_.size() / 2);
            if (pendingHops_ > 0) {   // a short note: analysed on the window that ends where the next one starts
                pendingHops_ = -1;
                analyse(s, completed, at);
            }
            onOnset(at, s);
            // The analysis window ends kAnalysisDelayHops after the onset: it begins a hop after
            // it, past the attack (whose broadband spread would read as partials).
            pendingHops_ = std::max(1, static_cast<int>((at + static_cast<std::int64_t>(kAnalysisDelayHops) * hop_ - written_) / hop_));
        }
    }
    return completed;
}

} // namespace armadillo::instruments
