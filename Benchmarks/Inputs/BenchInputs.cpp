// Input handling grows linearly with input size (issue 24): each input that took minutes in
// quadratic code — a score of pattern/stop pairs (the parser's finishing step and the player's
// span table), a score of cues (the duplicate check), a calibration JSON of many keys (the
// duplicate-key check), a motion CSV — is timed at N, 4N, 16N and 64N elements, and the time per element
// at each size against the one before (1.0 = linear, 4.0 = quadratic) are printed.
// Thread CPU time, best of 3; prints numbers, never passes or fails.
#include "Core/Csv.h"
#include "Link/Calibration.h"
#include "Core/Json.h"
#include "Tactile/Score.h"
#include "Tactile/ScorePlayer.h"
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <functional>
#include <string>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::tactile;

namespace {

double threadSeconds()
{
    timespec ts {};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double bestOf3(const std::function<void()>& work)
{
    double best = 1e300;
    for (int k = 0; k < 3; ++k) {
        const double t0 = threadSeconds();
        work();
        best = std::min(best, threadSeconds() - t0);
    }
    return best;
}

std::string pairsScore(int n)
{
    std::string s = "armadillo-score 2\nunits seconds\n";
    char lines[120];
    for (int i = 0; i < n; ++i) {
        std::snprintf(lines, sizeof lines, "%.3f pattern pulse m=%d voice=%d dur=hold\n%.4f stop voice=%d\n", i * 0.001, 1 + i % 9, i % 8,
                      i * 0.001 + 0.0005, i % 8);
        s += lines;
    }
    return s;
}

std::string cuesScore(int n)
{
    std::string s = "armadillo-score 2\nunits seconds\n";
    for (int i = 0; i < n; ++i) s += std::to_string(0.05 * i) + " cue c" + std::to_string(i) + "\n";
    return s;
}

std::string keysJson(int n)
{
    std::string json = link::calibrationToJson(link::defaultCalibration());
    json.erase(json.rfind('}'));
    for (int i = 0; i < n; ++i) json += ",\n\"extra" + std::to_string(i) + "\": " + std::to_string(i);
    return json + "\n}\n";
}

std::string motionCsv(int n)
{
    std::string s = "t,qw,qx,qy,qz\n";
    char row[96];
    for (int i = 0; i < n; ++i) {
        std::snprintf(row, sizeof row, "%.3f,0.7071,0,0.7071,%.4f\n", i * 0.005, 1e-4 * (i % 100));
        s += row;
    }
    return s;
}

/// Times `run` on inputs of n, 4n, 16n and 64n elements and prints the time per element and the
/// ratio of each to the one before (4.0 would be quadratic).
void measure(const char* name, int n, const std::function<std::string(int)>& make, const std::function<void(const std::string&)>& run)
{
    std::printf("%-36s", name);
    double previous = 0.0;
    for (int size : {n, 4 * n, 16 * n, 64 * n}) {
        const std::string input = make(size);
        const double perElement = bestOf3([&] { run(input); }) / size;
        std::printf("  %7d: %6.3f us", size, 1e6 * perElement);
        if (previous > 0.0) std::printf(" (x%.2f)", perElement / previous);
        previous = perElement;
    }
    std::printf("\n");
}

} // namespace

int main()
{
    std::printf("input handling: time per element at N, 4N, 16N and 64N elements; (xR) = per-element time against the size before\n"
                "(1.0 = linear, 4.0 = quadratic); thread CPU time, best of 3\n");
    measure("score: pattern/stop pairs (parse)", 25000, pairsScore, [](const std::string& text) { (void) parseScore(text, "pairs.score"); });
    measure("score: pairs, parse + player spans", 25000, pairsScore, [](const std::string& text) {
        ScorePlayer player;
        player.setScore(parseScore(text, "pairs.score"));
    });
    measure("score: cues (parse)", 25000, cuesScore, [](const std::string& text) { (void) parseScore(text, "cues.score"); });
    measure("calibration JSON: extra keys", 25000, keysJson, [](const std::string& text) { (void) link::parseCalibration(text, "keys.json"); });
    measure("motion CSV: quaternion rows", 25000, motionCsv,
            [](const std::string& text) { (void) readQuaternions(CsvTable::parse(text, "motion.csv")); });
    return 0;
}
