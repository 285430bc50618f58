#include "Access/Feedback.h"
#include "Braille/Reading.h"
#include <algorithm>

namespace armadillo::access {

std::vector<TactileSegment> feedbackSensation(bool right, float level)
{
    if (right) return {{0.0, 0.4, kAllNineMotors, 4.0f, true, false}};
    return {{0.0, 0.1, kOuterMotors, level, false, false},
            {0.2, 0.1, kOuterMotors, level, false, false},
            {0.4, 0.1, kOuterMotors, level, false, false}};
}

std::vector<TactileSegment> drawnText(const std::string& text, int grade, braille::DisplayMethod method, float level, double at,
                                      double& end, std::size_t maxSegments)
{
    constexpr double kOn = 0.4, kGap = 0.2, kLetterGap = 0.5, kWordGap = 1.2;
    braille::TranslationOptions o;
    o.grade = grade;
    const auto units = braille::layoutDocument(braille::translateText(text, o), method);
    std::vector<TactileSegment> segs;
    for (const auto& unit : units) {
        if (segs.size() + unit.steps.size() + 1 > maxSegments) break;
        if (unit.kind != braille::UnitKind::Cell) {
            segs.push_back({at, braille::kWordGapCue.duration, braille::kWordGapCue.motors, level * braille::kWordGapCue.gain, braille::kWordGapCue.soft, false});
            at += kWordGap;
            continue;
        }
        for (std::size_t s = 0; s < unit.steps.size(); ++s) {
            if (unit.steps[s] != 0) segs.push_back({at, kOn, unit.steps[s], level, false, false});
            at += kOn + (s + 1 < unit.steps.size() ? kGap : kLetterGap);
        }
    }
    end = at;
    return segs;
}

std::vector<TactileSegment> feedbackSequence(bool right, const std::string& again, float level)
{
    auto segments = feedbackSensation(right, level);
    double at = 0.0;
    for (const auto& seg : segments) at = std::max(at, seg.at + seg.duration);
    at += feedbackPause(right);
    const bool drawable = !again.empty() && again.size() <= 24 &&
                          std::all_of(again.begin(), again.end(), [](char c) { return (c >= 'a' && c <= 'z') || c == ' '; });
    if (!right && drawable) {
        double end = 0.0;
        const auto cells = drawnText(again, 1, braille::DisplayMethod::Rows, level, at, end, 100);
        segments.insert(segments.end(), cells.begin(), cells.end());
        at = end + 0.5;
    }
    const auto cue = nextCue(level, at);
    segments.insert(segments.end(), cue.begin(), cue.end());
    return segments;
}

namespace {

template <std::size_t N>
std::vector<TactileSegment> cueSegments(const std::array<braille::CueBurst, N>& cue, float level, double at)
{
    std::vector<TactileSegment> segs;
    for (const auto& b : cue) segs.push_back({at + b.at, b.duration, b.motors, level * b.gain, b.soft, false});
    return segs;
}

} // namespace

// The cue shapes are defined once, in Braille/Sensations.h, for the braille scene's messages too.
std::vector<TactileSegment> nextCue(float level, double at) { return cueSegments(braille::kSweepCue, level, at); }

std::vector<TactileSegment> yourTurnCue(float level, double at) { return cueSegments(braille::kDoubleTapCue, level, at); }

} // namespace armadillo::access

