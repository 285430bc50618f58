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

namespace armadillo {

/// What the follower has heard, as the control thread sees it.
struct FollowState {
    bool heard = false;          ///< some sound has come in since the start (or the last reset)
    int note = -1;               ///< followed note sounding or last heard (index into the followed notes), -1 = none yet
    double sinceOnset = 0.0;     ///< s of audio since that note was heard to start
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
    static constexpr int kCandidates = 3;        ///< current note, next, the one after (a missed note)

    /// Not real-time. Notes of parts that follow notes are tracked; every part gets an envelope;
    /// cues are looked for. sampleRate 8000..192000 Hz.
    void prepare(const Score& score, double sampleRate, const FollowerParams& params = {});
    /// Audio thread, real-time: `channels` (≥ 1) planar channels of n samples each, mixed to mono.
    void process(const float* const* in, int channels, int n) noexcept;
    /// Any other thread: the follower starts again from before the first note at the next process().
    void requestReset() noexcept { resetRequested_.store(true, std::memory_order_release); }
    /// Any other thread: what has been heard so far.
    FollowState state() const noexcept;

    /// The followed notes (score order): their index in Score::notes.
    const std::vector<int>& followedNotes() const noexcept { return followed_; }
    double sampleRate() const noexcept { return sampleRate_; }
    int hopSize() const noexcept { return hop_; }

private:
    struct Note {
        double periodSamples = 0.0;
        double expected = 0.0;   ///< s the score gives it
        bool repeatsPrevious = false;
    };
    void reset() noexcept;
    void analyse() noexcept;
    float correlation(double period) const noexcept;
    void publish() noexcept;

    FollowerParams params_ {};
    double sampleRate_ = 48000.0;
    int hop_ = 120, window_ = 960;
    std::vector<Note> notes_;
    std::vector<int> followed_;
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

} // namespace armadillo
