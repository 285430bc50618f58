#include "Instruments/Frets.h"
#include <algorithm>
#include <cmath>

namespace armadillo::instruments {

const std::vector<std::string>& fretScaleNames()
{
    static const std::vector<std::string> names {"major", "natural minor", "harmonic minor", "dorian",
                                                 "mixolydian", "major pentatonic", "minor pentatonic"};
    return names;
}

namespace {
/// The scales as fixed tables (read in control(); the vectors below are for UIs and tests).
struct ScaleSteps {
    std::array<int, 7> steps;
    int count;
};
constexpr std::array<ScaleSteps, 7> kScaleSteps {{
    {{0, 2, 4, 5, 7, 9, 11}, 7}, {{0, 2, 3, 5, 7, 8, 10}, 7}, {{0, 2, 3, 5, 7, 8, 11}, 7}, {{0, 2, 3, 5, 7, 9, 10}, 7},
    {{0, 2, 4, 5, 7, 9, 10}, 7}, {{0, 2, 4, 7, 9, 0, 0}, 5},  {{0, 3, 5, 7, 10, 0, 0}, 5}}};
const ScaleSteps& scaleSteps(FretScale scale) noexcept
{
    return kScaleSteps[static_cast<std::size_t>(std::clamp(static_cast<int>(scale), 0, static_cast<int>(kScaleSteps.size()) - 1))];
}
} // namespace

const std::vector<int>& fretScaleSteps(FretScale scale)
{
    static const std::vector<std::vector<int>> steps {
        {0, 2, 4, 5, 7, 9, 11}, {0, 2, 3, 5, 7, 8, 10}, {0, 2, 3, 5, 7, 8, 11}, {0, 2, 3, 5, 7, 9, 10},
        {0, 2, 4, 5, 7, 9, 10}, {0, 2, 4, 7, 9},        {0, 3, 5, 7, 10}};
    const auto i = static_cast<std::size_t>(std::clamp(static_cast<int>(scale), 0, static_cast<int>(steps.size()) - 1));
    return steps[i];
}

const std::vector<std::string>& pitchClassNames()
{
    static const std::vector<std::string> names {"A", "A#", "B", "C", "C#", "D", "D#", "E", "F", "F#", "G", "G#"};
    return names;
}

double semitonesForAxisY(const PitchMapParams& p, double axisY) noexcept
{
    const double y0 = std::sin(core::degToRad(p.bottomElevationDeg));
    const double y1 = std::sin(core::degToRad(p.topElevationDeg));
    const double span = std::fabs(y1 - y0) < 1e-6 ? (y1 >= y0 ? 1e-6 : -1e-6) : (y1 - y0);
    return p.rangeSemitones * (axisY - y0) / span;
}

double frequencyForSemitones(const PitchMapParams& p, double semitones) noexcept
{
    return p.baseHz * std::exp2(semitones / 12.0);
}

namespace {
/// Semitones from base up to the first root at or above base (0..12).
double rootOffset(const PitchMapParams& p, int rootPitchClass) noexcept
{
    // Pitch class of base relative to A (440 Hz is an A).
    const double baseFromA = 12.0 * std::log2(p.baseHz / 440.0);
    double r = std::fmod(static_cast<double>(rootPitchClass) - baseFromA, 12.0);
    if (r < 0.0) r += 12.0;
    if (r > 12.0 - 1e-6) r = 0.0;   // base is (within rounding) the root itself
    return r;
}
} // namespace

FretList fretSemitonesFixed(const PitchMapParams& p, FretScale scale, int rootPitchClass) noexcept
{
    const ScaleSteps& steps = scaleSteps(scale);
    const double r = rootOffset(p, rootPitchClass);
    FretList frets;
    const double top = p.rangeSemitones + 1e-6;
    for (int octave = -1; octave <= 10 && frets.count < kMaxFrets; ++octave) {
        for (int k = 0; k < steps.count && frets.count < kMaxFrets; ++k) {
            const double s = r + 12.0 * octave + steps.steps[static_cast<std::size_t>(k)];
            if (s < -1e-6 || s > top) continue;
            frets.values[static_cast<std::size_t>(frets.count++)] = s;
        }
    }
    return frets;
}

std::vector<double> fretSemitones(const PitchMapParams& p, FretScale scale, int rootPitchClass)
{
    const FretList f = fretSemitonesFixed(p, scale, rootPitchClass);
    return {f.values.begin(), f.values.begin() + f.count};
}

double snapToScale(double semitones, const PitchMapParams& p, FretScale scale, int rootPitchClass, double amount) noexcept
{
    if (!(amount > 0.0)) return semitones;
    const ScaleSteps& steps = scaleSteps(scale);
    const double r = rootOffset(p, rootPitchClass);
    const double rel = semitones - r;
    const double octave = std::floor(rel / 12.0);
    const double within = rel - 12.0 * octave;
    double best = 12.0;   // the next octave's root is always a candidate
    for (int k = 0; k < steps.count; ++k) {
        const int step = steps.steps[static_cast<std::size_t>(k)];
        if (std::fabs(within - step) < std::fabs(within - best)) best = step;
    }
    const double target = r + 12.0 * octave + best;
    return semitones + std::min(amount, 1.0) * (target - semitones);
}

int fretMotor(int fretIndex) noexcept
{
    static constexpr std::array<int, kMaxFrets> motors {
        core::motorIndex(2, 0), core::motorIndex(2, 1), core::motorIndex(2, 2), // elbow row: A B C#
        core::motorIndex(1, 0), core::motorIndex(1, 1), core::motorIndex(1, 2), // middle row: D E F#
        core::motorIndex(0, 0), core::motorIndex(0, 1)};        // wrist row: G# A (right unused)
    return fretIndex >= 0 && fretIndex < kMaxFrets ? motors[static_cast<std::size_t>(fretIndex)] : -1;
}

void FretTracker::configure(const std::vector<double>& fretHz, double adjust)
{
    FretList list;
    list.count = std::min(static_cast<int>(fretHz.size()), kMaxFrets);
    for (int j = 0; j < list.count; ++j) list.values[static_cast<std::size_t>(j)] = fretHz[static_cast<std::size_t>(j)];
    configure(list, adjust);
}

void FretTracker::configure(const FretList& fretHz, double adjust) noexcept
{
    count_ = std::clamp(fretHz.count, 0, kMaxFrets);
    for (int j = 0; j < count_; ++j) hz_[static_cast<std::size_t>(j)] = fretHz.values[static_cast<std::size_t>(j)];
    for (int j = 1; j < count_; ++j) {
        const auto uj = static_cast<std::size_t>(j);
        // Boundary j: on (fret ≥ j) above f_j(1−a), off below f_{j−1}(1+a). Adjacent scale notes
        // are at least a semitone apart (ratio 1.059), so enter > exit for any a below ~2.8%.
        boundaries_[uj].setThresholds(hz_[uj] * (1.0 - adjust), hz_[uj - 1] * (1.0 + adjust));
    }
    if (count_ == 0) current_ = -1;
    primed_ = false;
}

int FretTracker::update(double frequencyHz) noexcept
{
    if (count_ == 0 || !std::isfinite(frequencyHz)) return current_ = (count_ == 0 ? -1 : current_);
    if (!primed_) {
        for (int j = 1; j < count_; ++j) boundaries_[static_cast<std::size_t>(j)].reset(frequencyHz >= hz_[static_cast<std::size_t>(j)]);
        primed_ = true;
    }
    int fret = 0;
    for (int j = 1; j < count_; ++j)
        if (boundaries_[static_cast<std::size_t>(j)].update(frequencyHz)) ++fret;
    current_ = fret;
    return current_;
}

} // namespace armadillo::instruments
