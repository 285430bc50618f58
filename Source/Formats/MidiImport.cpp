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

ImportedScore importMidi(const MidiFile& midi, const MidiImportOptions& o, const std::string& source)
{
    const int trackCount = static_cast<int>(midi.trackNames.size());
    if (o.maxMotors < 1 || o.maxMotors > core::kGridMotors)
        throw core::InputError(source, 0, "max-motors", "the budget must be 1..9 motors at once");
    std::vector<const MidiTrackRule*> rule(static_cast<std::size_t>(trackCount), nullptr);
    for (const MidiTrackRule& r : o.tracks) {
        if (r.track < 1 || r.track > trackCount)
            throw core::InputError(source, 0, "track", "no track " + std::to_string(r.track) + " (the file has " + std::to_string(trackCount) + ")");
        if (!r.off && r.motors == 0) throw core::InputError(source, 0, "track", "track " + std::to_string(r.track) + " has no motors");
        rule[static_cast<std::size_t>(r.track - 1)] = &r;
    }
    const auto ruleOf = [&](const MidiNote& n) { return rule[static_cast<std::size_t>(n.track)]; };
    const auto percussion = [&](const MidiNote& n) { return n.channel == 9 && !ruleOf(n); };

    // Key ranges: the default rule's (the whole piece), each overridden track's, percussion's.
    Placement grid, drums;
    for (int m = 0; m < core::kGridMotors; ++m) grid.motors.push_back(binMotor(m));
    for (int b = 0; b < 3; ++b) drums.motors.push_back(binMotor(b));   // elbow row
    std::vector<Placement> byTrack(static_cast<std::size_t>(trackCount));
    for (int t = 0; t < trackCount; ++t)
        if (const MidiTrackRule* r = rule[static_cast<std::size_t>(t)]; r && !r->off) {
            for (int m = 0; m < core::kMaxMotors; ++m)
                if (r->motors & (1u << m)) byTrack[static_cast<std::size_t>(t)].motors.push_back(m);
            std::stable_sort(byTrack[static_cast<std::size_t>(t)].motors.begin(), byTrack[static_cast<std::size_t>(t)].motors.end(),
                             [](int a, int b) { return (a < core::kGridMotors ? motorBin(a) : a) < (b < core::kGridMotors ? motorBin(b) : b); });
        }
    const auto widen = [](Placement& p, int key, bool& first) {
        if (first) p.lo = p.hi = key;
        p.lo = std::min(p.lo, key);
        p.hi = std::max(p.hi, key);
        first = false;
    };
    bool gridFirst = true, drumsFirst = true;
    std::vector<char> trackFirst(static_cast<std::size_t>(trackCount), 1);
    for (const MidiNote& n : midi.notes) {
        const MidiTrackRule* r = ruleOf(n);
        if (r && r->off) continue;
        if (r) {
            bool f = trackFirst[static_cast<std::size_t>(n.track)] != 0;
            widen(byTrack[static_cast<std::size_t>(n.track)], n.key, f);
            trackFirst[static_cast<std::size_t>(n.track)] = 0;
        } else if (percussion(n)) {
            widen(drums, n.key, drumsFirst);
        } else {
            widen(grid, n.key, gridFirst);
        }
    }
    const auto placementOf = [&](const MidiNote& n) -> const Placement& {
        if (ruleOf(n)) return byTrack[static_cast<std::size_t>(n.track)];
        return percussion(n) ? drums : grid;
    };

    ImportedScore out;
    ImportReport& report = out.report;
    report.format = "midi";
    struct Kept {
        const MidiNote* note;
        std::int64_t end;
        int motor;
    };
    std::vector<Kept> kept;
    std::array<std::int64_t, core::kMaxMotors> busyUntil {};
    std::array<bool, core::kMaxMotors> used {};
    const auto& notes = midi.notes;
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
        if (static_cast<int>(order.size()) > o.maxMotors) {
            report.dropped += static_cast<int>(order.size()) - o.maxMotors;
            order.resize(static_cast<std::size_t>(o.maxMotors));
        }
        // Room in the budget: notes held from before end here, the oldest first.
        std::vector<std::size_t> sounding;
        for (std::size_t k = 0; k < kept.size(); ++k)
            if (kept[k].end > tick) sounding.push_back(k);
        for (std::size_t s = 0; static_cast<int>(sounding.size() - s + order.size()) > o.maxMotors; ++s) {
            Kept& held = kept[sounding[s]];
            held.end = tick;
            busyUntil[static_cast<std::size_t>(held.motor)] = tick;
            ++report.shortened;
        }
        for (const MidiNote* n : order) {
            const Placement& p = placementOf(*n);
            const int count = static_cast<int>(p.motors.size());
            const int position = p.hi > p.lo ? std::clamp((n->key - p.lo) * count / (p.hi - p.lo + 1), 0, count - 1) : count / 2;
            // The nearest free motor (upward on a tie) that no note has just left: a new onset on
            // a motor still running from the note before would not be felt as one.
            int chosen = -1;
            const double now = midi.secondsAt(tick);
            for (const bool allowJustLeft : {false, true})
                for (int d = 0; d < count && chosen < 0; ++d)
                    for (const int c : {position + d, position - d}) {
                        if (c < 0 || c >= count || chosen >= 0) continue;
                        const auto m = static_cast<std::size_t>(p.motors[static_cast<std::size_t>(c)]);
                        const bool justLeft = used[m] && now - midi.secondsAt(busyUntil[m]) < kJustLeft;
                        if (busyUntil[m] <= tick && (allowJustLeft || !justLeft)) chosen = static_cast<int>(m);
                    }
            if (chosen < 0) {
                ++report.dropped;
                continue;
            }
            busyUntil[static_cast<std::size_t>(chosen)] = n->end;
            used[static_cast<std::size_t>(chosen)] = true;
            kept.push_back({n, n->end, chosen});
        }
    }
    if (kept.empty()) throw core::InputError(source, 0, "", "no notes to import (the file has " + std::to_string(notes.size()) + ")");
    std::stable_sort(kept.begin(), kept.end(), [](const Kept& a, const Kept& b) { return a.note->start < b.note->start; });

    // Parts: one per track with notes (at most 8), else one for all.
    std::vector<int> partOfTrack(static_cast<std::size_t>(trackCount), -1);
    std::vector<std::string> partNames;
    std::vector<int> partTrack;
    for (const Kept& k : kept)
        if (k.note->channel != 9 && partOfTrack[static_cast<std::size_t>(k.note->track)] < 0) {
            partOfTrack[static_cast<std::size_t>(k.note->track)] = static_cast<int>(partNames.size());
            std::string nm = scoretext::name(midi.trackNames[static_cast<std::size_t>(k.note->track)], "track-" + std::to_string(k.note->track + 1));
            for (const auto& other : partNames)
                if (other == nm) nm = "track-" + std::to_string(k.note->track + 1);
            partNames.push_back(nm);
            partTrack.push_back(k.note->track);
        }
    const bool onePart = partNames.size() > static_cast<std::size_t>(tactile::kMaxScoreParts);

    // Times: beats (ticks per quarter) or seconds (SMPTE).
    const auto timeText = [&](std::int64_t tick) {
        return midi.smpte ? scoretext::number(midi.secondsAt(tick)) : scoretext::number(static_cast<double>(tick) / midi.ticksPerQuarter);
    };
    struct Line {
        std::int64_t tick;
        int kind;   // 0 tempo, 1 cue, 2 note
        std::string text;
    };
    std::vector<Line> lines;
    for (const Kept& k : kept) {
        const MidiNote& n = *k.note;
        const double seconds = midi.secondsAt(k.end) - midi.secondsAt(n.start);
        const float level = midiVelocityLevel(n.velocity, seconds, o);
        std::string s = timeText(n.start) + " note m=" + std::to_string(k.motor + 1) + " dur=" +
                        (midi.smpte ? scoretext::number(seconds) : scoretext::number(static_cast<double>(k.end - n.start) / midi.ticksPerQuarter)) +
                        " level=" + scoretext::number(level, 1);
        // Percussion has no pitch to follow: such notes belong to no part and play where the
        // alignment of the pitched notes places the score.
        if (n.channel != 9) {
            if (o.follow) s += " pitch=" + pitchName(n.key);
            s += " part=" + (onePart ? std::string("music") : partNames[static_cast<std::size_t>(partOfTrack[static_cast<std::size_t>(n.track)])]);
        }
        if (n.velocity < o.softBelowVelocity && seconds >= o.softLongerThan) s += " start=soft";
        lines.push_back({n.start, 2, std::move(s)});
        ++report.notes;
    }
    std::set<std::string> cueNames;
    const auto cue = [&](std::int64_t tick, const std::string& wanted) {
        std::string nm = wanted;
        for (int k = 2; cueNames.count(nm); ++k) nm = wanted + "-" + std::to_string(k);
        cueNames.insert(nm);
        lines.push_back({tick, 1, timeText(tick) + " cue " + nm});
        ++report.cues;
    };
    const auto bpmOf = [&](double us) {
        const double bpm = 6.0e7 / us;
        if (bpm > 1000.0 || bpm < 1.0) report.warnings.push_back("a tempo of " + scoretext::number(bpm, 2) + " bpm clamped to 1..1000");
        return std::clamp(bpm, 1.0, 1000.0);
    };
    if (!midi.smpte)
        for (std::size_t t = 1; t < midi.tempo.size(); ++t) {
            lines.push_back({midi.tempo[t].tick, 0, timeText(midi.tempo[t].tick) + " tempo " + scoretext::number(bpmOf(midi.tempo[t].microsPerQuarter), 3)});
            cue(midi.tempo[t].tick, "tempo-" + std::to_string(t));
        }
    for (const MidiMarker& m : midi.markers) cue(m.tick, scoretext::name(m.text, m.cuePoint ? "cue-point" : "marker"));
    std::stable_sort(lines.begin(), lines.end(), [](const Line& a, const Line& b) {
        return a.tick != b.tick ? a.tick < b.tick : a.kind < b.kind;
    });

    std::string title;
    for (const auto& nm : midi.trackNames)
        if (title.empty()) title = scoretext::oneLine(nm);
    if (title.empty()) title = scoretext::oneLine(std::filesystem::path(source).stem().string());
    if (title.empty()) title = "imported";
    std::string& text = out.text;
    text += "armadillo-score 2\n";
    text += "# Imported from " + scoretext::oneLine(std::filesystem::path(source).filename().string()) +
            " by `armadillo score import` (docs/FORMATS.md, \"MIDI files\"):\n"
            "# lowest pitch at the elbow, highest at the wrist; at most " + std::to_string(o.maxMotors) +
            " notes at once; velocity -> level capped at the rated level for notes over " +
            scoretext::number(o.safety.maxAboveRatingRun, 3) + " s.\n";
    text += "title " + title + "\n";
    text += midi.smpte ? "units seconds\n" : "units beats\n";
    if (!midi.smpte) text += "tempo " + scoretext::number(bpmOf(midi.tempo.front().microsPerQuarter), 3) + "\n";
    if (onePart) {
        text += std::string("part music follow=") + (o.follow ? "notes" : "none") + "\n";
    } else {
        for (std::size_t p = 0; p < partNames.size(); ++p) {
            text += "part " + partNames[p] + " follow=" + (o.follow ? "notes" : "none");
            const std::string& trackName = midi.trackNames[static_cast<std::size_t>(partTrack[p])];
            text += "   # track " + std::to_string(partTrack[p] + 1) + (trackName.empty() ? "" : ": " + scoretext::oneLine(trackName)) + "\n";
        }
    }
    for (const Line& l : lines) text += l.text + "\n";
    std::int64_t lastTick = midi.endTick;
    for (const Kept& k : kept) lastTick = std::max(lastTick, k.end);
    text += "length " + (midi.smpte ? scoretext::lengthNumber(midi.secondsAt(lastTick))
                                    : scoretext::lengthNumber(static_cast<double>(lastTick) / midi.ticksPerQuarter)) + "\n";
    if (midi.unterminatedNotes > 0) report.warnings.push_back(std::to_string(midi.unterminatedNotes) + " notes had no note-off (ended at their track's end)");
    out.score = tactile::parseScore(text, source);
    return out;
}

} // namespace armadillo::formats
