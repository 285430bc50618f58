// `armadillo braille`: the cells of a text and the row sensations the display shows; Braille ASCII
// in and out; the §4.4.1 training plan, and offline replay of a training session into its log.
#include "Braille/Cells.h"
#include "Braille/Reading.h"
#include "Braille/Sensations.h"
#include "Braille/Training.h"
#include "Cli/CommandLine.h"
#include "Cli/GuidedTraining.h"
#include "Cli/Commands.h"
#include "Core/AtomicFile.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include <charconv>
#include <cmath>
#include <iostream>
#include <sstream>

namespace armadillo::cli {

namespace {
using namespace armadillo::braille;

std::string pad(std::string s, std::size_t width)
{
    // Pads by code points so braille and accented letters line up.
    std::size_t cps = 0;
    for (unsigned char c : s) cps += (c & 0xC0) != 0x80;
    if (cps < width) s.append(width - cps, ' ');
    return s;
}

std::string sensations(Dots cell, DisplayMethod method)
{
    std::string s;
    for (MotorSet m : cellSteps(cell, method)) s += (s.empty() ? "" : " | ") + motorList(m);
    return s;
}

void printDocument(const BrailleDocument& doc, DisplayMethod method)
{
    std::cout << "# table " << doc.table << ", method " << displayMethodName(method)
              << "; motors k = 3*row + col + 1 (row 0 = wrist; col 0 = left, 1 = underside, 2 = right, right arm)\n"
              << "# columns: print, cell, dots, motor sets shown one after another ('-' = pause)\n";
    for (std::size_t m = 0; m < doc.messages.size(); ++m) {
        std::cout << "message " << m + 1 << "\n";
        for (const BrailleSymbol& s : doc.messages[m].symbols) {
            if (s.isSpace()) {
                std::cout << "  " << pad("(space)", 13) << "word gap: the underside line, motors 2,5,8\n";
                continue;
            }
            for (std::size_t c = 0; c < s.cells.size(); ++c) {
                const Dots d = s.cells[c];
                std::cout << "  " << pad(c == 0 ? (s.print.empty() ? "(sign)" : s.print) : "", 10) << unicodeCell(d) << "  "
                          << pad("dots " + dotNumbers(d), 12) << sensations(d, method) << "\n";
            }
        }
    }
    std::cout << "# " << doc.cellCount() << " cells in " << doc.messages.size() << " message(s)\n";
}

std::string toBrf(const BrailleDocument& doc)
{
    std::string out;
    for (std::size_t m = 0; m < doc.messages.size(); ++m) {
        if (m > 0) out += "\r\n";
        for (const auto& s : doc.messages[m].symbols)
            for (Dots d : s.cells) out += dotsToBrf(d);
        out += "\r\n";
    }
    return out;
}

struct TimedAnswer {
    double t = 0.0;
    std::string answer;
};

/// `t,answer` text: a header line, then one answer a line (the answer is the rest of the line).
std::vector<TimedAnswer> readAnswers(const std::string& path)
{
    std::istringstream in(core::readWholeFile(path));
    std::vector<TimedAnswer> out;
    long line = 0;
    bool header = false;
    double last = -INFINITY;
    for (std::string l; std::getline(in, l);) {
        ++line;
        if (!l.empty() && l.back() == '\r') l.pop_back();
        if (l.empty() || l.front() == '#') continue;
        const auto comma = l.find(',');
        if (!header) {
            if (l.substr(0, comma) != "t" || comma == std::string::npos || l.substr(comma + 1) != "answer")
                throw core::InputError(path, line, "", "the header must be 't,answer'");
            header = true;
            continue;
        }
        if (comma == std::string::npos) throw core::InputError(path, line, "answer", "missing ',answer'");
        TimedAnswer a;
        const auto [end, ec] = std::from_chars(l.data(), l.data() + comma, a.t);
        if (ec != std::errc() || end != l.data() + comma || !std::isfinite(a.t)) throw core::InputError(path, line, "t", "not a number");
        if (a.t < last) throw core::InputError(path, line, "t", "time goes backwards");
        last = a.t;
        a.answer = l.substr(comma + 1);
        out.push_back(a);
    }
    if (!header) throw core::InputError(path, 0, "", "empty file (expected the header 't,answer')");
    return out;
}

TrainingOptions trainingOptions(const CommandLine& cl)
{
    TrainingOptions o;
    o.seed = static_cast<std::uint64_t>(cl.integer("--seed", 1, 0, 2147483647L));
    o.trialsPerStage = static_cast<int>(cl.integer("--trials", 10, 1, 1000));
    if (cl.has("--stages")) {
        o.stages.clear();
        std::istringstream names(cl.value("--stages"));
        for (std::string n; std::getline(names, n, ',');) {
            TrainingStage s {};
            if (!parseTrainingStage(n, s))
                throw UsageError("unknown training stage '" + n + "' (sides, hold, one-dot, gaps, alphabet, letters, words, signs,\n"
                                 "contractions)");
            o.stages.push_back(s);
        }
    }
    bool words = false;
    for (auto s : o.stages) words = words || s == TrainingStage::Words || s == TrainingStage::Signs;
    if (cl.has("--method") && !parseDisplayMethod(cl.value("--method"), o.method))
        throw UsageError("--method is one of rows, whole, columns, dots");
    if (words) o.signWords = cl.has("--words") ? readWordList(cl.value("--words")) : defaultSignWords();
    return o;
}

int printPlan(const CommandLine& cl)
{
    const TrainingSession session(trainingOptions(cl));
    // CSV: the prompts hold commas, so they are quoted.
    std::cout << "trial,stage,prompt,expected\n";
    int i = 0;
    for (const auto& t : session.trials())
        std::cout << ++i << "," << trainingStageName(t.stage) << ",\"" << t.prompt << "\"," << t.expected << "\n";
    return core::kExitOk;
}

/// Offline replay of a training session: a motion file drives the roll reader, an answers file
/// gives the reader's answers, and the log is written as the live session would write it.
int replayTraining(const CommandLine& cl)
{
    if (!cl.has("--motion") || !cl.has("--answers") || !cl.has("--log"))
        throw UsageError("--train needs --motion FILE, --answers FILE and --log FILE (or use --plan)");
    checkOutputPath("--log", cl.value("--log"));
    TrainingSession session(trainingOptions(cl));
    const auto motion = motionAsQuaternions(core::CsvTable::read(cl.value("--motion")));
    const auto answers = readAnswers(cl.value("--answers"));
    std::size_t next = 0;
    for (const auto& row : motion) {
        while (next < answers.size() && answers[next].t <= row.t) {
            session.answer(answers[next].t, answers[next].answer);
            ++next;
        }
        const Eigen::Quaterniond q = row.q.normalized();
        session.update(row.t, q * Eigen::Vector3d::UnitX(), q * Eigen::Vector3d::UnitY(), true);
    }
    for (; next < answers.size(); ++next) session.answer(answers[next].t, answers[next].answer);
    session.saveLog(cl.value("--log"));
    std::cout << "{\"trials\":" << session.trials().size() << ",\"answered\":" << session.answeredCount()
              << ",\"correct\":" << session.correctCount() << ",\"finished\":" << (session.finished() ? "true" : "false") << "}\n";
    return core::kExitOk;
}
} // namespace

int runBraille(const Arguments& args)
{
    return guarded("braille", [&]() -> int {
        std::vector<OptionSpec> options {
                        {"--text", "TEXT", "the text to show (UTF-8; each line is one message)"},
                        {"--brf", "FILE", "read a Braille ASCII (.brf) file instead of --text"},
                        {"--grade", "1|2", "1 = uncontracted (default), 2 = contracted"},
                        {"--table", "TABLE", "a liblouis table list (default en-ueb-g1.ctb / en-ueb-g2.ctb)"},
                        {"--capitals", "", "keep capital signs (default: letters as the thesis shows them)"},
                        {"--method", "M", "rows (default, §4.2.5), whole, columns, dots (§4.2.1-4.2.2); also how training shows cells"},
                        {"--out-brf", "FILE", "also write the cells as Braille ASCII (atomic)"},
                        {"--plan", "", "print the training trials of §4.4.1 (with --seed, --trials, --stages)"},
                        {"--train", "", "replay a training session: --motion, --answers, --log"},
                        {"--motion", "FILE", "pose or quaternion file of the session (--train)"},
                        {"--answers", "FILE", "the reader's answers, 't,answer' lines (--train)"},
                        {"--log", "FILE", "where the training log goes (--train; CSV, atomic)"},
                        {"--stages", "LIST", "comma list of sides,hold,one-dot,gaps,alphabet,letters,words, and (not in the\n"
                                            "default list) signs (the §5.3 shorthand), contractions (Grade 2)"},
                        {"--trials", "N", "trials per stage (default 10); with --adaptive: trials in all (default 30)"},
                        {"--seed", "N", "random choices of the training (default 1)"},
                        {"--words", "FILE", "sign word list (default: the shipped Braille/signwords.txt)"}};
        // The adaptive training on the device and the progress report (issue 26).
        const auto guided = guidedTrainingOptionSpecs();
        options.insert(options.end(), guided.begin(), guided.end());
        CommandLine cl("braille", "(--text \"...\" | --brf FILE) [options]  |  --plan | --train ... | --train --adaptive ... | --report R",
                       "Arm Braille (thesis §4.2-4.4). Prints each character's braille cells and the row\n"
                       "sensations (motor sets) the forearm display shows for them, one after another.\n"
                       "Grade 1 (uncontracted, as in the thesis) by default, Grade 2 with --grade 2, any\n"
                       "liblouis table with --table. Also writes Braille ASCII (--out-brf), prints the\n"
                       "training plan of §4.4.1 (--plan), replays a training session offline (--train),\n"
                       "runs the adaptive training on the device for a reader alone (--train --adaptive:\n"
                       "spoken, on a braille display, answered by chords; docs/ACCESSIBILITY.md) and\n"
                       "reports a reader's progress (--report).",
                       options);

        if (!cl.parse(args)) return core::kExitOk;
        if (cl.has("--report")) return printProgressReport(cl);
        if (cl.has("--adaptive")) {
            if (!cl.has("--train")) throw UsageError("--adaptive is a kind of training: use --train --adaptive");
            return runGuidedTraining(cl);
        }
        for (const auto& o : guided)
            if (o.name != "--words" && cl.has(o.name)) throw UsageError(o.name + " belongs to --train --adaptive");
        if (cl.has("--plan")) return printPlan(cl);
        if (cl.has("--train")) return replayTraining(cl);

        if (cl.has("--text") == cl.has("--brf")) throw UsageError("give exactly one of --text and --brf");
        if (cl.has("--out-brf")) checkOutputPath("--out-brf", cl.value("--out-brf"));
        DisplayMethod method = DisplayMethod::Rows;
        if (cl.has("--method") && !parseDisplayMethod(cl.value("--method"), method))
            throw UsageError("--method is one of rows, whole, columns, dots");
        BrailleDocument doc;
        if (cl.has("--brf")) {
            if (cl.has("--grade") || cl.has("--table")) throw UsageError("--grade and --table apply to --text, not to a .brf file");
            doc = readBrfFile(cl.value("--brf"));
        } else {
            TranslationOptions o;
            o.grade = static_cast<int>(cl.integer("--grade", 1, 1, 2));
            o.table = cl.value("--table");
            o.capitals = cl.has("--capitals");
            doc = translateText(cl.value("--text"), o);
            if (doc.messages.empty()) throw core::InputError("text", 0, "", "nothing to show: the text is empty");
        }
        printDocument(doc, method);
        if (cl.has("--out-brf")) core::writeFileAtomically(cl.value("--out-brf"), toBrf(doc));
        return core::kExitOk;
    });
}

} // namespace armadillo::cli
