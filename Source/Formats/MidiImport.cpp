// MIDI file → tactile score (docs/FORMATS.md, "MIDI files"). The rule, step by step:
//  1. notes are taken onset by onset (all notes starting on the same tick together);
//  2. an onset with more notes than the budget (maxMotors) keeps the highest, the lowest, then
//     the others from the top down; notes still held from before are ended at the new onset,
//     the oldest first, until the budget holds;
//  3. each note's motor: by default the piece's pitch range (pitched notes of the tracks without
//     an override) is cut into nine equal bins, lowest → elbow left (motor 7) … highest → wrist
//     right (motor 3) (bin = 3·(2 − row) + column), so the lowest voice is at the elbow and the
//     highest at the wrist; a track with `--track N=SET` uses the motors of SET in that order over
//     its own range; General MIDI percussion (channel 10) uses the elbow row; the note takes the
//     free motor nearest its bin (notes that sound together never share a motor), preferring one
//     that no note left in the last 50 ms (so every onset is felt as one), or is dropped when
//     none is free;
//  4. level: midiVelocityLevel() (velocity → level, capped at the rated level for notes longer
//     than the safety's run above the rating); quiet long notes start soft;
//  5. tempo changes become `tempo` events and cues, markers and cue points become cues.
#include "Core/Errors.h"
#include "Formats/ScoreImport.h"
#include "Formats/ScoreText.h"
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <set>

namespace armadillo::formats {

namespace {

std::string pitchName(int key)
{
    static const char* const kNames[12] = {"C", "Cs", "D", "Ds", "E", "F", "Fs", "G", "Gs", "A", "As", "B"};
    const int octave = key / 12 - 1;
    if (octave < 0 || octave > 9) return scoretext::number(440.0 * std::pow(2.0, (key - 69) / 12.0), 3) + "hz";
    return std::string(kNames[key % 12]) + std::to_string(octave);
}

constexpr double kJustLeft = 0.050;   // s: a motor a note left this recently is not the next note's first choice

int motorBin(int index) noexcept { return 3 * (2 - index / 3) + index % 3; }

/// Which motors a note may use and where in them its pitch points.
struct Placement {
    std::vector<int> motors;   ///< allowed motors, by bin (low → high)
    int lo = 0, hi = 127;      ///< the key range spread over them
};

} // namespace

int binMotor(int bin) noexcept
{
    bin = std::clamp(bin, 0, 8);
    return 3 * (2 - bin / 3) + bin % 3;
}

float midiVelocityLevel(int velocity, double seconds, const MidiImportOptions& o) noexcept
{
    const double v = std::clamp(velocity, 1, 127);
    double top = seconds > o.safety.maxAboveRatingRun ? static_cast<double>(o.safety.ratedLevel) : static_cast<double>(o.shortTop);
    top = std::clamp(top, static_cast<double>(o.quietLevel), static_cast<double>(core::kMaxLevel));
    const auto quiet = static_cast<double>(o.quietLevel);
    const double level = quiet + (top - quiet) * (v - 1.0) / 126.0;
    return static_cast<float>(std::round(level * 2.0) / 2.0);
}

namespace {

/// One import, step by step (the rule at the top of this file): the tracks' rules and key ranges,
/// the notes kept onset by onset and their motors, the parts, the score's lines, its text.
class MidiImporter {
public:
    MidiImporter(const MidiFile& midi, const MidiImportOptions& o, const std::string& source)
        : midi_(midi), o_(o), source_(source), trackCount_(static_cast<int>(midi.trackNames.size()))
    {
    }

    ImportedScore run()
    {
        readRules();
        spreadRanges();
        keepNotes();
        if (kept_.empty()) throw core::InputError(source_, 0, "", "no notes to import (the file has " + std::to_string(midi_.notes.size()) + ")");
        std::stable_sort(kept_.begin(), kept_.end(), [](const Kept& a, const Kept& b) { return a.note->start < b.note->start; });
        makeParts();
        noteLines();
        cueLines();
        std::stable_sort(lines_.begin(), lines_.end(), [](const Line& a, const Line& b) { return a.tick != b.tick ? a.tick < b.tick : a.kind < b.kind; });
        writeText();
        if (midi_.unterminatedNotes > 0) out_.report.warnings.push_back(std::to_string(midi_.unterminatedNotes) + " notes had no note-off (ended at their track's end)");
        out_.score = tactile::parseScore(out_.text, source_);
        return std::move(out_);
    }

private:
    struct Kept {
        const MidiNote* note;
        std::int64_t end;
        int motor;
    };
    struct Line {
        std::int64_t tick;
        int kind;   // 0 tempo, 1 cue, 2 note
        std::string text;
    };

    const MidiTrackRule* ruleOf(const MidiNote& n) const { return rule_[static_cast<std::size_t>(n.track)]; }
    bool percussion(const MidiNote& n) const { return n.channel == 9 && !ruleOf(n); }
    const Placement& placementOf(const MidiNote& n) const
    {
        if (ruleOf(n)) return byTrack_[static_cast<std::size_t>(n.track)];
        return percussion(n) ? drums_ : grid_;
    }

    void readRules()
    {
        if (o_.maxMotors < 1 || o_.maxMotors > core::kGridMotors)
            throw core::InputError(source_, 0, "max-motors", "the budget must be 1..9 motors at once");
        rule_.assign(static_cast<std::size_t>(trackCount_), nullptr);
        for (const MidiTrackRule& r : o_.tracks) {
            if (r.track < 1 || r.track > trackCount_)
                throw core::InputError(source_, 0, "track", "no track " + std::to_string(r.track) + " (the file has " + std::to_string(trackCount_) + ")");
            if (!r.off && r.motors == 0) throw core::InputError(source_, 0, "track", "track " + std::to_string(r.track) + " has no motors");
            rule_[static_cast<std::size_t>(r.track - 1)] = &r;
        }
    }

    /// Key ranges: the default rule's (the whole piece), each overridden track's, percussion's.
    void spreadRanges()
    {
        for (int m = 0; m < core::kGridMotors; ++m) grid_.motors.push_back(binMotor(m));
        for (int b = 0; b < 3; ++b) drums_.motors.push_back(binMotor(b));   // elbow row
        byTrack_.assign(static_cast<std::size_t>(trackCount_), Placement {});
        for (int t = 0; t < trackCount_; ++t)
            if (const MidiTrackRule* r = rule_[static_cast<std::size_t>(t)]; r && !r->off) {
                auto& motors = byTrack_[static_cast<std::size_t>(t)].motors;
                for (int m = 0; m < core::kMaxMotors; ++m)
                    if (r->motors & (1u << m)) motors.push_back(m);
                std::stable_sort(motors.begin(), motors.end(),
                                 [](int a, int b) { return (a < core::kGridMotors ? motorBin(a) : a) < (b < core::kGridMotors ? motorBin(b) : b); });
            }
        const auto widen = [](Placement& p, int key, bool& first) {
            if (first) p.lo = p.hi = key;
            p.lo = std::min(p.lo, key);
            p.hi = std::max(p.hi, key);
            first = false;
        };
        bool gridFirst = true, drumsFirst = true;
        std::vector<char> trackFirst(static_cast<std::size_t>(trackCount_), 1);
        for (const MidiNote& n : midi_.notes) {
            const MidiTrackRule* r = ruleOf(n);
            if (r && r->off) continue;
            if (r) {
                bool f = trackFirst[static_cast<std::size_t>(n.track)] != 0;
                widen(byTrack_[static_cast<std::size_t>(n.track)], n.key, f);
                trackFirst[static_cast<std::size_t>(n.track)] = 0;
            } else if (percussion(n)) {
                widen(drums_, n.key, drumsFirst);
            } else {
                widen(grid_, n.key, gridFirst);
            }
        }
    }

    /// Onset by onset: the notes kept within the budget, each on its motor.
    void keepNotes()
    {
        const auto& notes = midi_.notes;
        for (std::size_t i = 0; i < notes.size();) {
            std::size_t j = i;
            while (j < notes.size() && notes[j].start == notes[i].start) ++j;
            const std::int64_t tick = notes[i].start;
            std::vector<const MidiNote*> group;   // by key, low → high
            for (std::size_t k = i; k < j; ++k)
                if (!(ruleOf(notes[k]) && ruleOf(notes[k])->off)) group.push_back(&notes[k]);
            i = j;
            if (group.empty()) continue;
            // Priority: the highest, the lowest, then from the top down.
            std::vector<const MidiNote*> order;
            order.push_back(group.back());
            if (group.size() > 1) order.push_back(group.front());
            for (std::size_t k = group.size() - 1; k-- > 1;) order.push_back(group[k]);
            if (static_cast<int>(order.size()) > o_.maxMotors) {
                out_.report.dropped += static_cast<int>(order.size()) - o_.maxMotors;
                order.resize(static_cast<std::size_t>(o_.maxMotors));
            }
            makeRoom(tick, order.size());
            for (const MidiNote* n : order) place(*n, tick);
        }
    }

    /// Room in the budget for `coming` notes at `tick`: notes held from before end here, the oldest first.
    void makeRoom(std::int64_t tick, std::size_t coming)
    {
        std::vector<std::size_t> sounding;
        for (std::size_t k = 0; k < kept_.size(); ++k)
            if (kept_[k].end > tick) sounding.push_back(k);
        for (std::size_t s = 0; static_cast<int>(sounding.size() - s + coming) > o_.maxMotors; ++s) {
            Kept& held = kept_[sounding[s]];
            held.end = tick;
            busyUntil_[static_cast<std::size_t>(held.motor)] = tick;
            ++out_.report.shortened;
        }
    }

    void place(const MidiNote& n, std::int64_t tick)
    {
        const Placement& p = placementOf(n);
        const int count = static_cast<int>(p.motors.size());
        const int position = p.hi > p.lo ? std::clamp((n.key - p.lo) * count / (p.hi - p.lo + 1), 0, count - 1) : count / 2;
        // The nearest free motor (upward on a tie) that no note has just left: a new onset on
        // a motor still running from the note before would not be felt as one.
        int chosen = -1;
        const double now = midi_.secondsAt(tick);
        for (const bool allowJustLeft : {false, true})
            for (int d = 0; d < count && chosen < 0; ++d)
                for (const int c : {position + d, position - d}) {
                    if (c < 0 || c >= count || chosen >= 0) continue;
                    const auto m = static_cast<std::size_t>(p.motors[static_cast<std::size_t>(c)]);
                    const bool justLeft = used_[m] && now - midi_.secondsAt(busyUntil_[m]) < kJustLeft;
                    if (busyUntil_[m] <= tick && (allowJustLeft || !justLeft)) chosen = static_cast<int>(m);
                }
        if (chosen < 0) {
            ++out_.report.dropped;
            return;
        }
        busyUntil_[static_cast<std::size_t>(chosen)] = n.end;
        used_[static_cast<std::size_t>(chosen)] = true;
        kept_.push_back({&n, n.end, chosen});
    }

    /// Parts: one per track with notes (at most 8), else one for all.
    void makeParts()
    {
        partOfTrack_.assign(static_cast<std::size_t>(trackCount_), -1);
        for (const Kept& k : kept_)
            if (k.note->channel != 9 && partOfTrack_[static_cast<std::size_t>(k.note->track)] < 0) {
                partOfTrack_[static_cast<std::size_t>(k.note->track)] = static_cast<int>(partNames_.size());
                std::string nm = scoretext::name(midi_.trackNames[static_cast<std::size_t>(k.note->track)], "track-" + std::to_string(k.note->track + 1));
                for (const auto& other : partNames_)
                    if (other == nm) nm = "track-" + std::to_string(k.note->track + 1);
                partNames_.push_back(nm);
                partTrack_.push_back(k.note->track);
            }
        onePart_ = partNames_.size() > static_cast<std::size_t>(tactile::kMaxScoreParts);
    }

    /// Times: beats (ticks per quarter) or seconds (SMPTE).
    std::string timeText(std::int64_t tick) const
    {
        return midi_.smpte ? scoretext::number(midi_.secondsAt(tick)) : scoretext::number(static_cast<double>(tick) / midi_.ticksPerQuarter);
    }

    void noteLines()
    {
        for (const Kept& k : kept_) {
            const MidiNote& n = *k.note;
            const double seconds = midi_.secondsAt(k.end) - midi_.secondsAt(n.start);
            const float level = midiVelocityLevel(n.velocity, seconds, o_);
            std::string s = timeText(n.start) + " note m=" + std::to_string(k.motor + 1) + " dur=" +
                            (midi_.smpte ? scoretext::number(seconds) : scoretext::number(static_cast<double>(k.end - n.start) / midi_.ticksPerQuarter)) +
                            " level=" + scoretext::number(level, 1);
            // Percussion has no pitch to follow: such notes belong to no part and play where the
            // alignment of the pitched notes places the score.
            if (n.channel != 9) {
                if (o_.follow) s += " pitch=" + pitchName(n.key);
                s += " part=" + (onePart_ ? std::string("music") : partNames_[static_cast<std::size_t>(partOfTrack_[static_cast<std::size_t>(n.track)])]);
            }
            if (n.velocity < o_.softBelowVelocity && seconds >= o_.softLongerThan) s += " start=soft";
            lines_.push_back({n.start, 2, std::move(s)});
            ++out_.report.notes;
        }
    }

    void cue(std::int64_t tick, const std::string& wanted)
    {
        std::string nm = wanted;
        for (int k = 2; cueNames_.count(nm); ++k) nm = wanted + "-" + std::to_string(k);
        cueNames_.insert(nm);
        lines_.push_back({tick, 1, timeText(tick) + " cue " + nm});
        ++out_.report.cues;
    }

    double bpmOf(double us)
    {
        const double bpm = 6.0e7 / us;
        if (bpm > 1000.0 || bpm < 1.0) out_.report.warnings.push_back("a tempo of " + scoretext::number(bpm, 2) + " bpm clamped to 1..1000");
        return std::clamp(bpm, 1.0, 1000.0);
    }

    /// Tempo changes become `tempo` events and cues; markers and cue points, cues.
    void cueLines()
    {
        if (!midi_.smpte)
            for (std::size_t t = 1; t < midi_.tempo.size(); ++t) {
                lines_.push_back({midi_.tempo[t].tick, 0, timeText(midi_.tempo[t].tick) + " tempo " + scoretext::number(bpmOf(midi_.tempo[t].microsPerQuarter), 3)});
                cue(midi_.tempo[t].tick, "tempo-" + std::to_string(t));
            }
        for (const MidiMarker& m : midi_.markers) cue(m.tick, scoretext::name(m.text, m.cuePoint ? "cue-point" : "marker"));
    }

    void writeText()
    {
        std::string title;
        for (const auto& nm : midi_.trackNames)
            if (title.empty()) title = scoretext::oneLine(nm);
        if (title.empty()) title = scoretext::oneLine(std::filesystem::path(source_).stem().string());
        if (title.empty()) title = "imported";
        std::string& text = out_.text;
        text += "armadillo-score 2\n";
        text += "# Imported from " + scoretext::oneLine(std::filesystem::path(source_).filename().string()) +
                " by `armadillo score import` (docs/FORMATS.md, \"MIDI files\"):\n"
                "# lowest pitch at the elbow, highest at the wrist; at most " + std::to_string(o_.maxMotors) +
                " notes at once; velocity -> level capped at the rated level for notes over " +
                scoretext::number(o_.safety.maxAboveRatingRun, 3) + " s.\n";
        text += "title " + title + "\n";
        text += midi_.smpte ? "units seconds\n" : "units beats\n";
        if (!midi_.smpte) text += "tempo " + scoretext::number(bpmOf(midi_.tempo.front().microsPerQuarter), 3) + "\n";
        if (onePart_) {
            text += std::string("part music follow=") + (o_.follow ? "notes" : "none") + "\n";
        } else {
            for (std::size_t p = 0; p < partNames_.size(); ++p) {
                text += "part " + partNames_[p] + " follow=" + (o_.follow ? "notes" : "none");
                const std::string& trackName = midi_.trackNames[static_cast<std::size_t>(partTrack_[p])];
                text += "   # track " + std::to_string(partTrack_[p] + 1) + (trackName.empty() ? "" : ": " + scoretext::oneLine(trackName)) + "\n";
            }
        }
        for (const Line& l : lines_) text += l.text + "\n";
        std::int64_t lastTick = midi_.endTick;
        for (const Kept& k : kept_) lastTick = std::max(lastTick, k.end);
        text += "length " + (midi_.smpte ? scoretext::lengthNumber(midi_.secondsAt(lastTick))
                                         : scoretext::lengthNumber(static_cast<double>(lastTick) / midi_.ticksPerQuarter)) + "\n";
    }

    const MidiFile& midi_;
    const MidiImportOptions& o_;
    const std::string& source_;
    const int trackCount_;
    std::vector<const MidiTrackRule*> rule_;
    Placement grid_, drums_;
    std::vector<Placement> byTrack_;
    std::vector<Kept> kept_;
    std::array<std::int64_t, core::kMaxMotors> busyUntil_ {};
    std::array<bool, core::kMaxMotors> used_ {};
    std::vector<int> partOfTrack_;
    std::vector<std::string> partNames_;
    std::vector<int> partTrack_;
    bool onePart_ = false;
    std::vector<Line> lines_;
    std::set<std::string> cueNames_;
    ImportedScore out_;
};

} // namespace

ImportedScore importMidi(const MidiFile& midi, const MidiImportOptions& o, const std::string& source)
{
    ImportedScore out = MidiImporter(midi, o, source).run();
    out.report.format = "midi";
    return out;
}

} // namespace armadillo::formats
