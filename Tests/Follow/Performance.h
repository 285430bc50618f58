#pragma once
// Recordings synthesised for the follower's tests and benchmark: a bassoon-like tone playing a
// melody with its own timing (tempo changes, a fermata, another start), optionally with white
// noise at a given SNR, and a drum-and-bass test signal. Every onset and envelope value the
// tests compare against comes from here, i.e. from what was actually synthesised.
#include "Core/Csv.h"
#include "Core/Wav.h"
#include "Tactile/Score.h"
#include <cmath>
#include <random>
#include <vector>

namespace armadillo::test {

struct PlayedNote {
    double onset = 0.0;     ///< s in the recording
    double end = 0.0;       ///< s: the tone has faded by here (slurred notes: the next onset)
    double pitchHz = 0.0;
    int scoreNote = -1;     ///< index in Score::notes
};

struct Performance {
    core::AudioBuffer audio;
    std::vector<PlayedNote> notes;
    std::vector<double> envelope;   ///< the synthesised amplitude, one value per sample
    double envelopeAt(double t) const
    {
        const auto i = static_cast<std::size_t>(std::max(0.0, t * audio.sampleRate));
        return i < envelope.size() ? envelope[i] : 0.0;
    }
};

struct PerformanceStyle {
    double start = 1.37;          ///< s of silence before the first note
    double tempoSwing = 0.20;     ///< ±: the local tempo is score × (1 + swing·sin(2π·beat/period))
    double swingPeriodBeats = 7.0;
    double firstNoteSeconds = 6.9;   ///< the fermata: the opening note's length (the score says 4.8 s)
    double snrDb = 1000.0;        ///< white noise at this SNR (signal RMS over its sounding part)
    double sampleRate = 48000.0;
    std::uint64_t seed = 11;
    double crescendoFrom = 0.08, crescendoTo = 0.5;   ///< peak amplitude over the opening note
};

/// Score-time → performance-time map for notes, rests kept: each note's duration is divided by
/// the local tempo factor at its start; the first note lasts firstNoteSeconds.
inline Performance perform(const tactile::Score& score, const std::vector<int>& followed, const PerformanceStyle& st)
{
    Performance p;
    const double fs = st.sampleRate;
    std::vector<PlayedNote> played;
    double t = st.start;
    for (std::size_t k = 0; k < followed.size(); ++k) {
        const tactile::ScoreNote& n = score.notes[static_cast<std::size_t>(followed[k])];
        if (k > 0) {   // the gap (rest) before this note, at the local tempo
            const tactile::ScoreNote& prev = score.notes[static_cast<std::size_t>(followed[k - 1])];
            const double beat = score.beatAtSeconds(prev.end);
            const double factor = 1.0 + st.tempoSwing * std::sin(2.0 * 3.14159265358979 * beat / st.swingPeriodBeats);
            t += (n.start - prev.end) / factor;
        }
        const double beat = score.beatAtSeconds(n.start);
        const double factor = 1.0 + st.tempoSwing * std::sin(2.0 * 3.14159265358979 * beat / st.swingPeriodBeats);
        const double dur = k == 0 ? st.firstNoteSeconds : (n.end - n.start) / factor;
        played.push_back({t, t + dur, n.pitchHz, followed[k]});
        t += dur;
    }
    const double total = t + 1.0;
    const auto frames = static_cast<std::size_t>(total * fs);
    std::vector<double> x(frames, 0.0);
    p.envelope.assign(frames, 0.0);
    // A bassoon-like spectrum: weak fundamental, strong 2nd–4th harmonics, then falling.
    static constexpr double kHarmonics[] = {0.35, 1.0, 0.8, 0.65, 0.5, 0.4, 0.3, 0.22, 0.16, 0.12, 0.09, 0.07};
    std::mt19937_64 rng(st.seed);
    std::uniform_real_distribution<double> phase0(0.0, 6.283185307179586);
    std::vector<double> phase(std::size(kHarmonics));
    for (auto& ph : phase) ph = phase0(rng);
    double norm = 0.0;
    for (double a : kHarmonics) norm += a * a;
    norm = 1.0 / std::sqrt(2.0 * norm) * std::sqrt(2.0);   // peak amplitude ≈ the envelope value
    // Articulation: a note followed by a gap (or a note of the same pitch) fades out over 40 ms
    // before it; slurred notes change pitch with continuous amplitude.
    for (std::size_t k = 0; k < played.size(); ++k) {
        PlayedNote& n = played[k];
        const bool last = k + 1 == played.size();
        const bool slurred = !last && played[k + 1].onset - n.end < 1e-9 && std::fabs(played[k + 1].pitchHz / n.pitchHz - 1.0) > 0.01;
        if (!slurred) n.end -= std::min(0.07, 0.3 * (n.end - n.onset));   // tongued: a breath before the next
    }
    for (std::size_t k = 0; k < played.size(); ++k) {
        const PlayedNote& n = played[k];
        const bool slurredIn = k > 0 && std::fabs(played[k - 1].end - n.onset) < 1e-9;
        const bool slurredOut = k + 1 < played.size() && std::fabs(played[k + 1].onset - n.end) < 1e-9;
        const double attack = slurredIn ? 0.0 : 0.035, release = slurredOut ? 0.0 : 0.04;
        const double level = k == 0 ? -1.0 : 0.32 + 0.03 * static_cast<double>(k % 3);
        const auto i0 = static_cast<std::size_t>(n.onset * fs), i1 = static_cast<std::size_t>(n.end * fs);
        for (std::size_t i = i0; i < i1 && i < frames; ++i) {
            const double u = static_cast<double>(i) / fs - n.onset, left = n.end - static_cast<double>(i) / fs;
            double a = level;
            if (k == 0) a = st.crescendoFrom + (st.crescendoTo - st.crescendoFrom) * u / (n.end - n.onset);
            if (attack > 0.0 && u < attack) a *= 0.5 - 0.5 * std::cos(3.14159265358979 * u / attack);
            if (release > 0.0 && left < release) a *= 0.5 - 0.5 * std::cos(3.14159265358979 * left / release);
            p.envelope[i] = a;
            double s = 0.0;
            for (std::size_t h = 0; h < std::size(kHarmonics); ++h) {
                phase[h] += 6.283185307179586 * n.pitchHz * static_cast<double>(h + 1) / fs;
                if (phase[h] > 6.283185307179586) phase[h] -= 6.283185307179586;
                if (n.pitchHz * static_cast<double>(h + 1) < 0.45 * fs) s += kHarmonics[h] * std::sin(phase[h]);
            }
            x[i] = a * s * norm / 2.2;
        }
    }
    if (st.snrDb < 200.0) {
        double energy = 0.0;
        std::size_t sounding = 0;
        for (std::size_t i = 0; i < frames; ++i)
            if (p.envelope[i] > 0.0) {
                energy += x[i] * x[i];
                ++sounding;
            }
        const double rms = std::sqrt(energy / static_cast<double>(std::max<std::size_t>(1, sounding)));
        std::normal_distribution<double> noise(0.0, rms * std::pow(10.0, -st.snrDb / 20.0));
        for (auto& v : x) v += noise(rng);
    }
    p.audio.sampleRate = fs;
    p.audio.channels.assign(2, std::vector<float>(frames));
    for (std::size_t i = 0; i < frames; ++i) p.audio.channels[0][i] = p.audio.channels[1][i] = static_cast<float>(x[i]);
    p.notes = std::move(played);
    return p;
}

/// When `motor` turns on (off in the row before) in the tactile rows near a note that sounds at
/// `onset` s: the first such row within [onset − 0.15 s, onset + 0.3 s], as its time − onset (s);
/// NaN when there is none.
inline double motorOnsetNear(const std::vector<core::TactileRow>& rows, int motor, double onset)
{
    const auto m = static_cast<std::size_t>(motor);
    for (std::size_t i = 1; i < rows.size(); ++i) {
        if (rows[i].t < onset - 0.15) continue;
        if (rows[i].t > onset + 0.3) break;
        if (rows[i].levels[m] > 0 && rows[i - 1].levels[m] == 0) return rows[i].t - onset;
    }
    return std::nan("");
}

} // namespace armadillo::test
