#pragma once
// Follows the recording the listener plays (docs/TACTILE.md, "Following the recording"): the
// audio thread feeds it blocks; it tracks onsets and the pitch of the score's followed notes
// with an online left-to-right alignment, keeps one envelope per part, and passes the score's
// cues where the recording shows them. The control thread reads the result lock-free.
//
// Threads: prepare() is not real-time (allocates). process() runs on the audio thread: it
// allocates, locks and throws nothing, its buffers are fixed-size and its work per block is
// bounded (a fixed number of correlations of a fixed window per hop). state() and
// requestReset() may be called from any one other thread; results cross through atomics.
#include "Tactile/Score.h"
#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

namespace armadillo::tactile {

/// Notes that start together are one event of the alignment (a chord, a melody note with its
/// bass): notes of parts that follow notes, with a pitch, whose starts lie within this much score
/// time of the event's first note.
inline constexpr double kEventTogether = 0.025;
/// Pitches an event is matched on (the first ones in score order; more notes still sound).
inline constexpr int kEventPitches = 6;

/// The followed notes grouped into events, in score order: each event lists its notes' indices
/// in Score::notes (score order). Shared by the follower and the player, so both count alike.
std::vector<std::vector<int>> followedEvents(const Score& score);

/// What the follower has heard, as the control thread sees it.
struct FollowState {
    bool heard = false;          ///< some sound has come in since the start (or the last reset)
    int note = -1;               ///< followed event sounding or last heard (index into followedEvents()), -1 = none yet
    double sinceOnset = 0.0;     ///< s of audio since that event was heard to start
    bool sounding = false;       ///< the recording sounds now (the note is held, not a rest)
    double position = -1.0;      ///< texture scores: s of score time from the first sound and the cues passed (-1: none yet)
    int cuesPassed = 0;          ///< how many cues the alignment has passed
    std::array<float, kMaxScoreParts> envelope {};   ///< linear amplitude per part (its attack/release)
    double audioSeconds = 0.0;   ///< s of audio processed since the start
};

/// Tunables of the note tracker; the defaults are what the tests and docs describe.
struct FollowerParams {
    double windowSeconds = 0.020;    ///< correlation window (s)
    double hopSeconds = 0.0025;      ///< analysis step (s)
    float pitchThreshold = 0.5f;     ///< normalised autocorrelation at a note's period that says "this pitch sounds"
    float switchMargin = 0.1f;       ///< how much better than the current note the next must match
    int confirmHops = 2;             ///< consecutive hops a change must hold
};

class ScoreFollower {
public:
    static constexpr int kRing = 16384;          ///< samples kept (power of two)
    static constexpr int kCandidates = 3;        ///< current event, next, the one after (a missed event)

    /// Not real-time. Notes of parts that follow notes are tracked; every part gets an envelope;
    /// cues are looked for. sampleRate 8000..192000 Hz.
    void prepare(const Score& score, double sampleRate, const FollowerParams& params = {});
    /// Audio thread, real-time: `channels` (≥ 1) planar channels of n samples each, mixed to mono.
    void process(const float* const* in, int channels, int n) noexcept;
    /// Any other thread: the follower starts again from before the first note at the next process().
    void requestReset() noexcept { resetRequested_.store(true, std::memory_order_release); }
    /// Any other thread: what has been heard so far.
    FollowState state() const noexcept;

    /// How many followed events the alignment runs through.
    int eventCount() const noexcept { return static_cast<int>(notes_.size()); }
    double sampleRate() const noexcept { return sampleRate_; }
    int hopSize() const noexcept { return hop_; }

private:
    /// One event of the alignment: the periods of its pitches and of the notes held into it from
    /// earlier events (distinct, at most kEventPitches, its own first).
    struct Note {
        std::array<double, kEventPitches> periodSamples {};
        int pitches = 0;
        bool repeatsPrevious = false;   ///< the same pitches as the event before
    };
    void reset() noexcept;
    void analyse() noexcept;   // one hop: the steps below, then publish()
    /// The hop's level: noise floor, gate, dips and onsets. Returns the lowest recent level.
    float trackLevel() noexcept;
    using PitchMatches = std::array<std::array<float, kEventPitches>, kCandidates>;
    using CandidateMatches = std::array<float, kCandidates>;
    /// How well each candidate event (current_ + c) and each of its pitches match the hop.
    void matchCandidates(PitchMatches& rp, CandidateMatches& r) noexcept;
    /// Moves current_ to a candidate that clearly sounds. Returns the current event's match.
    float alignNotes() noexcept;
    /// Score time and the cues: seen, missed or held for.
    void followCues(float recentMin) noexcept;
    float correlation(double period) const noexcept;
    /// Whether `period` is one of event e's pitches (within 1 %).
    bool hasPitch(int e, double period) const noexcept;
    void publish() noexcept;

    FollowerParams params_ {};
    double sampleRate_ = 48000.0;
    int hop_ = 120, window_ = 960;
    std::vector<Note> notes_;   ///< the followed events
    std::vector<ScoreCue> cues_;
    std::vector<ScorePart> parts_;
    std::array<float, kMaxScoreParts> attackCoef_ {}, releaseCoef_ {};

    // Audio-thread state.
    std::array<float, kRing> ring_ {};
    std::uint64_t written_ = 0;        ///< samples ever written
    int hopFill_ = 0;
    double hopEnergy_ = 0.0;
    float noiseFloor_ = 1e-4f;
    int hopsSinceReset_ = 0;
    float level_ = 0.0f;               ///< RMS of the last hop
    float peak_ = 0.0f;                ///< loudest hop since the last onset (decaying)
    float dipLevel_ = 0.0f;
    bool dipped_ = true;
    bool gate_ = false;
    bool onsetEvent_ = false;
    std::array<float, 20> recentLevels_ {};   ///< hop levels of the last 50 ms (cue onsets)
    int recentIndex_ = 0;
    int current_ = -1;
    std::uint64_t onsetFrame_ = 0;
    int candidate_ = -1, confirm_ = 0;
    bool heard_ = false;
    std::uint64_t firstSoundFrame_ = 0;
    double cueShift_ = 0.0;
    double holdAt_ = 1e300;            ///< score time held at a cue not yet seen
    int nextCue_ = 0;
    std::array<float, kMaxScoreParts> env_ {};
    float cueEnvelope_ = 0.0f;
    bool sounding_ = false;
    int sinceOnsetEvent_ = 1 << 20;    ///< hops since the last onset
    float floorRise_ = 1.0f, peakDecay_ = 1.0f, cueAttack_ = 1.0f, cueRelease_ = 1.0f;   ///< per hop

    // Published (audio thread → any thread).
    std::atomic<bool> resetRequested_ {false};
    std::atomic<std::uint64_t> pubNote_ {0};        ///< (note + 1) << 44 | onset frame
    std::atomic<std::uint64_t> pubFrames_ {0};
    std::atomic<std::uint64_t> pubFirstSound_ {0};  ///< first sound frame + 1 (0 = none)
    std::atomic<double> pubCueShift_ {0.0};
    std::atomic<double> pubHoldAt_ {1e300};
    std::atomic<int> pubCues_ {0};
    std::atomic<bool> pubSounding_ {false};
    std::array<std::atomic<float>, kMaxScoreParts> pubEnv_ {};
};

} // namespace armadillo::tactile
