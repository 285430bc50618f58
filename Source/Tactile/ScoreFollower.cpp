// Score follower (docs/TACTILE.md, "Following the recording").
//
// Every hop (2.5 ms) of mono audio:
//   - loudness: the hop's RMS; a noise floor (learnt over the first 100 ms, then following the
//     quietest hops down at once and creeping up 1.5 dB/s); a gate 12 dB above it (and above −66 dBFS); a dip (the gate closing,
//     or 10 dB under the note's peak) followed by a rise of 8 dB is an onset (a tongued or new
//     note);
//   - pitch: the normalised autocorrelation of the last 20 ms at the periods of the current
//     event's pitches, the next event's and the one after's (fractional lags, linear interpolation). A bassoon-like
//     tone gives ≈ 1 at its own period and ≤ 0.4 at a semitone's; white noise ≈ 0;
//   - alignment: left to right through the followed notes. The next note (or the one after, if
//     one was missed) takes over when it matches at least `pitchThreshold` and `switchMargin`
//     better than the current one for `confirmHops` hops; a note of the same pitch as the one
//     before it takes over only at an onset. Tempo, rubato and fermatas need no model: a note
//     lasts until the next one is heard;
//   - one envelope per part (its attack/release), and the cues: from the first sound on, score
//     time runs with the audio; a cue's detector firing within its window moves score time to
//     the cue's time; a cue not seen by the end of its window is passed where it stands.
#include "Tactile/ScoreFollower.h"
#include "Core/Errors.h"
#include <algorithm>
#include <cmath>

namespace armadillo::tactile {

static_assert(std::atomic<double>::is_always_lock_free, "the follower publishes doubles lock-free");
static_assert(std::atomic<std::uint64_t>::is_always_lock_free, "the follower publishes 64-bit words lock-free");

std::vector<std::vector<int>> followedEvents(const Score& score)
{
    std::vector<std::vector<int>> events;
    double first = 0.0;
    for (std::size_t i = 0; i < score.notes.size(); ++i) {
        const ScoreNote& n = score.notes[i];
        if (n.part < 0 || !score.parts[static_cast<std::size_t>(n.part)].followNotes || !(n.pitchHz > 0.0)) continue;
        if (events.empty() || n.start > first + kEventTogether) {
            events.emplace_back();
            first = n.start;
        }
        events.back().push_back(static_cast<int>(i));
    }
    return events;
}

namespace {
constexpr std::uint64_t kFrameMask = (std::uint64_t(1) << 44) - 1;
constexpr float kMinGate = 5.0e-4f;   // −66 dBFS
constexpr double kNoHold = 1e300;
}

void ScoreFollower::prepare(const Score& score, double sampleRate, const FollowerParams& params)
{
    if (!(sampleRate >= 8000.0 && sampleRate <= 192000.0))
        throw core::InputError("", 0, "sampleRate", "the score follower needs a sample rate of 8000..192000 Hz");
    params_ = params;
    sampleRate_ = sampleRate;
    hop_ = std::max(8, static_cast<int>(std::lround(sampleRate * params.hopSeconds)));
    window_ = std::clamp(static_cast<int>(std::lround(sampleRate * params.windowSeconds)), 32, kRing / 4);
    notes_.clear();
    parts_ = score.parts;
    cues_ = score.cues;
    const std::vector<std::vector<int>> events = followedEvents(score);
    double longest = 0.0;
    for (const auto& event : events)
        for (const int i : event) longest = std::max(longest, score.notes[static_cast<std::size_t>(i)].end - score.notes[static_cast<std::size_t>(i)].start);
    for (std::size_t e = 0; e < events.size(); ++e) {
        // The event's own notes, then the followed notes of earlier events still held at its
        // start (a bass under the melody): what the recording should sound while it is current.
        std::vector<int> sounding = events[e];
        const double start = score.notes[static_cast<std::size_t>(events[e].front())].start;
        for (std::size_t k = e; k-- > 0 && score.notes[static_cast<std::size_t>(events[k].front())].start >= start - longest;)
            for (const int i : events[k])
                if (score.notes[static_cast<std::size_t>(i)].end > start + kEventTogether) sounding.push_back(i);
        Note f;
        for (const int i : sounding) {
            const ScoreNote& n = score.notes[static_cast<std::size_t>(i)];
            const double period = sampleRate / n.pitchHz;
            if (period + window_ + 2 >= kRing)
                throw core::InputError(score.source, n.line, "pitch", "pitch too low for the follower at this sample rate");
            bool known = false;
            for (int k = 0; k < f.pitches; ++k) known = known || std::fabs(f.periodSamples[static_cast<std::size_t>(k)] / period - 1.0) < 0.01;
            if (!known && f.pitches < kEventPitches) f.periodSamples[static_cast<std::size_t>(f.pitches++)] = period;
        }
        if (!notes_.empty()) {
            const Note& prev = notes_.back();
            bool same = prev.pitches == f.pitches;
            for (int k = 0; same && k < f.pitches; ++k) {
                bool found = false;
                for (int j = 0; j < prev.pitches; ++j)
                    found = found || std::fabs(prev.periodSamples[static_cast<std::size_t>(j)] / f.periodSamples[static_cast<std::size_t>(k)] - 1.0) < 0.01;
                same = found;
            }
            f.repeatsPrevious = same;
        }
        notes_.push_back(f);
    }
    const double hopS = hop_ / sampleRate;
    for (std::size_t p = 0; p < parts_.size(); ++p) {
        attackCoef_[p] = static_cast<float>(1.0 - std::exp(-hopS / (parts_[p].attackMs * 1e-3)));
        releaseCoef_[p] = static_cast<float>(1.0 - std::exp(-hopS / (parts_[p].releaseMs * 1e-3)));
    }
    floorRise_ = static_cast<float>(std::pow(10.0, 1.5 / 20.0 * hopS));
    peakDecay_ = static_cast<float>(std::pow(10.0, -6.0 / 20.0 * hopS));
    cueAttack_ = static_cast<float>(1.0 - std::exp(-hopS / 0.010));
    cueRelease_ = static_cast<float>(1.0 - std::exp(-hopS / 0.150));
    ring_.fill(0.0f);
    written_ = 0;
    resetRequested_.store(false);
    reset();
}

void ScoreFollower::reset() noexcept
{
    hopFill_ = 0;
    hopEnergy_ = 0.0;
    noiseFloor_ = 1e-4f;
    hopsSinceReset_ = 0;
    level_ = peak_ = dipLevel_ = 0.0f;
    dipped_ = true;
    gate_ = false;
    onsetEvent_ = false;
    recentLevels_.fill(0.0f);
    recentIndex_ = 0;
    current_ = -1;
    onsetFrame_ = written_;
    candidate_ = -1;
    confirm_ = 0;
    heard_ = false;
    firstSoundFrame_ = 0;
    cueShift_ = 0.0;
    holdAt_ = kNoHold;
    nextCue_ = 0;
    env_.fill(0.0f);
    cueEnvelope_ = 0.0f;
    sounding_ = false;
    sinceOnsetEvent_ = 1 << 20;
    publish();
}

void ScoreFollower::process(const float* const* in, int channels, int n) noexcept
{
    if (resetRequested_.exchange(false, std::memory_order_acq_rel)) reset();
    if (!in || channels < 1 || n <= 0) return;
    const float scale = 1.0f / static_cast<float>(channels);
    for (int i = 0; i < n; ++i) {
        float x = 0.0f;
        for (int c = 0; c < channels; ++c)
            if (in[c]) x += in[c][i];
        x *= scale;
        if (!std::isfinite(x)) x = 0.0f;
        ring_[static_cast<std::size_t>(written_ & (kRing - 1))] = x;
        ++written_;
        hopEnergy_ += static_cast<double>(x) * static_cast<double>(x);
        if (++hopFill_ == hop_) {
            analyse();
            hopFill_ = 0;
            hopEnergy_ = 0.0;
        }
    }
    pubFrames_.store(written_, std::memory_order_release);
}

bool ScoreFollower::hasPitch(int e, double period) const noexcept
{
    if (e < 0 || e >= static_cast<int>(notes_.size())) return false;
    const Note& n = notes_[static_cast<std::size_t>(e)];
    for (int k = 0; k < n.pitches; ++k)
        if (std::fabs(n.periodSamples[static_cast<std::size_t>(k)] / period - 1.0) < 0.01) return true;
    return false;
}

float ScoreFollower::correlation(double period) const noexcept
{
    const auto lag = static_cast<std::uint64_t>(period);
    const float f = static_cast<float>(period - static_cast<double>(lag));
    const std::uint64_t end = written_;
    const auto w = static_cast<std::uint64_t>(window_);
    if (end < w + lag + 1) return 0.0f;
    float ab = 0.0f, aa = 0.0f, bb = 0.0f;
    constexpr std::uint64_t mask = kRing - 1;
    for (std::uint64_t j = end - w; j < end; ++j) {
        const float b = ring_[static_cast<std::size_t>(j & mask)];
        const float a = (1.0f - f) * ring_[static_cast<std::size_t>((j - lag) & mask)] + f * ring_[static_cast<std::size_t>((j - lag - 1) & mask)];
        ab += a * b;
        aa += a * a;
        bb += b * b;
    }
    const float d = std::sqrt(aa * bb);
    return d > 1e-12f ? ab / d : 0.0f;
}

void ScoreFollower::analyse() noexcept
{
    level_ = static_cast<float>(std::sqrt(hopEnergy_ / hop_));
    const float recentMin = trackLevel();
    // Envelopes.
    for (std::size_t p = 0; p < parts_.size(); ++p) {
        float& e = env_[p];
        e += (level_ - e) * (level_ > e ? attackCoef_[p] : releaseCoef_[p]);
    }
    cueEnvelope_ += (level_ - cueEnvelope_) * (level_ > cueEnvelope_ ? cueAttack_ : cueRelease_);
    const float r0 = alignNotes();
    sounding_ = gate_ || (current_ >= 0 && r0 >= params_.pitchThreshold) || (current_ >= 0 && onsetFrame_ == written_);
    if (!heard_ && (gate_ || current_ >= 0)) {
        heard_ = true;
        firstSoundFrame_ = written_ - static_cast<std::uint64_t>(hop_);
    }
    followCues(recentMin);
    publish();
}

float ScoreFollower::trackLevel() noexcept
{
    // Noise floor, gate, dips and onsets.
    // The first 100 ms after a start learn the floor (the lowest hop); the gate waits for them.
    const bool learning = hopsSinceReset_ < 40;
    if (hopsSinceReset_ == 0 || level_ < noiseFloor_) noiseFloor_ = std::max(level_, 1e-6f);
    else if (!learning) noiseFloor_ *= floorRise_;
    ++hopsSinceReset_;
    const float open = std::max(4.0f * noiseFloor_, kMinGate);
    if (!gate_ && !learning && level_ > open) gate_ = true;
    else if (gate_ && level_ < 0.6f * open) gate_ = false;
    peak_ = std::max(peak_ * peakDecay_, level_);
    if (!gate_ || level_ < 0.316f * peak_) {
        if (!dipped_) {
            dipped_ = true;
            dipLevel_ = level_;
        } else {
            dipLevel_ = std::min(dipLevel_, level_);
        }
    }
    onsetEvent_ = false;
    if (dipped_ && gate_ && level_ > 2.5f * std::max(dipLevel_, noiseFloor_)) {
        onsetEvent_ = true;
        dipped_ = false;
        peak_ = level_;
        sinceOnsetEvent_ = 0;
    } else if (sinceOnsetEvent_ < (1 << 20)) {
        ++sinceOnsetEvent_;
    }
    float recentMin = level_;
    for (float l : recentLevels_) recentMin = std::min(recentMin, l);
    recentLevels_[static_cast<std::size_t>(recentIndex_)] = level_;
    recentIndex_ = (recentIndex_ + 1) % static_cast<int>(recentLevels_.size());
    return recentMin;
}

void ScoreFollower::matchCandidates(PitchMatches& rp, CandidateMatches& r) noexcept
{
    const int count = static_cast<int>(notes_.size());
    {
        std::array<double, kCandidates * kEventPitches> seenPeriod {};
        std::array<float, kCandidates * kEventPitches> seenR {};
        int seen = 0;
        for (int c = 0; c < kCandidates; ++c) {
            const int idx = current_ + c;
            if (idx < 0 || idx >= count) continue;
            const Note& e = notes_[static_cast<std::size_t>(idx)];
            for (int k = 0; k < e.pitches; ++k) {
                const double period = e.periodSamples[static_cast<std::size_t>(k)];
                float v = -1.0f;
                for (int j = 0; j < seen && v < -0.5f; ++j)
                    if (seenPeriod[static_cast<std::size_t>(j)] == period) v = seenR[static_cast<std::size_t>(j)];
                if (v < -0.5f) {
                    v = std::max(0.0f, correlation(period));
                    seenPeriod[static_cast<std::size_t>(seen)] = period;
                    seenR[static_cast<std::size_t>(seen++)] = v;
                }
            }
        }
        // A pitch whose period also fits a higher pitch in play (an octave, a twelfth...: its
        // frequency k times this one's) is credited only with what that pitch's period does not
        // explain: G2 is not heard just because D5, its sixth harmonic, sounds.
        for (int c = 0; c < kCandidates; ++c) {
            const int idx = current_ + c;
            if (idx < 0 || idx >= count) continue;
            const Note& e = notes_[static_cast<std::size_t>(idx)];
            float sum = 0.0f;
            for (int k = 0; k < e.pitches; ++k) {
                const double period = e.periodSamples[static_cast<std::size_t>(k)];
                float v = 0.0f, above = 0.0f;
                for (int j = 0; j < seen; ++j) {
                    const double ratio = period / seenPeriod[static_cast<std::size_t>(j)];
                    if (ratio == 1.0) v = seenR[static_cast<std::size_t>(j)];
                    else if (ratio > 1.9 && std::fabs(ratio - std::round(ratio)) < 0.015 * ratio) above = std::max(above, seenR[static_cast<std::size_t>(j)]);
                }
                v = std::max(0.0f, v - above);
                rp[static_cast<std::size_t>(c)][static_cast<std::size_t>(k)] = v;
                sum += v;
            }
            r[static_cast<std::size_t>(c)] = std::min(1.0f, sum);
        }
    }
}

float ScoreFollower::alignNotes() noexcept
{
    // Notes: a left-to-right alignment over the followed events. An event's match is the sum of
    // its pitches' correlations (each ≥ 0, the sum at most 1): in a mix of harmonic tones of
    // unrelated periods the correlation at one tone's period is about that tone's share of the
    // energy, so a chord that sounds scores ≈ 1 and each of its notes alone ≈ its share.
    const int count = static_cast<int>(notes_.size());
    PitchMatches rp {};
    CandidateMatches r {};
    r.fill(-1.0f);
    if (count > 0 && level_ > 1e-5f) {
        matchCandidates(rp, r);
        // What event a explains that event b does not: its pitches that b lacks.
        const auto exclusive = [&](int a, int b) {
            const int ia = current_ + a, ib = current_ + b;
            const Note& e = notes_[static_cast<std::size_t>(ia)];
            float sum = 0.0f;
            for (int k = 0; k < e.pitches; ++k)
                if (!hasPitch(ib, e.periodSamples[static_cast<std::size_t>(k)])) sum += rp[static_cast<std::size_t>(a)][static_cast<std::size_t>(k)];
            return std::min(1.0f, sum);
        };
        int best = -1;
        for (int c = 1; c < kCandidates; ++c) {
            const int idx = current_ + c;
            if (idx < 0 || idx >= count) continue;
            const float rc = r[static_cast<std::size_t>(c)];
            if (rc < params_.pitchThreshold) continue;
            if (current_ >= 0 && !notes_[static_cast<std::size_t>(idx)].repeatsPrevious && exclusive(c, 0) < exclusive(0, c) + params_.switchMargin)
                continue;
            // An event of the same pitches as the one before it shows itself only by its onset.
            if (notes_[static_cast<std::size_t>(idx)].repeatsPrevious && (c != 1 || sinceOnsetEvent_ > 24)) continue;
            if (c == 2 && rc < r[1] + params_.switchMargin) continue;   // the next event first
            best = c;
            break;
        }
        if (best > 0 && best == candidate_) {
            ++confirm_;
        } else {
            candidate_ = best;
            confirm_ = best > 0 ? 1 : 0;
        }
        if (best > 0 && (confirm_ >= params_.confirmHops || notes_[static_cast<std::size_t>(current_ + best)].repeatsPrevious)) {
            current_ += best;
            onsetFrame_ = written_;
            candidate_ = -1;
            confirm_ = 0;
            peak_ = std::max(peak_, level_);
        }
    }
    return r[0];
}

void ScoreFollower::followCues(float recentMin) noexcept
{
    // Cues: score time runs with the audio from the first sound; a cue seen moves it, and a
    // cue not yet seen holds score time at its own time until it is seen or its window ends.
    holdAt_ = kNoHold;
    if (heard_ && nextCue_ < static_cast<int>(cues_.size())) {
        const ScoreCue& c = cues_[static_cast<std::size_t>(nextCue_)];
        const double position = static_cast<double>(written_ - firstSoundFrame_) / sampleRate_ + cueShift_;
        bool seen = false;
        switch (c.detect) {
        case ScoreCue::Detect::None: break;
        case ScoreCue::Detect::Onset: seen = gate_ && level_ >= 2.8f * std::max(recentMin, noiseFloor_); break;
        case ScoreCue::Detect::Loud: seen = cueEnvelope_ >= static_cast<float>(std::pow(10.0, c.levelDb / 20.0)); break;
        case ScoreCue::Detect::Quiet: seen = cueEnvelope_ <= static_cast<float>(std::pow(10.0, c.levelDb / 20.0)); break;
        }
        if (c.detect == ScoreCue::Detect::None) {
            if (position >= c.time) ++nextCue_;
        } else if (seen && position >= c.time - c.window) {
            cueShift_ += c.time - position;
            ++nextCue_;
        } else if (position > c.time + c.window) {
            ++nextCue_;   // never seen: score time returns to the audio's clock
        } else {
            holdAt_ = c.time - 1e-3;   // just before it: what starts at the cue waits for it
        }
    }
}

void ScoreFollower::publish() noexcept
{
    pubNote_.store((static_cast<std::uint64_t>(current_ + 1) << 44) | (onsetFrame_ & kFrameMask), std::memory_order_release);
    pubSounding_.store(sounding_, std::memory_order_relaxed);
    pubFirstSound_.store(heard_ ? firstSoundFrame_ + 1 : 0, std::memory_order_relaxed);
    pubCueShift_.store(cueShift_, std::memory_order_relaxed);
    pubHoldAt_.store(holdAt_, std::memory_order_relaxed);
    pubCues_.store(nextCue_, std::memory_order_relaxed);
    for (std::size_t p = 0; p < pubEnv_.size(); ++p) pubEnv_[p].store(env_[p], std::memory_order_relaxed);
    pubFrames_.store(written_, std::memory_order_release);
}

FollowState ScoreFollower::state() const noexcept
{
    FollowState s;
    const std::uint64_t frames = pubFrames_.load(std::memory_order_acquire);
    const std::uint64_t note = pubNote_.load(std::memory_order_acquire);
    s.note = static_cast<int>(note >> 44) - 1;
    const std::uint64_t onset = note & kFrameMask;
    const std::uint64_t now = frames & kFrameMask;
    s.sinceOnset = now >= onset ? static_cast<double>(now - onset) / sampleRate_ : 0.0;
    s.sounding = pubSounding_.load(std::memory_order_relaxed);
    const std::uint64_t first = pubFirstSound_.load(std::memory_order_relaxed);
    s.heard = first != 0;
    s.position = s.heard && frames + 1 >= first ? static_cast<double>(frames - (first - 1)) / sampleRate_ + pubCueShift_.load(std::memory_order_relaxed) : -1.0;
    if (s.heard) s.position = std::min(s.position, pubHoldAt_.load(std::memory_order_relaxed));
    s.cuesPassed = pubCues_.load(std::memory_order_relaxed);
    for (std::size_t p = 0; p < s.envelope.size(); ++p) s.envelope[p] = pubEnv_[p].load(std::memory_order_relaxed);
    s.audioSeconds = static_cast<double>(frames) / sampleRate_;
    return s;
}

} // namespace armadillo::tactile
