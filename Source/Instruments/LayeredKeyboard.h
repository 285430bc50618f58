#pragma once
// The listening half of the "layered-keyboard" scene (thesis §5.2): notes just played on a real
// instrument, found in the audio input — onsets, pitches (polyphonic, at most kMaxChordNotes at
// one onset) — and the audio of each note captured into a slot prepared in advance.
//
// Method (docs/INSTRUMENTS.md, "Layered keyboard"):
// - Onsets: spectral flux. Every hop of H = N/8 samples the magnitude spectrum of the last N
//   samples (Hann window, N = 4096 at 44.1/48 kHz: 85 ms, 10.7 Hz bins, so the partials of most
//   intervals are resolved and their beating does not count); the flux is the sum of the bins'
//   rises over the previous hop, 50 Hz–8 kHz. An onset is a peak of that rise which is above the
//   sensitivity floor and more than kOnsetFlux of the previous spectrum's sum; a note has entered
//   half the window at the peak, so the onset is placed N/2 before it.
//   At most one onset per 8 hops (~85 ms at 48 kHz: notes closer than that are one chord).
// - Pitches: on the N samples from one hop after the onset (past the attack; from the next
//   onset backwards for notes shorter than that), the magnitude spectrum minus the spectrum just before the onset (what was ringing already:
//   earlier notes still sounding are not found again); its peaks (local maxima above half the
//   floor, frequency by parabolic interpolation of the log magnitude, at most kMaxPeaks); then
//   an iterative harmonic sum over the semitones `lowNote`..`highNote`:
//   salience(m) = Σ_{h=1..8} a_h/h, a_h the strongest peak within 35 cents of h·f_m; the best
//   candidate is taken when its fundamental is present (a_1 ≥ 0.2 of its strongest partial) and,
//   for the first note, when its partials hold ≥ 12% of all peak amplitude (a noise burst does
//   not); its partials are removed from the peak list and the search repeats while the next
//   salience is ≥ 0.3 of the first, up to `maxNotes` (≤ 4). Limits: notes an octave (or a
//   twelfth) apart struck together count as one (the upper one's partials are the lower one's);
//   two notes a semitone apart below ~C4 merge into one peak; the range is C3..C7 by default.
// - Capture: the input is kept in a history ring; an onset opens the next of kMaxLayers slots
//   (2 s each) which copies the input from one hop before the onset until the next onset or
//   until full. A layer whose analysis finds no pitch is dropped. A new phrase (an onset after
//   `phraseGap` s of no onset) forgets the previous phrase's layers.
// - MIDI input (an instrument that has it: `settings.midi`): the onsets and pitches come from its
//   note-ons instead (noteOn()), exact; note-ons within kMidiChordSeconds of a layer's first note
//   join it (a chord, at most `maxNotes`, in arrival order); the layer is complete
//   kMidiChordSeconds after its first note. The audio is still what is captured (from one hop
//   before the first note-on), and the audio's own onsets are not looked for.
//
// Real-time: every buffer is sized in prepare(); process() allocates, locks and throws nothing,
// and its work per sample is bounded (one FFT of N points per onset and one per analysis).
#include <array>
#include <complex>
#include <cstdint>
#include <string>
#include <vector>

namespace armadillo::instruments {

/// In-place iterative radix-2 complex FFT of a fixed power-of-two size (tables built in prepare).
class Fft {
public:
    void prepare(int size);   ///< size a power of two ≥ 2 (not real-time)
    int size() const noexcept { return n_; }
    /// Forward transform, X[k] = Σ x[n]·e^{−2πikn/N}. Real-time.
    void forward(std::complex<float>* data) const noexcept;

private:
    int n_ = 0;
    std::vector<int> bitReversed_;
    std::vector<std::complex<float>> twiddles_;   ///< e^{−2πik/N}, k < N/2
};

inline constexpr int kMaxChordNotes = 4;
inline constexpr int kMaxLayers = 8;

/// "C4", "F#5": the MIDI note's name (MIDI 60 = C4, 69 = A4 = 440 Hz). Not real-time.
std::string noteName(int midiNote);

/// One captured layer: the notes found at one onset and the audio from it on.
struct CapturedLayer {
    std::array<int, kMaxChordNotes> notes {};   ///< MIDI note numbers, strongest first
    int noteCount = 0;
    double onsetSeconds = 0.0;                  ///< s since the listener's first sample
    int slot = -1;                              ///< which capture slot holds its audio
};

struct ListenerSettings {
    int lowNote = 48;            ///< C3
    int highNote = 96;           ///< C7
    int maxNotes = kMaxChordNotes;
    double floorDb = -50.0;      ///< dBFS: a hop must be this loud for an onset, a partial for a note
    double phraseGap = 3.0;      ///< s without an onset that ends a phrase
    bool hold = false;           ///< true: capture nothing new (the layers stay as they are)
    bool midi = false;           ///< true: the notes come from MIDI (noteOn()); the audio's onsets are ignored
};

class NoteListener {
public:
    static constexpr double kOnsetFlux = 0.15;       ///< relative spectral flux of an onset
    static constexpr int kAnalysisDelayHops = 9;     ///< the pitch window ends N + H after the onset
    static constexpr int kRefractoryHops = 8;
    static constexpr double kSlotSeconds = 2.0;
    static constexpr double kMidiChordSeconds = 0.030;   ///< note-ons this close to a layer's first are one chord
    static constexpr int kMidiQueue = 64;                ///< note-ons waiting for their sample

    /// Not real-time: sizes every buffer for this sample rate.
    void prepare(double sampleRate);
    /// Forgets every layer and the history (not real-time: it clears the slots).
    void clear();
    /// Audio thread: mono input. Returns the number of layers completed in this call (their
    /// pitch known); read them with layer(). Real-time.
    int process(const float* mono, int n, const ListenerSettings& settings) noexcept;

    /// A MIDI note-on (audio thread, real-time) at sample `at` of the input: samplesProcessed()
    /// plus its offset in the block process() is given next. Used when settings.midi is set;
    /// at most kMidiQueue wait for their sample (more are dropped: midiDropped()).
    void noteOn(std::int64_t at, int note) noexcept;
    /// Samples given to process() so far (the listener's clock).
    std::int64_t samplesProcessed() const noexcept { return written_; }
    std::uint32_t midiDropped() const noexcept { return midiDropped_; }

    /// Layers of the current phrase in capture order, index 0 the oldest (audio thread).
    int layerCount() const noexcept { return layerCount_; }
    const CapturedLayer& layer(int index) const noexcept;
    /// The most recent completed layer (valid after process() returned > 0).
    const CapturedLayer& newest() const noexcept { return layer(layerCount_ - 1); }
    /// A slot's audio and how much of it is written (audio thread; it grows while the note lasts).
    const float* slotAudio(int slot) const noexcept { return slots_.data() + static_cast<std::size_t>(slot) * slotFrames_; }
    int slotLength(int slot) const noexcept { return slotLength_[static_cast<std::size_t>(slot)]; }
    /// Increases each time a slot is reopened for a new layer (players notice their audio changed).
    std::uint32_t slotGeneration(int slot) const noexcept { return slotGeneration_[static_cast<std::size_t>(slot)]; }
    /// Increases with each new phrase.
    std::uint32_t phrase() const noexcept { return phrase_; }
    int fftSize() const noexcept { return fft_.size(); }
    int hopSize() const noexcept { return hop_; }
    double sampleRate() const noexcept { return fs_; }

    /// The pitch analysis alone, on a magnitude spectrum of fftSize()/2 bins (real-time): writes
    /// up to settings.maxNotes MIDI notes into `notes`, returns how many.
    int findNotes(const float* magnitude, const ListenerSettings& settings, int* notes) noexcept;
    /// The layer whose audio a slot holds (audio thread).
    const CapturedLayer& slotLayer(int slot) const noexcept { return layers_[static_cast<std::size_t>(slot)]; }
    static constexpr int kMaxPeaks = 256;

private:
    void spectrumEndingAt(std::int64_t endSample, float* magnitude) noexcept;
    void onOnset(std::int64_t onsetSample, const ListenerSettings& settings) noexcept;
    void analyse(const ListenerSettings& settings, int& completed, std::int64_t endSample) noexcept;
    void midiNote(std::int64_t at, int note, const ListenerSettings& settings, int& completed) noexcept;
    void completeMidiLayer(int& completed) noexcept;

    double fs_ = 48000.0;
    Fft fft_;
    int hop_ = 512;
    std::vector<float> window_;                   ///< Hann, N
    std::vector<std::complex<float>> work_;       ///< N
    std::vector<float> before_, after_;           ///< magnitudes, N/2
    struct Peak {
        double hz = 0.0, amplitude = 0.0;
    };
    std::array<Peak, kMaxPeaks> peaks_ {};
    std::vector<float> history_;                  ///< ring of the input, a power of two ≥ 4N
    std::int64_t written_ = 0;                    ///< samples ever written to history_

    int hopFill_ = 0;
    std::vector<float> current_, previous_;       ///< this hop's and the previous hop's magnitudes, N/2
    double lastFlux_ = 0.0;                       ///< relative flux of the previous hop
    double lastRise_ = 0.0;                       ///< its absolute rise (sum of magnitudes)
    bool lastLoud_ = false;                       ///< its absolute rise was above the floor
    int refractory_ = 0;
    int pendingHops_ = -1;                        ///< hops until the analysis of the open layer; −1 none
    std::int64_t lastOnset_ = -1;

    std::vector<float> slots_;                    ///< kMaxLayers × slotFrames_
    std::size_t slotFrames_ = 0;
    std::array<int, kMaxLayers> slotLength_ {};
    std::array<std::uint32_t, kMaxLayers> slotGeneration_ {};
    int recordingSlot_ = -1;                      ///< the slot the input is appended to; −1 none
    std::array<CapturedLayer, kMaxLayers> layers_ {};   ///< ring: layers_[(first_ + i) % kMaxLayers]
    int first_ = 0, layerCount_ = 0, nextSlot_ = 0;
    CapturedLayer open_ {};                       ///< the layer waiting for its analysis
    std::uint32_t phrase_ = 0;
    std::array<std::int64_t, kMidiQueue> midiAt_ {};   ///< ring of waiting note-ons: sample …
    std::array<int, kMidiQueue> midiNote_ {};          ///< … and note
    int midiHead_ = 0, midiCount_ = 0;
    std::uint32_t midiDropped_ = 0;
    bool midiOpen_ = false;                            ///< open_ is a MIDI layer still taking chord notes
    std::int64_t midiOpenAt_ = 0;
};

} // namespace armadillo::instruments
