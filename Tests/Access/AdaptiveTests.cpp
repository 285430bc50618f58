// Training that adapts and remembers (issue 26): the plan, the profile file and the report.
#include "Access/AdaptivePlan.h"
#include "Access/Report.h"
#include "Core/Errors.h"
#include <catch2/catch.hpp>
#include <cstdio>
#include <map>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::access;

namespace {
/// The reader who always mixes up e and i and knows every other letter.
std::string confusedReader(const std::string& expected)
{
    std::string a;
    for (char c : expected) a += c == 'e' ? 'i' : c == 'i' ? 'e' : c;
    return a;
}

/// Runs `trials` trials; returns how often each letter was shown in the second half.
std::map<char, int> runSession(AdaptivePlanner& plan, int trials, std::map<char, int>* firstHalf = nullptr)
{
    std::map<char, int> shown;
    for (int i = 0; i < trials; ++i) {
        const PlannedTrial t = plan.next();
        const std::string answer = confusedReader(t.expected);
        plan.record(t, answer, answer == t.expected, 1.5, 4.0 * (i + 1));
        if (i >= trials / 2)
            for (char c : t.shown) shown[c] += c != ' ';
        else if (firstHalf)
            for (char c : t.shown) (*firstHalf)[c] += c != ' ';
    }
    return shown;
}

void checkConfusedShownTwiceAsOften(const std::map<char, int>& shown)
{
    double others = 0.0;
    for (char c = 'a'; c <= 'z'; ++c)
        if (c != 'e' && c != 'i') others += shown.count(c) ? shown.at(c) : 0;
    others /= 24.0;
    const int e = shown.count('e') ? shown.at('e') : 0, i = shown.count('i') ? shown.at('i') : 0;
    INFO("e " << e << ", i " << i << ", mean of the others " << others);
    CHECK(e >= 2.0 * others);
    CHECK(i >= 2.0 * others);
}
} // namespace

TEST_CASE("adaptive: letters the reader confuses come back at least twice as often, and the profile remembers", "[adaptive]")
{
    ReaderProfile profile;
    AdaptiveOptions o;
    o.stages = {"letters", "words"};
    o.words = {"exit", "men"};
    o.seed = 3;
    AdaptivePlanner plan(profile, o);
    const std::map<char, int> second = runSession(plan, 200);
    checkConfusedShownTwiceAsOften(second);
    CHECK(plan.stage() == "letters");   // never steady with e and i mixed up: no words yet

    // Confused pairs side by side: a "pairs" trial showed e and i together.
    bool pair = false;
    for (const ReaderAnswer& a : plan.answers()) pair = pair || (a.stage == "pairs" && (a.expected == "ei" || a.expected == "ie"));
    CHECK(pair);

    // Remembered: the next session, planned from the saved profile alone, starts with e and i
    // already weighted up.
    profile.answers = plan.answers();
    profile.sessions.push_back({1, "2026-01-01T00:00:00Z", "rows", 800.0});
    const ReaderProfile reloaded = parseReaderProfile(readerProfileToJson(profile), "mem");
    REQUIRE(reloaded.answers.size() == profile.answers.size());
    CHECK(reloaded.nextSession() == 2);
    o.session = 2;
    o.seed = 4;
    AdaptivePlanner next(reloaded, o);
    CHECK(next.weight("e") > 2.0 * next.weight("a"));
    std::map<char, int> first;
    runSession(next, 60, &first);
    checkConfusedShownTwiceAsOften(first);

    // The report shows the confusion both ways, and where the reader stands.
    const std::string report = progressReport(reloaded);
    INFO(report);
    CHECK(report.find("e -> i") != std::string::npos);
    CHECK(report.find("i -> e") != std::string::npos);
    CHECK(report.find("confusion matrix") != std::string::npos);
    CHECK(report.find("UbiBraille: 82 % after 10 min") != std::string::npos);
    CHECK(report.find("letters/min") != std::string::npos);
    // Per stage and session: session 1's letters and pairs, each with its own count.
    int letters1 = 0, pairs1 = 0, lettersRight1 = 0;
    for (const ReaderAnswer& a : reloaded.answers) {
        if (a.session != 1) continue;
        letters1 += a.stage == "letters";
        lettersRight1 += a.stage == "letters" && a.correct;
        pairs1 += a.stage == "pairs";
    }
    char row[128];
    std::snprintf(row, sizeof row, "%7d  %-13s  %7d", 1, "letters", letters1);
    CHECK(report.find(row) != std::string::npos);
    std::snprintf(row, sizeof row, "%7d  %-13s  %7d", 1, "pairs", pairs1);
    CHECK(report.find(row) != std::string::npos);
    CHECK(pairs1 > 0);
    CHECK(lettersRight1 < letters1);
}

TEST_CASE("adaptive: a reader who knows every letter moves on to words; steady history skips letters", "[adaptive]")
{
    AdaptiveOptions o;
    o.words = {"exit", "men", "push"};
    AdaptivePlanner plan(ReaderProfile {}, o);
    int trials = 0;
    while (plan.stage() == "letters" && trials < 400) {
        const PlannedTrial t = plan.next();
        plan.record(t, t.expected, true, 1.0);
        ++trials;
    }
    CHECK(plan.stage() == "words");
    CHECK(trials >= 52);   // every letter at least twice first
    const PlannedTrial w = plan.next();
    CHECK(w.stage == "words");
    ReaderProfile history;
    history.answers = plan.answers();
    AdaptivePlanner later(history, o);
    CHECK(later.stage() == "words");
}

TEST_CASE("adaptive: spaced repetition brings back what has not been seen for a while", "[adaptive]")
{
    ReaderProfile p;
    // Every letter answered right twice, 'q' long ago, the others recently.
    for (int round = 0; round < 2; ++round) {
        p.answers.push_back({1, "letters", "rows", "q", "q", true, 1.0, -1.0});
        for (char c = 'a'; c <= 'z'; ++c)
            if (c != 'q') for (int k = 0; k < 2; ++k) p.answers.push_back({1, "letters", "rows", std::string(1, c), std::string(1, c), true, 1.0, -1.0});
    }
    AdaptiveOptions o;
    o.stages = {"letters"};
    AdaptivePlanner plan(p, o);
    CHECK(plan.weight("q") > plan.weight("z"));
}

TEST_CASE("reader profile: a missing file is a new reader; bad files are refused with the key named", "[adaptive]")
{
    CHECK(loadReaderProfile("/nonexistent/reader.json").answers.empty());
    auto refuses = [](const std::string& json, const std::string& what) {
        try {
            parseReaderProfile(json, "r.json");
        } catch (const InputError& e) {
            INFO(e.what());
            CHECK(std::string(e.what()).find(what) != std::string::npos);
            return true;
        }
        return false;
    };
    CHECK(refuses("{}", "format"));
    CHECK(refuses("{\"format\": \"armadillo-reader\", \"answers\": 3}", "answers"));
    CHECK(refuses("{\"format\": \"armadillo-reader\", \"answers\": [{\"session\": 1}]}", "stage"));
    CHECK(refuses("{\"format\": \"armadillo-reader\", \"answers\": [{\"session\": 0, \"stage\": \"letters\", \"expected\": \"a\", "
                  "\"answer\": \"a\", \"correct\": true}]}",
                  "session"));
    CHECK(refuses("{\"format\": \"armadillo-reader\", \"version\": 2}", "version"));
    AdaptiveOptions nonsense;
    nonsense.stages = {"nonsense"};
    CHECK_THROWS_AS(AdaptivePlanner(ReaderProfile {}, nonsense), InputError);
    AdaptiveOptions noWords;
    noWords.stages = {"words"};
    CHECK_THROWS_AS(AdaptivePlanner(ReaderProfile {}, noWords), InputError);
}
