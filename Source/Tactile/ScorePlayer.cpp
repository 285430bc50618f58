// Score player (thesis §3.3): position → what sounds there, each control step.
#include "Tactile/ScorePlayer.h"
#include <algorithm>
#include <cmath>

namespace armadillo::tactile {

void ScorePlayer::setScore(Score score)
{
    score_ = std::move(score);
    used_.fill(false);
    for (const auto& p : score_.patterns) used_[static_cast<std::size_t>(p.request.voice)] = true;
    longestNote_ = 0.0;
    for (const auto& n : score_.notes) longestNote_ = std::max(longestNote_, n.end - n.start);
    followedOf_.assign(score_.notes.size(), -1);
    events_ = followedEvents(score_);
    eventLength_.assign(events_.size(), 0.0);
    for (std::size_t e = 0; e < events_.size(); ++e)
        for (const int i : events_[e]) {
            followedOf_[static_cast<std::size_t>(i)] = static_cast<int>(e);
            const ScoreNote& n = score_.notes[static_cast<std::size_t>(i)];
            eventLength_[e] = std::max(eventLength_[e], n.end - score_.notes[static_cast<std::size_t>(events_[e].front())].start);
        }
    // Per voice, the pattern that plays is a step function of the position: it can change only
    // at a start or end of one of the voice's patterns. Between two such boundaries it is the
    // last-listed pattern whose span [start, end) holds the position. One sweep per voice over
    // its boundaries in order, with the started patterns in a heap by listing order (those that
    // have ended are dropped when they come to the top): O(P log P), not P × boundaries.
    for (int v = 0; v < core::kPatternVoices; ++v) {
        auto& spans = spans_[static_cast<std::size_t>(v)];
        spans.clear();
        std::vector<std::size_t> mine;
        std::vector<double> bounds;
        for (std::size_t i = 0; i < score_.patterns.size(); ++i) {
            const ScorePattern& p = score_.patterns[i];
            if (p.request.voice != v) continue;
            mine.push_back(i);
            bounds.push_back(p.start);
            if (std::isfinite(p.end)) bounds.push_back(p.end);
        }
        std::stable_sort(mine.begin(), mine.end(),
                         [&](std::size_t a, std::size_t b) { return score_.patterns[a].start < score_.patterns[b].start; });
        std::sort(bounds.begin(), bounds.end());
        bounds.erase(std::unique(bounds.begin(), bounds.end()), bounds.end());
        std::vector<std::size_t> started;   // a max-heap of pattern indices
        std::size_t next = 0;
        for (double b : bounds) {
            while (next < mine.size() && score_.patterns[mine[next]].start <= b) {
                started.push_back(mine[next++]);
                std::push_heap(started.begin(), started.end());
            }
            while (!started.empty() && !(b < score_.patterns[started.front()].end)) {
                std::pop_heap(started.begin(), started.end());
                started.pop_back();
            }
            const long active = started.empty() ? 0 : static_cast<long>(started.front()) + 1;
            if (spans.empty() || spans.back().pattern != active) spans.push_back({b, active});
        }
    }
    spanCursor_.fill(0);
    reset();
}

long ScorePlayer::activePattern(int voice, double position) noexcept
{
    const auto& spans = spans_[static_cast<std::size_t>(voice)];
    std::size_t& c = spanCursor_[static_cast<std::size_t>(voice)];
    if (spans.empty() || position < spans.front().start) return 0;
    if (c >= spans.size() || position < spans[c].start) {   // a jump back: search
        const auto after = std::upper_bound(spans.begin(), spans.end(), position,
                                            [](double x, const VoiceSpan& sp) { return x < sp.start; });
        c = static_cast<std::size_t>(after - spans.begin()) - 1;
    }
    // Forward: a step crosses few boundaries; a long leap ahead is a search as well.
    for (int k = 0; k < 4 && c + 1 < spans.size() && spans[c + 1].start <= position; ++k) ++c;
    if (c + 1 < spans.size() && spans[c + 1].start <= position) {
        const auto after = std::upper_bound(spans.begin() + static_cast<long>(c), spans.end(), position,
                                            [](double x, const VoiceSpan& sp) { return x < sp.start; });
        c = static_cast<std::size_t>(after - spans.begin()) - 1;
    }
    return spans[c].pattern;
}

void ScorePlayer::reset() noexcept
{
    ownClock_ = 0.0;
    position_ = 0.0;
    previous_ = -1.0;
    resync_ = true;
}

void ScorePlayer::silence(core::MotorCanvas& canvas) noexcept
{
    canvas.clearLevels();
    for (int v = 0; v < core::kPatternVoices; ++v) {
        if (running_[static_cast<std::size_t>(v)] != 0) canvas.stopVoice(v);
        running_[static_cast<std::size_t>(v)] = 0;
    }
}

float ScorePlayer::amplitudeLevel(const ScoreNote& note, const ScorePart& part, float amplitude, bool offBelowFloor) noexcept
{
    if (note.envelope.empty()) return 0.0f;
    const auto [lo, hi] = std::minmax_element(note.envelope.begin(), note.envelope.end());
    const double a = std::isfinite(amplitude) ? std::max(0.0, static_cast<double>(amplitude)) : 0.0;
    double x;
    if (part.curveDb) {
        const double db = 20.0 * std::log10(std::max(a, 1e-9));
        x = (db - part.floorDb) / (part.topDb - part.floorDb);
    } else {
        const double floor = std::pow(10.0, part.floorDb / 20.0), top = std::pow(10.0, part.topDb / 20.0);
        x = (a - floor) / (top - floor);
    }
    if (!(x > 0.0)) return offBelowFloor ? 0.0f : *lo;
    x = std::min(x, 1.0);
    return static_cast<float>(static_cast<double>(*lo) + x * static_cast<double>(*hi - *lo));
}

void ScorePlayer::control(const core::Transport& transport, double dt, core::MotorCanvas& canvas, const FollowState* follow) noexcept
{
    if (!(dt >= 0.0) || !std::isfinite(dt)) dt = 0.0;
    double position;
    double speed = 1.0;   // score seconds per real second (beat sync at another tempo)
    if (follow) {
        // The recording places the score: the followed note heard last (and how long ago), or
        // for a score without followed notes the cue-aligned time since the first sound.
        if (!events_.empty()) {
            position = -1.0;
            if (follow->note >= 0 && follow->note < static_cast<int>(events_.size())) {
                const auto e = static_cast<std::size_t>(follow->note);
                position = score_.notes[static_cast<std::size_t>(events_[e].front())].start + std::min(follow->sinceOnset, 0.999 * eventLength_[e]);
            }
        } else {
            position = follow->heard ? follow->position : -1.0;
        }
        if (!(position >= 0.0)) {   // before the recording's first note: nothing
            silence(canvas);
            resync_ = true;
            previous_ = -1.0;
            position_ = 0.0;
            return;
        }
    } else if (transport.valid) {
        if (!transport.playing) {   // paused or stopped: nothing plays, resume re-syncs
            silence(canvas);
            resync_ = true;
            previous_ = -1.0;
            return;
        }
        if (sync_ == Sync::Beats && std::isfinite(transport.ppq)) {
            position = score_.secondsAtBeat(transport.ppq);
            const double hostBpm = transport.bpm > 0.0 && std::isfinite(transport.bpm) ? transport.bpm : 120.0;
            speed = hostBpm / score_.bpmAtSeconds(position);
        } else {
            position = std::isfinite(transport.seconds) ? transport.seconds : 0.0;
        }
    } else {
        ownClock_ += dt;   // the first step (dt = 0) is at 0
        position = ownClock_;
    }
    position_ = position;

    // A jump (seek, loop, a new start): anything running is restarted from this position. Hosts
    // report positions per audio block, so a position may stand still for a few steps, leap by
    // a block, or wobble back a little; none of that is a jump.
    constexpr double kWobble = 0.010;   // s backwards that is still the same play-through
    constexpr double kLeap = 0.050;     // s ahead of the expected position that is not a seek
    const double expected = previous_ + dt * speed;
    if (previous_ < 0.0 || position < previous_ - kWobble || position > expected + std::max(kLeap, 2.0 * dt * speed))
        resync_ = true;
    previous_ = position;
    if (resync_) {
        for (int v = 0; v < core::kPatternVoices; ++v) {
            if (running_[static_cast<std::size_t>(v)] != 0) canvas.stopVoice(v);
            running_[static_cast<std::size_t>(v)] = 0;
        }
        resync_ = false;
    }

    // Notes: the sustained target of every motor, from the position alone.
    std::array<float, core::kMaxMotors> level {};
    std::uint16_t soft = 0;   // motors whose loudest note asked for a soft start
    if (position < score_.length) {
        const auto firstAfter = std::upper_bound(score_.notes.begin(), score_.notes.end(), position,
                                                 [](double p, const ScoreNote& n) { return p < n.start; });
        for (auto it = firstAfter; it != score_.notes.begin();) {
            --it;
            if (it->start < position - longestNote_) break;
            const auto index = static_cast<std::size_t>(it - score_.notes.begin());
            float l = it->levelAt(position);
            if (follow && followedOf_[index] >= 0) {
                // Placed by the follower below; a note of an earlier event still held (a bass
                // under the melody) sounds on while the recording does, by the position.
                if (followedOf_[index] >= follow->note || !follow->sounding) continue;
            }
            if (follow && l > 0.0f && it->part >= 0 && score_.parts[static_cast<std::size_t>(it->part)].followAmplitude)
                l = amplitudeLevel(*it, score_.parts[static_cast<std::size_t>(it->part)],
                                   follow->envelope[static_cast<std::size_t>(it->part)], true);
            if (!(l > 0.0f)) continue;
            for (int m = 0; m < core::kMaxMotors; ++m)
                if ((it->motors & (1u << m)) && l > level[static_cast<std::size_t>(m)]) {
                    level[static_cast<std::size_t>(m)] = l;
                    soft = static_cast<std::uint16_t>(it->soft ? (soft | (1u << m)) : (soft & ~(1u << m)));
                }
        }
    }
    // The followed event the recording plays now: its notes' motors from the moment it was heard.
    if (follow && follow->sounding && follow->note >= 0 && follow->note < static_cast<int>(events_.size())) {
        for (const int index : events_[static_cast<std::size_t>(follow->note)]) {
            const ScoreNote& n = score_.notes[static_cast<std::size_t>(index)];
            const ScorePart& part = score_.parts[static_cast<std::size_t>(n.part)];
            const float l = part.followAmplitude
                                ? amplitudeLevel(n, part, follow->envelope[static_cast<std::size_t>(n.part)], false)
                                : n.levelAtFraction(follow->sinceOnset / (n.end - n.start));
            const bool noteSoft = n.soft || part.followAmplitude;   // a followed envelope is a swell
            for (int m = 0; m < core::kMaxMotors; ++m)
                if ((n.motors & (1u << m)) && l > level[static_cast<std::size_t>(m)]) {
                    level[static_cast<std::size_t>(m)] = l;
                    soft = static_cast<std::uint16_t>(noteSoft ? (soft | (1u << m)) : (soft & ~(1u << m)));
                }
        }
    }
    const float gain = std::clamp(intensity_, 0.0f, 1.5f);
    for (int m = 0; m < core::kMaxMotors; ++m) {
        if (soft & (1u << m)) canvas.setSoftLevel(m, level[static_cast<std::size_t>(m)] * gain);
        else canvas.setLevel(m, level[static_cast<std::size_t>(m)] * gain);
    }

    // Patterns: per voice, the one whose span holds the position.
    for (int v = 0; v < core::kPatternVoices; ++v) {
        const auto vi = static_cast<std::size_t>(v);
        if (!used_[vi]) continue;
        const long active = position < score_.length ? activePattern(v, position) : 0;
        if (active == running_[vi]) continue;
        if (active == 0) {
            canvas.stopVoice(v);
        } else {
            const ScorePattern& p = score_.patterns[static_cast<std::size_t>(active - 1)];
            core::PatternRequest r = p.request;
            r.level = std::min(float(core::kMaxLevel), r.level * gain);
            // The voice runs for what is left of its span, in real seconds.
            r.duration = std::isfinite(p.end) ? (p.end - position) / speed : -1.0;
            canvas.trigger(r);
        }
        running_[vi] = active;
    }
}

} // namespace armadillo::tactile
