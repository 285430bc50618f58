// Tactile score parser and tempo map. The format (docs/TACTILE.md):
//
//   armadillo-score 1                 first line that is not blank or a comment
//   title Any words                   directives (before the first event)
//   units beats | seconds
//   tempo BPM                         the tempo at beat 0
//   length TIME                       where the score ends (default: the last event's end; may
//                                     also come after the events)
//   TIME note m=MOTORS dur=D level=L[->L2->...]
//   TIME pattern KIND [m=MOTORS] [level=L] [dur=D|hold] [rate=HZ] [voice=V]
//   TIME stop voice=V | TIME stop all
//   TIME tempo BPM                    (beats only)
//
// TIME is a number in the file's units, or +D: D after the previous event.
//
// Version 2 (`armadillo-score 2`) adds, for following the recording the listener plays:
//   part NAME [follow=none|notes|amplitude|notes+amplitude] [attack=MS] [release=MS]
//             [curve=linear|db] [floor=DB] [top=DB]             (a directive)
//   note ... [pitch=C5|440hz] [part=NAME] [start=soft|fast]
//   pattern ... [part=NAME] [start=soft|fast]
//   TIME cue NAME [detect=none|onset|loud|quiet] [window=S] [level=DB]
#include "Tactile/Score.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <unordered_set>

namespace armadillo::tactile {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kMaxTime = 1.0e6;        // units: a score of more than ~11 days is a typo
constexpr std::size_t kMaxEnvelope = 64;

std::optional<double> parseNumber(std::string_view s) noexcept
{
    if (s.empty() || s.size() > 64) return std::nullopt;
    // Plain decimal only: no hex, inf or nan, so a score reads the same everywhere.
    for (char c : s)
        if (!((c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E'))
            return std::nullopt;
    char buffer[72];
    std::copy(s.begin(), s.end(), buffer);
    buffer[s.size()] = '\0';
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(buffer, &end);
    if (end != buffer + s.size() || errno == ERANGE || !std::isfinite(v)) return std::nullopt;
    return v;
}

std::vector<std::string_view> splitWords(std::string_view line)
{
    std::vector<std::string_view> words;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        std::size_t j = i;
        while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
        if (j > i) words.push_back(line.substr(i, j - i));
        i = j;
    }
    return words;
}

struct NamedSet {
    std::string_view name;
    std::uint16_t mask;
};
constexpr NamedSet kMotorSets[] = {
    {"all", motors::kGrid},          {"grid", motors::kGrid},
    {"wrist", motors::kWristRow},    {"middle", motors::kMiddleRow},
    {"elbow", motors::kElbowRow},    {"left", motors::kLeftColumn},
    {"under", motors::kUndersideColumn}, {"right", motors::kRightColumn},
    {"back", motors::kBack},         {"wrist-anchors", motors::kWristAnchors},
    {"bones", motors::kBoneAnchors},
};

bool parseMotorNumber(std::string_view s, int& k) noexcept
{
    if (s.empty() || s.size() > 2) return false;
    k = 0;
    for (char c : s) {
        if (c < '0' || c > '9') return false;
        k = 10 * k + (c - '0');
    }
    return k >= 1 && k <= core::kMaxMotors;
}

class Parser {
public:
    Parser(std::string_view text, const std::string& source) : text_(text), source_(source) {}

    Score run()
    {
        score_.source = source_;
        score_.tempo.push_back(TempoPoint {});
        bool sawHeader = false;
        std::size_t pos = 0;
        while (pos <= text_.size()) {
            std::size_t end = text_.find('\n', pos);
            if (end == std::string_view::npos) end = text_.size();
            ++line_;
            std::string_view raw = text_.substr(pos, end - pos);
            pos = end + 1;
            if (raw.find('\0') != std::string_view::npos) fail("", "a NUL byte: not a text file");
            const auto hash = raw.find('#');
            if (hash != std::string_view::npos) raw = raw.substr(0, hash);
            words_ = splitWords(raw);
            if (words_.empty()) continue;
            if (!sawHeader) {
                if (words_.size() != 2 || words_[0] != "armadillo-score" || (words_[1] != "1" && words_[1] != "2"))
                    fail("", "a score starts with the line 'armadillo-score 1' (or 2)");
                score_.version = words_[1] == "2" ? 2 : 1;
                sawHeader = true;
                continue;
            }
            const char first = words_[0][0];
            if ((first >= '0' && first <= '9') || first == '+' || first == '.') event();
            else directive();
            if (end == text_.size()) break;
        }
        if (!sawHeader) {
            line_ = 0;
            fail("", "empty score: no 'armadillo-score 1' line");
        }
        finish();
        return std::move(score_);
    }

private:
    [[noreturn]] void fail(std::string_view field, const std::string& message) const
    {
        throw core::InputError(source_, line_, std::string(field), message);
    }

    double number(std::string_view word, std::string_view field, double lo, double hi)
    {
        const auto v = parseNumber(word);
        if (!v) fail(field, "'" + std::string(word) + "' is not a number");
        if (*v < lo || *v > hi)
            fail(field, std::string(word) + " is out of range " + trim(lo) + ".." + trim(hi));
        return *v;
    }

    static std::string trim(double v)
    {
        std::string s = std::to_string(v);
        while (s.size() > 1 && s.back() == '0') s.pop_back();
        if (!s.empty() && s.back() == '.') s.pop_back();
        return s;
    }

    // key=value arguments after the command; each key at most once, only the allowed ones.
    struct Args {
        std::vector<std::pair<std::string_view, std::string_view>> items;
        std::optional<std::string_view> get(std::string_view key) const
        {
            for (const auto& [k, v] : items)
                if (k == key) return v;
            return std::nullopt;
        }
    };
    Args arguments(std::size_t from, std::initializer_list<std::string_view> allowed)
    {
        Args a;
        for (std::size_t i = from; i < words_.size(); ++i) {
            const auto w = words_[i];
            const auto eq = w.find('=');
            if (eq == std::string_view::npos || eq == 0 || eq + 1 == w.size())
                fail(w, "expected key=value, got '" + std::string(w) + "'");
            const auto key = w.substr(0, eq);
            if (std::find(allowed.begin(), allowed.end(), key) == allowed.end())
                fail(key, "unknown key '" + std::string(key) + "' for " + std::string(words_[1]));
            if (a.get(key)) fail(key, "'" + std::string(key) + "' given twice");
            a.items.emplace_back(key, w.substr(eq + 1));
        }
        return a;
    }

    void directive()
    {
        const std::string_view name = words_[0];
        if (sawEvent_ && name != "length") fail(name, "directives ('" + std::string(name) + "') go before the first event");
        if (name == "title") {
            if (words_.size() < 2) fail(name, "title needs some words");
            if (seen(name)) fail(name, "'title' given twice (a score has one title)");
            const char* first = words_[1].data();
            const char* last = words_.back().data() + words_.back().size();
            score_.title.assign(first, static_cast<std::size_t>(last - first));
            return;
        }
        if (name == "part") {
            part();
            return;
        }
        if (words_.size() != 2) fail(name, "'" + std::string(name) + "' takes exactly one value");
        if (seen(name)) fail(name, "'" + std::string(name) + "' given twice");
        if (name == "units") {
            if (words_[1] == "beats") score_.inBeats = true;
            else if (words_[1] == "seconds") score_.inBeats = false;
            else fail(name, "units are 'beats' or 'seconds', not '" + std::string(words_[1]) + "'");
        } else if (name == "tempo") {
            score_.tempo[0].bpm = number(words_[1], name, 1.0, 1000.0);
        } else if (name == "length") {
            lengthUnits_ = number(words_[1], name, 0.0, kMaxTime);
            lengthLine_ = line_;
        } else {
            fail(name, "unknown directive '" + std::string(name) + "' (expected title, units, tempo, length, part or an event time)");
        }
    }

    void needV2(std::string_view field)
    {
        if (score_.version < 2) fail(field, "'" + std::string(field) + "' needs 'armadillo-score 2' as the first line");
    }

    void part()
    {
        needV2("part");
        if (words_.size() < 2) fail("part", "part NAME [follow=...] [attack=MS] [release=MS] [curve=linear|db] [floor=DB] [top=DB]");
        ScorePart p;
        p.line = line_;
        p.name = std::string(words_[1]);
        if (p.name.find('=') != std::string::npos) fail("part", "a part needs a name first: part NAME key=value ...");
        for (const auto& q : score_.parts)
            if (q.name == p.name) fail("part", "part '" + p.name + "' given twice");
        if (static_cast<int>(score_.parts.size()) >= kMaxScoreParts) fail("part", "at most 8 parts");
        const Args a = arguments(2, {"follow", "attack", "release", "curve", "floor", "top"});
        if (const auto f = a.get("follow")) {
            if (*f == "notes") p.followNotes = true;
            else if (*f == "amplitude") p.followAmplitude = true;
            else if (*f == "notes+amplitude" || *f == "amplitude+notes") p.followNotes = p.followAmplitude = true;
            else if (*f != "none") fail("follow", "follow is none, notes, amplitude or notes+amplitude, not '" + std::string(*f) + "'");
        }
        if (const auto v = a.get("attack")) p.attackMs = number(*v, "attack", 0.1, 10000.0);
        if (const auto v = a.get("release")) p.releaseMs = number(*v, "release", 0.1, 10000.0);
        if (const auto v = a.get("curve")) {
            if (*v == "db") p.curveDb = true;
            else if (*v != "linear") fail("curve", "curve is linear or db, not '" + std::string(*v) + "'");
        }
        if (const auto v = a.get("floor")) p.floorDb = number(*v, "floor", -120.0, 0.0);
        if (const auto v = a.get("top")) p.topDb = number(*v, "top", -120.0, 0.0);
        if (!(p.topDb > p.floorDb)) fail("top", "top (" + trim(p.topDb) + " dB) must lie above floor (" + trim(p.floorDb) + " dB)");
        score_.parts.push_back(std::move(p));
    }

    int partOf(const Args& a)
    {
        const auto v = a.get("part");
        if (!v) return -1;
        needV2("part");
        for (std::size_t i = 0; i < score_.parts.size(); ++i)
            if (score_.parts[i].name == *v) return static_cast<int>(i);
        fail("part", "no part '" + std::string(*v) + "' (declare it with a 'part' line before the events)");
    }

    bool softOf(const Args& a)
    {
        const auto v = a.get("start");
        if (!v) return false;
        needV2("start");
        if (*v == "soft") return true;
        if (*v == "fast") return false;
        fail("start", "start is soft or fast, not '" + std::string(*v) + "'");
    }

    bool seen(std::string_view name)
    {
        for (const auto& s : seenDirectives_)
            if (s == name) return true;
        seenDirectives_.emplace_back(name);
        return false;
    }

    std::uint16_t motorsOf(const Args& a, bool required)
    {
        const auto m = a.get("m");
        if (!m) {
            if (required) fail("m", "which motors? (m=3, m=1,3, m=1-9, m=wrist ...)");
            return motors::kGrid;
        }
        std::uint16_t mask = 0;
        if (!parseMotorSet(*m, mask) || mask == 0)
            fail("m", "'" + std::string(*m) + "' is not a motor set (numbers 1..16, ranges a-b, or names)");
        return mask;
    }

    float level(std::string_view word)
    {
        return static_cast<float>(number(word, "level", 0.0, double(core::kMaxLevel)));
    }

    // Seconds from the file's units (time or duration measured from `fromUnits`).
    double toSeconds(double units) const
    {
        return score_.inBeats ? score_.secondsAtBeat(units) : units;
    }

    void event()
    {
        const std::string_view timeWord = words_[0];
        double t;
        if (timeWord[0] == '+') {
            if (timeWord.size() < 2 || timeWord[1] == '+' || timeWord[1] == '-')
                fail("time", "'" + std::string(timeWord) + "' is not a time");
            t = lastTime_ + number(timeWord.substr(1), "time", 0.0, kMaxTime);
        } else {
            t = number(timeWord, "time", 0.0, kMaxTime);
        }
        if (t > kMaxTime) fail("time", "time beyond " + trim(kMaxTime));
        if (t < lastTime_)
            fail("time", "time goes backwards (" + trim(t) + " after " + trim(lastTime_) + "): events must be in order");
        lastTime_ = t;
        sawEvent_ = true;
        if (words_.size() < 2) fail("command", "an event needs a command: note, pattern, stop or tempo");
        const std::string_view command = words_[1];
        if (command == "note") note(t);
        else if (command == "pattern") pattern(t);
        else if (command == "stop") stop(t);
        else if (command == "tempo") tempo(t);
        else if (command == "cue") cue(t);
        else fail("command", "unknown command '" + std::string(command) + "' (note, pattern, stop, tempo, cue)");
    }

    void cue(double t)
    {
        needV2("cue");
        if (words_.size() < 3 || words_[2].find('=') != std::string_view::npos) fail("cue", "a cue needs a name: TIME cue NAME [detect=...]");
        ScoreCue c;
        c.line = line_;
        c.name = std::string(words_[2]);
        if (!cueNames_.insert(c.name).second) fail("cue", "cue '" + c.name + "' given twice");
        const Args a = arguments(3, {"detect", "window", "level"});
        if (const auto d = a.get("detect")) {
            if (*d == "onset") c.detect = ScoreCue::Detect::Onset;
            else if (*d == "loud") c.detect = ScoreCue::Detect::Loud;
            else if (*d == "quiet") c.detect = ScoreCue::Detect::Quiet;
            else if (*d != "none") fail("detect", "detect is none, onset, loud or quiet, not '" + std::string(*d) + "'");
        }
        if (const auto w = a.get("window")) c.window = number(*w, "window", 0.0, 600.0);
        if (const auto l = a.get("level")) c.levelDb = number(*l, "level", -120.0, 0.0);
        pendingCues_.push_back({t, std::move(c)});
        end_ = std::max(end_, t);
    }

    void note(double t)
    {
        const Args a = arguments(2, {"m", "dur", "level", "pitch", "part", "start"});
        ScoreNote n;
        n.line = line_;
        n.motors = motorsOf(a, true);
        n.part = partOf(a);
        n.soft = softOf(a);
        if (const auto p = a.get("pitch")) {
            needV2("pitch");
            n.pitchHz = parsePitch(*p);
            if (!(n.pitchHz >= 20.0 && n.pitchHz <= 5000.0))
                fail("pitch", "'" + std::string(*p) + "' is not a pitch (a note name like C5, Fs4 (F sharp), Bb3, or 20hz..5000hz)");
        }
        if (n.part >= 0 && score_.parts[static_cast<std::size_t>(n.part)].followNotes && n.pitchHz == 0.0)
            fail("pitch", "a note of a part that follows notes needs pitch= (what the recording plays)");
        const auto dur = a.get("dur");
        if (!dur) fail("dur", "a note needs dur=");
        const double d = number(*dur, "dur", 0.0, kMaxTime);
        if (!(d > 0.0)) fail("dur", "a note lasts more than 0");
        const auto lv = a.get("level");
        if (!lv) fail("level", "a note needs level= (a level 0..15 or an envelope like 2->7)");
        std::string_view rest = *lv;
        while (true) {
            const auto arrow = rest.find("->");
            n.envelope.push_back(level(rest.substr(0, arrow)));
            if (n.envelope.size() > kMaxEnvelope) fail("level", "an envelope has at most 64 points");
            if (arrow == std::string_view::npos) break;
            rest = rest.substr(arrow + 2);
        }
        pendingNotes_.push_back({t, t + d, std::move(n)});
        end_ = std::max(end_, t + d);
    }

    void pattern(double t)
    {
        if (words_.size() < 3) fail("pattern", "which pattern? (" + kindList() + ")");
        const auto kind = patternKindFromName(words_[2]);
        if (!kind) fail("pattern", "unknown pattern '" + std::string(words_[2]) + "' (" + kindList() + ")");
        // The kind is word 2; arguments start at 3.
        const Args a = arguments(3, {"m", "level", "dur", "rate", "voice", "part", "start"});
        PendingPattern p;
        p.at = t;
        p.line = line_;
        (void) partOf(a);   // a pattern plays by the score position (which the alignment moves)
        p.request.kind = *kind;
        p.request.soft = softOf(a);
        p.request.motors = motorsOf(a, false);
        p.request.level = a.get("level") ? level(*a.get("level")) : 10.0f;
        p.request.voice = a.get("voice") ? voiceNumber(*a.get("voice")) : 0;
        if (a.get("rate")) p.request.rate = number(*a.get("rate"), "rate", 1e-3, 1000.0);
        if (const auto dur = a.get("dur")) {
            if (*dur == "hold") p.hold = true;
            else {
                p.durUnits = number(*dur, "dur", 0.0, kMaxTime);
                if (!(p.durUnits > 0.0)) fail("dur", "a pattern lasts more than 0 (or dur=hold)");
            }
        }
        end_ = std::max(end_, t + p.durUnits);
        pendingPatterns_.push_back(p);
    }

    void stop(double t)
    {
        if (words_.size() == 3 && words_[2] == "all") {
            for (int v = 0; v < core::kPatternVoices; ++v) pendingStops_.push_back({t, v, line_});
            return;
        }
        const Args a = arguments(2, {"voice"});
        const auto v = a.get("voice");
        if (!v) fail("voice", "stop needs voice=V or 'all'");
        pendingStops_.push_back({t, voiceNumber(*v), line_});
        end_ = std::max(end_, t);
    }

    int voiceNumber(std::string_view word)
    {
        const double v = number(word, "voice", 0.0, double(core::kPatternVoices - 1));
        if (std::floor(v) != v) fail("voice", "a voice is a whole number 0..7");
        return static_cast<int>(v);
    }

    void tempo(double t)
    {
        if (!score_.inBeats) fail("tempo", "tempo changes need 'units beats'");
        if (words_.size() != 3) fail("tempo", "tempo takes one value: TIME tempo BPM");
        const double bpm = number(words_[2], "tempo", 1.0, 1000.0);
        TempoPoint p;
        p.beat = t;
        p.seconds = score_.secondsAtBeat(t);
        p.bpm = bpm;
        if (score_.tempo.back().beat == t) score_.tempo.back().bpm = bpm;   // same beat: replaces
        else score_.tempo.push_back(p);
    }

    static std::string kindList()
    {
        std::string s;
        for (int k = 0; k < kPatternKinds; ++k) {
            if (k) s += ", ";
            s += patternName(static_cast<core::PatternKind>(k));
        }
        return s;
    }

    void finish()
    {
        // Notes: the tempo map is complete now, so beats become seconds.
        for (auto& p : pendingNotes_) {
            p.note.start = toSeconds(p.from);
            p.note.end = toSeconds(p.to);
            score_.notes.push_back(std::move(p.note));
        }
        for (auto& c : pendingCues_) {
            c.cue.time = toSeconds(c.at);
            score_.cues.push_back(std::move(c.cue));
        }
        // Patterns: each runs until its duration, a stop on its voice, or the next pattern on
        // its voice, whichever comes first. One pass over each list (patterns and stops are in
        // file order, so in time order): per voice, the next pattern is found walking backwards
        // and the first stop at or after a pattern by a cursor that only moves forward.
        std::vector<std::vector<std::size_t>> stopsOf(core::kPatternVoices);
        for (std::size_t k = 0; k < pendingStops_.size(); ++k) stopsOf[static_cast<std::size_t>(pendingStops_[k].voice)].push_back(k);
        std::vector<std::size_t> stopCursor(core::kPatternVoices, 0);
        std::vector<double> nextOnVoice(pendingPatterns_.size(), kInfinity);
        {
            std::vector<double> later(core::kPatternVoices, kInfinity);
            for (std::size_t i = pendingPatterns_.size(); i-- > 0;) {
                const auto v = static_cast<std::size_t>(pendingPatterns_[i].request.voice);
                nextOnVoice[i] = later[v];
                later[v] = pendingPatterns_[i].at;
            }
        }
        for (std::size_t i = 0; i < pendingPatterns_.size(); ++i) {
            const PendingPattern& p = pendingPatterns_[i];
            ScorePattern sp;
            sp.line = p.line;
            sp.request = p.request;
            sp.start = toSeconds(p.at);
            // Its own end: the written duration, a one-shot's default length, or never.
            double end = kInfinity;
            if (p.durUnits > 0.0) end = toSeconds(p.at + p.durUnits);
            else if (!p.hold && !patternIsPeriodic(p.request.kind))
                end = sp.start + patternLength(p.request, kDefaultPatternParams);
            // Cut short by the first stop on its voice written at or after it, or by the next
            // pattern on its voice.
            const auto v = static_cast<std::size_t>(p.request.voice);
            const std::vector<std::size_t>& stops = stopsOf[v];
            std::size_t& cursor = stopCursor[v];
            while (cursor < stops.size()) {
                const PendingStop& s = pendingStops_[stops[cursor]];
                if (s.at > p.at || (s.at == p.at && s.line > p.line)) break;
                ++cursor;
            }
            if (cursor < stops.size()) end = std::min(end, toSeconds(pendingStops_[stops[cursor]].at));
            if (std::isfinite(nextOnVoice[i])) end = std::min(end, toSeconds(nextOnVoice[i]));
            sp.end = end;
            sp.request.duration = p.durUnits > 0.0 ? toSeconds(p.at + p.durUnits) - sp.start : (p.hold ? -1.0 : 0.0);
            if (!(sp.end > sp.start)) continue;   // stopped or replaced at the instant it starts
            score_.patterns.push_back(sp);
        }
        if (lengthUnits_ >= 0.0) {
            if (lengthUnits_ < end_) {
                line_ = lengthLine_;
                fail("length", "length " + trim(lengthUnits_) + " ends before the last event (" + trim(end_) + ")");
            }
            score_.length = toSeconds(lengthUnits_);
        } else {
            score_.length = toSeconds(end_);
            for (const auto& p : score_.patterns)
                if (std::isfinite(p.end)) score_.length = std::max(score_.length, p.end);
        }
        // A pattern running "until stopped" ends with the score.
        for (auto& p : score_.patterns) p.end = std::min(p.end, std::max(score_.length, p.start));
        score_.patterns.erase(std::remove_if(score_.patterns.begin(), score_.patterns.end(),
                                             [](const ScorePattern& p) { return !(p.end > p.start); }),
                              score_.patterns.end());
    }

    struct PendingNote {
        double from, to;
        ScoreNote note;
    };
    struct PendingPattern {
        double at = 0.0;
        long line = 0;
        core::PatternRequest request {};
        double durUnits = 0.0;
        bool hold = false;
    };
    struct PendingCue {
        double at;
        ScoreCue cue;
    };
    struct PendingStop {
        double at;
        int voice;
        long line;
    };

    std::string_view text_;
    std::string source_;
    Score score_;
    std::vector<std::string_view> words_;
    std::vector<std::string> seenDirectives_;
    std::vector<PendingNote> pendingNotes_;
    std::vector<PendingPattern> pendingPatterns_;
    std::vector<PendingStop> pendingStops_;
    std::vector<PendingCue> pendingCues_;
    std::unordered_set<std::string> cueNames_;
    long line_ = 0;
    double lastTime_ = 0.0;
    double end_ = 0.0;
    double lengthUnits_ = -1.0;
    long lengthLine_ = 0;
    bool sawEvent_ = false;
};

} // namespace

bool parseMotorSet(std::string_view text, std::uint16_t& mask) noexcept
{
    mask = 0;
    if (text.empty()) return false;
    std::size_t pos = 0;
    while (pos <= text.size()) {
        std::size_t comma = text.find(',', pos);
        if (comma == std::string_view::npos) comma = text.size();
        const std::string_view item = text.substr(pos, comma - pos);
        if (item.empty()) return false;
        bool named = false;
        for (const auto& s : kMotorSets)
            if (s.name == item) {
                mask = static_cast<std::uint16_t>(mask | s.mask);
                named = true;
            }
        if (!named) {
            const auto dash = item.find('-');
            int a = 0, b = 0;
            if (dash == std::string_view::npos) {
                if (!parseMotorNumber(item, a)) return false;
                b = a;
            } else if (!parseMotorNumber(item.substr(0, dash), a) || !parseMotorNumber(item.substr(dash + 1), b) || b < a) {
                return false;
            }
            for (int k = a; k <= b; ++k) mask = static_cast<std::uint16_t>(mask | (1u << (k - 1)));
        }
        if (comma == text.size()) break;
        pos = comma + 1;
    }
    return true;
}

float ScoreNote::levelAt(double seconds) const noexcept
{
    if (envelope.empty() || !(seconds >= start) || !(seconds < end)) return 0.0f;
    if (envelope.size() == 1) return envelope[0];
    const double x = (seconds - start) / (end - start) * double(envelope.size() - 1);
    const auto i = std::min(static_cast<std::size_t>(x), envelope.size() - 2);
    const double f = x - double(i);
    return static_cast<float>((1.0 - f) * static_cast<double>(envelope[i]) + f * static_cast<double>(envelope[i + 1]));
}

float ScoreNote::levelAtFraction(double fraction) const noexcept
{
    if (envelope.empty()) return 0.0f;
    const double f = std::isfinite(fraction) ? std::clamp(fraction, 0.0, 0.999999) : 0.0;
    return levelAt(start + f * (end - start));
}

double parsePitch(std::string_view text) noexcept
{
    if (text.size() > 2 && (text.substr(text.size() - 2) == "hz" || text.substr(text.size() - 2) == "Hz")) {
        const auto v = parseNumber(text.substr(0, text.size() - 2));
        return v && *v > 0.0 ? *v : 0.0;
    }
    if (text.size() < 2 || text.size() > 3) return 0.0;
    static constexpr int kSemitone[7] = {9, 11, 0, 2, 4, 5, 7};   // A B C D E F G from C
    const char letter = text[0];
    if (letter < 'A' || letter > 'G') return 0.0;
    int semitone = kSemitone[letter - 'A'];
    std::size_t i = 1;
    if (text.size() == 3) {
        if (text[1] == 's') ++semitone;   // '#' starts a comment in a score: sharps are written s
        else if (text[1] == 'b') --semitone;
        else return 0.0;
        i = 2;
    }
    if (text[i] < '0' || text[i] > '9') return 0.0;
    const int octave = text[i] - '0';
    const int midi = 12 * (octave + 1) + semitone;   // C4 = 60
    return 440.0 * std::pow(2.0, (midi - 69) / 12.0);
}

namespace {
std::atomic<bool (*)(const std::string&) noexcept> gAccepts {nullptr};
std::atomic<Score (*)(const std::string&)> gLoad {nullptr};
} // namespace

void setScoreFileReader(ScoreFileReader reader) noexcept
{
    gLoad.store(reader.load);
    gAccepts.store(reader.accepts);
}

ScoreFileReader scoreFileReader() noexcept
{
    ScoreFileReader r;
    r.accepts = gAccepts.load();
    r.load = gLoad.load();
    return r;
}

// The tempo points are in order of beat and of seconds (events are in time order and tempo
// is positive), so each look-up is a binary search: a score with many tempo changes stays linear.
double Score::secondsAtBeat(double beat) const noexcept
{
    if (tempo.empty()) return beat * 0.5;
    auto it = std::upper_bound(tempo.begin() + 1, tempo.end(), beat, [](double b, const TempoPoint& p) { return b < p.beat; });
    const TempoPoint& p = *(it - 1);
    return p.seconds + (beat - p.beat) * 60.0 / p.bpm;
}

namespace {
const TempoPoint& tempoAtSeconds(const std::vector<TempoPoint>& tempo, double seconds) noexcept
{
    auto it = std::upper_bound(tempo.begin() + 1, tempo.end(), seconds, [](double t, const TempoPoint& p) { return t < p.seconds; });
    return *(it - 1);
}
} // namespace

double Score::beatAtSeconds(double seconds) const noexcept
{
    if (tempo.empty()) return seconds * 2.0;
    const TempoPoint& p = tempoAtSeconds(tempo, seconds);
    return p.beat + (seconds - p.seconds) * p.bpm / 60.0;
}

double Score::bpmAtSeconds(double seconds) const noexcept
{
    if (tempo.empty()) return 120.0;
    return tempoAtSeconds(tempo, seconds).bpm;
}

Score parseScore(std::string_view text, const std::string& sourceName)
{
    return Parser(text, sourceName).run();
}

Score loadScore(const std::string& path) { return parseScore(core::readWholeFile(path), path); }

} // namespace armadillo::tactile
