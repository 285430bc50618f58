#include "Access/AdaptivePlan.h"
#include "Core/Errors.h"
#include <algorithm>
#include <cmath>

namespace armadillo::access {

namespace {
double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0); }
} // namespace

AdaptivePlanner::AdaptivePlanner(const ReaderProfile& history, const AdaptiveOptions& options)
    : options_(options), answers_(history.answers), rng_(options.seed)
{
    for (const std::string& s : options_.stages) {
        if (s != "letters" && s != "words" && s != "signs" && s != "contractions")
            throw core::InputError("training", 0, "", "unknown adaptive stage '" + s + "' (letters, words, signs, contractions)");
        if (items(s).empty()) throw core::InputError("training", 0, "", "the " + s + " stage has nothing to train");
        stages_.push_back(s);
    }
    if (stages_.empty()) throw core::InputError("training", 0, "", "no stage to train");
    // Start where the reader stands: skip stages the history shows steady.
    while (stage_ + 1 < stages_.size() && steady(stages_[stage_])) ++stage_;
}

std::vector<std::string> AdaptivePlanner::items(const std::string& stage) const
{
    std::vector<std::string> out;
    if (stage == "letters")
        for (char c = 'a'; c <= 'z'; ++c) out.emplace_back(1, c);
    else if (stage == "words")
        out = options_.words;
    else if (stage == "contractions")
        out = options_.contractions;
    else if (stage == "signs")
        for (const auto& s : options_.signs) out.push_back(s.second);
    return out;
}

double AdaptivePlanner::weight(const std::string& item) const
{
    const std::string& stage = stages_[stage_];
    int wrong = 0, shown = 0, lastSeen = -1;
    // The last 5 presentations of the item in this stage, newest first.
    for (int i = static_cast<int>(answers_.size()) - 1; i >= 0; --i) {
        const ReaderAnswer& a = answers_[static_cast<std::size_t>(i)];
        if (a.stage != stage || a.expected != item) continue;
        if (lastSeen < 0) lastSeen = i;
        if (shown < 5) {
            ++shown;
            wrong += !a.correct;
        }
    }
    const double e = (wrong + 1.0) / (shown + 2.0);
    const double n = static_cast<double>(std::max<std::size_t>(1, items(stage).size()));
    const double age = lastSeen < 0 ? 1.5 * n : static_cast<double>(answers_.size()) - 1.0 - lastSeen;
    return 0.2 + 4.0 * e * e + 0.5 * std::min(age / n, 1.5);
}

bool AdaptivePlanner::steady(const std::string& stage) const
{
    if (stage != "letters") return false;   // words are the last step of the protocol
    const auto stats = itemStats(answers_, stage);
    for (char c = 'a'; c <= 'z'; ++c) {
        const auto it = stats.find(std::string(1, c));
        if (it == stats.end() || it->second.seen < 2) return false;
        int wrong = 0;
        for (bool r : it->second.recent) wrong += !r;
        if ((wrong + 1.0) / (it->second.recent.size() + 2.0) > 0.5) return false;
    }
    int n = 0, right = 0;
    for (auto it = answers_.rbegin(); it != answers_.rend() && n < 20; ++it)
        if (it->stage == stage) {
            ++n;
            right += it->correct;
        }
    return n >= 20 && right >= 18;
}

std::string AdaptivePlanner::pick(const std::vector<std::string>& candidates)
{
    std::vector<double> w;
    double total = 0.0;
    for (const std::string& c : candidates) {
        const double x = (c == last_ && candidates.size() > 1) ? 0.0 : weight(c);
        w.push_back(x);
        total += x;
    }
    double r = uniform01(rng_) * total;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
        if (r < w[i]) return candidates[i];
        r -= w[i];
    }
    for (std::size_t i = candidates.size(); i-- > 0;)
        if (w[i] > 0.0) return candidates[i];
    return candidates.front();
}

PlannedTrial AdaptivePlanner::next()
{
    ++trial_;
    if (stage_ + 1 < stages_.size() && steady(stages_[stage_])) ++stage_;
    const std::string& stage = stages_[stage_];
    PlannedTrial t;
    if (stage == "letters" && trial_ % 6 == 0) {
        // The pair most often mixed up (either way round), if any pair twice or more.
        std::map<std::pair<std::string, std::string>, int> pairs;
        for (const ReaderAnswer& a : answers_)
            if (a.stage == "letters" && !a.correct && a.answer.size() == 1 && a.answer[0] >= 'a' && a.answer[0] <= 'z')
                ++pairs[std::minmax(a.expected, a.answer)];
        const auto best = std::max_element(pairs.begin(), pairs.end(), [](const auto& x, const auto& y) { return x.second < y.second; });
        if (best != pairs.end() && best->second >= 2) {
            const bool swap = (rng_() & 1u) != 0;
            const std::string& a = swap ? best->first.second : best->first.first;
            const std::string& b = swap ? best->first.first : best->first.second;
            t.stage = "pairs";
            t.expected = a + b;
            t.shown = a + " " + b;
            t.prompt = "two letters you have mixed up: which, in order?";
            last_.clear();
            return t;
        }
    }
    const std::string item = pick(items(stage));
    last_ = item;
    t.stage = stage;
    t.expected = item;
    t.shown = item;
    t.prompt = stage == "letters" ? "which letter?" : stage == "signs" ? "which sign?" : "which word?";
    if (stage == "signs")
        for (const auto& s : options_.signs)
            if (s.second == item) t.shown = s.first;
    return t;
}

void AdaptivePlanner::record(const PlannedTrial& trial, const std::string& answer, bool correct, double rt, double t)
{
    ReaderAnswer a;
    a.session = options_.session;
    a.stage = trial.stage;
    a.method = options_.method;
    a.expected = trial.expected;
    a.answer = answer;
    a.correct = correct;
    a.rt = rt;
    a.t = t;
    if (trial.stage == "pairs") {
        // Each letter of the pair also counts as a presentation of that letter.
        answers_.push_back(a);
        for (std::size_t i = 0; i < trial.expected.size(); ++i) {
            ReaderAnswer l = a;
            l.stage = "letters";
            l.expected = std::string(1, trial.expected[i]);
            l.answer = i < answer.size() ? std::string(1, answer[i]) : std::string();
            l.correct = l.answer == l.expected;
            l.rt = -1.0;
            answers_.push_back(l);
        }
        return;
    }
    answers_.push_back(a);
}

} // namespace armadillo::access
