#pragma once
// Plays a Score onto a MotorCanvas, locked to a clock: the host's transport when it is valid
// (seek, loop and tempo changes land on the right event), otherwise its own clock from dt.
// What sounds at a position is computed from the position alone, so a jump anywhere shows
// exactly what the score has there; patterns are restarted on a jump with their remaining time.
#include "Core/Scene.h"
#include "Tactile/Score.h"
#include "Tactile/ScoreFollower.h"
#include <array>
#include <cstddef>
#include <vector>

namespace armadillo::tactile {

class ScorePlayer {
public:
    enum class Sync {
        Seconds,   ///< transport.seconds is score time (the user's recording starts at 0)
        Beats,     ///< transport.ppq is the score's beat (the score's tempo map is ignored)
    };

    /// Not real-time.
    void setScore(Score score);
    const Score& score() const noexcept { return score_; }
    void setSync(Sync sync) noexcept { sync_ = sync; }
    /// Scales every level (0..1.5).
    void setIntensity(float intensity) noexcept { intensity_ = intensity; }
    /// Own clock back to 0; the next control() starts every running pattern afresh.
    void reset() noexcept;

    /// One control step: dt s since the previous one. Writes every motor's sustained target
    /// (0 where no note sounds) and starts/stops the pattern voices the score uses. Real-time:
    /// bounded work per step (a cursor per voice; a binary search only after a jump).
    /// With `follow` (audio comes in), the recording places the score instead of the clock:
    /// the followed notes sound when the follower hears them, amplitude parts take the
    /// recording's envelope, and everything else plays at the position the alignment gives
    /// (the followed note heard last, or the cues of a texture score). Nothing plays before
    /// the recording's first sound.
    void control(const core::Transport& transport, double dt, core::MotorCanvas& canvas, const FollowState* follow = nullptr) noexcept;
    /// The level a note of an amplitude-following part has at envelope `amplitude` (linear):
    /// the part's curve from floor to top mapped onto the note's written levels (lowest..highest).
    /// Below the floor: the lowest level, or 0 when `offBelowFloor`.
    static float amplitudeLevel(const ScoreNote& note, const ScorePart& part, float amplitude, bool offBelowFloor) noexcept;

    double position() const noexcept { return position_; }   ///< s of score time, last step
    bool finished() const noexcept { return position_ >= score_.length; }

private:
    void silence(core::MotorCanvas& canvas) noexcept;
    long activePattern(int voice, double position) noexcept;

    /// Which pattern (index + 1, 0 = none) a voice plays from `start` until the next span:
    /// computed once per score, so a control step never scans the pattern list.
    struct VoiceSpan {
        double start = 0.0;
        long pattern = 0;
    };

    Score score_ {};
    Sync sync_ = Sync::Seconds;
    float intensity_ = 1.0f;
    double ownClock_ = 0.0;
    double position_ = 0.0;
    double previous_ = -1.0;                       ///< last position (s); < 0: none yet
    bool resync_ = true;
    std::array<long, core::kPatternVoices> running_ {}; ///< index into score_.patterns + 1; 0 = none
    std::array<bool, core::kPatternVoices> used_ {}; ///< voices the score writes (others left alone)
    std::array<std::vector<VoiceSpan>, core::kPatternVoices> spans_ {}; ///< per voice, by start
    std::array<std::size_t, core::kPatternVoices> spanCursor_ {};   ///< span of the last step
    double longestNote_ = 0.0;
    std::vector<int> followedOf_;   ///< per note: its followed event, -1 = not followed
    std::vector<std::vector<int>> events_;   ///< followedEvents(score_)
    std::vector<double> eventLength_;        ///< per event: s from its start to its longest note's end
};

} // namespace armadillo::tactile
