#include "Access/Report.h"
#include <algorithm>
#include <cstdio>
#include <map>
#include <set>

namespace armadillo::access {

namespace {
std::string percent(int right, int n)
{
    if (n == 0) return "   -";
    char b[16];
    std::snprintf(b, sizeof b, "%3.0f %%", 100.0 * right / n);
    return b;
}

std::string fixed(double x, int decimals)
{
    char b[32];
    std::snprintf(b, sizeof b, "%.*f", decimals, x);
    return b;
}
} // namespace

std::string progressReport(const ReaderProfile& p)
{
    std::string out = "# reader " + (p.name.empty() ? std::string("(no name)") : p.name) + ": " + std::to_string(p.sessions.size()) +
                      " session(s), " + std::to_string(p.answers.size()) + " answers\n";
    // Accuracy per stage.
    std::map<std::string, std::pair<int, int>> byStage, byMethod;
    for (const ReaderAnswer& a : p.answers) {
        auto& s = byStage[a.stage];
        ++s.second;
        s.first += a.correct;
        if (a.stage == "letters") {
            auto& m = byMethod[a.method.empty() ? "rows" : a.method];
            ++m.second;
            m.first += a.correct;
        }
    }
    out += "\nstage          answers  right\n";
    for (const auto& [stage, rn] : byStage) {
        std::string name = stage;
        name.resize(15, ' ');
        out += name + std::to_string(rn.second);
        out.append(std::max<std::size_t>(1, 9 - std::to_string(rn.second).size()), ' ');
        out += percent(rn.first, rn.second) + "\n";
    }
    // Per session: accuracy, letters per minute.
    out += "\nsession  minutes  answers  right  letters/min\n";
    std::set<int> numbers;
    for (const auto& a : p.answers) numbers.insert(a.session);
    for (int n : numbers) {
        int total = 0, right = 0, letters = 0;
        double last = 0.0;
        for (const auto& a : p.answers)
            if (a.session == n) {
                ++total;
                right += a.correct;
                if (a.correct && a.stage != "pairs") letters += static_cast<int>(a.expected.size());
                last = std::max(last, a.t);
            }
        double seconds = last;
        for (const auto& s : p.sessions)
            if (s.session == n && s.seconds > 0.0) seconds = s.seconds;
        char line[128];
        std::snprintf(line, sizeof line, "%7d  %7.1f  %7d  %s  %s\n", n, seconds / 60.0, total, percent(right, total).c_str(),
                      seconds > 0.0 ? fixed(letters * 60.0 / seconds, 1).c_str() : "-");
        out += line;
    }
    // Accuracy per stage within each session.
    out += "\nsession  stage          answers  right\n";
    {
        std::map<std::pair<int, std::string>, std::pair<int, int>> cells;
        for (const auto& a : p.answers) {
            auto& c = cells[{a.session, a.stage}];
            ++c.second;
            c.first += a.correct;
        }
        for (const auto& [key, rn] : cells) {
            char line[128];
            std::snprintf(line, sizeof line, "%7d  %-13s  %7d  %s\n", key.first, key.second.c_str(), rn.second, percent(rn.first, rn.second).c_str());
            out += line;
        }
    }
    // Confusion matrix of the letters: rows = shown, columns = answered; only letters involved.
    std::map<std::pair<char, char>, int> confusion;
    std::set<char> involved;
    for (const auto& a : p.answers)
        if (a.stage == "letters" && a.expected.size() == 1 && a.answer.size() == 1 && a.answer != a.expected &&
            a.answer[0] >= 'a' && a.answer[0] <= 'z') {
            ++confusion[{a.expected[0], a.answer[0]}];
            involved.insert(a.expected[0]);
            involved.insert(a.answer[0]);
        }
    out += "\nconfusions (letter shown -> letter answered):";
    if (confusion.empty()) out += " none\n";
    else {
        out += "\n";
        std::vector<std::pair<int, std::pair<char, char>>> sorted;
        for (const auto& [k, v] : confusion) sorted.push_back({v, k});
        std::sort(sorted.rbegin(), sorted.rend());
        for (const auto& [count, k] : sorted) out += std::string("  ") + k.first + " -> " + k.second + ": " + std::to_string(count) + "\n";
        out += "confusion matrix (rows shown, columns answered):\n     ";
        for (char c : involved) out += std::string("  ") + c;
        out += "\n";
        for (char r : involved) {
            out += std::string("  ") + r + "  ";
            for (char c : involved) {
                const auto it = confusion.find({r, c});
                const std::string cell = r == c ? "." : it == confusion.end() ? "0" : std::to_string(it->second);
                out += std::string(3 - std::min<std::size_t>(3, cell.size()), ' ') + cell;
            }
            out += "\n";
        }
    }
    // Letter accuracy per display method.
    out += "\nletters by method:";
    if (byMethod.empty()) out += " none yet\n";
    else {
        out += "\n";
        for (const auto& [m, rn] : byMethod) out += "  " + m + ": " + percent(rn.first, rn.second) + " of " + std::to_string(rn.second) + "\n";
    }
    // Against the published figures: letter accuracy of the last 20 letter answers given by
    // 10 and by 25 minutes of training (the sessions' time added up).
    auto accuracyBy = [&](double minutes, int& n) {
        double before = 0.0;
        std::vector<bool> window;
        std::map<int, double> sessionSeconds;
        for (const auto& s : p.sessions) sessionSeconds[s.session] = s.seconds;
        int current = -1;
        double offset = 0.0;
        for (const auto& a : p.answers) {
            if (a.session != current) {
                if (current >= 0) offset += sessionSeconds.count(current) ? sessionSeconds[current] : before;
                current = a.session;
            }
            before = std::max(0.0, a.t);
            if (offset + before > minutes * 60.0) break;
            if (a.stage != "letters") continue;
            window.push_back(a.correct);
            if (window.size() > 20) window.erase(window.begin());
        }
        n = static_cast<int>(window.size());
        int right = 0;
        for (bool b : window) right += b;
        return percent(right, n);
    };
    int n10 = 0, n25 = 0;
    const std::string at10 = accuracyBy(10.0, n10), at25 = accuracyBy(25.0, n25);
    out += "\nagainst the published figures (letters; last 20 answers by that time of training):\n";
    out += "  by 10 min: " + at10 + " (" + std::to_string(n10) + " answers)   UbiBraille: 82 % after 10 min\n";
    out += "  by 25 min: " + at25 + " (" + std::to_string(n25) + " answers)   thesis (Sachs 2005): above 95 % after about 25 min\n";
    out += "  forearm study: 93 % with dots shown one at a time, 26 % with dots shown together (compare 'letters by method':\n"
           "  dots = one at a time, whole = together)\n";
    return out;
}

} // namespace armadillo::access
