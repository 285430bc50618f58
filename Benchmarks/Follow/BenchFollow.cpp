// Cost of the score follower per audio block (it runs on the audio thread): a synthesised
// bassoon-like performance of the Rite's solo with noise at 20 dB SNR, fed in blocks of 64,
// 256 and 1024 samples at 48 kHz, through ScoreFollower::process alone and through the score
// scene's Engine::processInput; and the follower's worst case, a score of six-note chords (three
// events of six pitches: 18 correlations a hop), on the same audio. Prints µs per block and the
// share of the block's duration; never passes or fails on time.
#include "Engine/Engine.h"
#include "Follow/Performance.h"
#include "Tactile/ScoreFollower.h"
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <vector>

using namespace armadillo;
using namespace armadillo::engine;
using namespace armadillo::tactile;

namespace {
double threadSeconds()
{
    timespec ts {};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}
} // namespace

int main()
{
    const std::string resources = ARMADILLO_SOURCE_DIR "/Resources";
    const Score score = loadScore(resources + "/Scores/rite-of-spring.score");
    std::vector<int> followed;
    for (std::size_t i = 0; i < score.notes.size(); ++i)
        if (score.notes[i].part >= 0 && score.parts[static_cast<std::size_t>(score.notes[i].part)].followNotes) followed.push_back(static_cast<int>(i));
    test::PerformanceStyle style;
    style.snrDb = 20.0;
    const test::Performance perf = test::perform(score, followed, style);
    const std::size_t frames = perf.audio.frames();
    const double fs = perf.audio.sampleRate;
    std::printf("follower: %.1f s of a 20 dB SNR bassoon performance at %.0f Hz (thread CPU time, best of 5, median beside it)\n",
                static_cast<double>(frames) / fs, fs);
    for (const int block : {64, 256, 1024}) {
        for (const bool throughEngine : {false, true}) {
            std::vector<double> runs;
            for (int rep = 0; rep < 5; ++rep) {
                ScoreFollower f;
                f.prepare(score, fs);
                EngineConfig config;
                config.scene = "score";
                config.sceneConfig.score = "rite-of-spring";
                config.sceneConfig.resourceDir = resources;
                Engine engine(config);
                std::size_t blocks = 0;
                const double t0 = threadSeconds();
                for (std::size_t at = 0; at + static_cast<std::size_t>(block) <= frames; at += static_cast<std::size_t>(block)) {
                    const float* in[2] = {perf.audio.channels[0].data() + at, perf.audio.channels[1].data() + at};
                    if (throughEngine) engine.processInput(in, 2, block);
                    else f.process(in, 2, block);
                    ++blocks;
                }
                runs.push_back((threadSeconds() - t0) / static_cast<double>(blocks));
            }
            std::sort(runs.begin(), runs.end());
            const double blockSeconds = block / fs;
            std::printf("  block %4d (%5.2f ms) %-28s %7.2f µs per block (median %7.2f), %5.2f %% of the block's time\n", block,
                        1e3 * blockSeconds, throughEngine ? "Engine::processInput (scene)" : "ScoreFollower::process", 1e6 * runs.front(),
                        1e6 * runs[runs.size() / 2], 100.0 * runs.front() / blockSeconds);
        }
    }
    // The worst case: every event a chord of kEventPitches distinct pitches.
    std::string chords = "armadillo-score 2\nunits seconds\npart all follow=notes\n";
    static const char* const kPitches[] = {"C3", "E3", "G3", "C4", "E4", "G4", "D3", "Fs3", "A3", "D4", "Fs4", "A4"};
    for (int e = 0; e < 30; ++e)
        for (int k = 0; k < kEventPitches; ++k)
            chords += std::to_string(e) + " note m=" + std::to_string(k + 1) + " dur=1 level=3 pitch=" + kPitches[(e % 2) * 6 + k] + " part=all\n";
    const Score chordScore = parseScore(chords, "chords");
    std::vector<double> runs;
    for (int rep = 0; rep < 5; ++rep) {
        ScoreFollower f;
        f.prepare(chordScore, fs);
        std::size_t blocks = 0;
        const double t0 = threadSeconds();
        for (std::size_t at = 0; at + 64 <= frames; at += 64) {
            const float* in[2] = {perf.audio.channels[0].data() + at, perf.audio.channels[1].data() + at};
            f.process(in, 2, 64);
            ++blocks;
        }
        runs.push_back((threadSeconds() - t0) / static_cast<double>(blocks));
    }
    std::sort(runs.begin(), runs.end());
    std::printf("  block   64 (%5.2f ms) %-28s %7.2f µs per block (median %7.2f), %5.2f %% of the block's time\n", 1e3 * 64 / fs,
                "six-note chords (worst case)", 1e6 * runs.front(), 1e6 * runs[runs.size() / 2], 100.0 * runs.front() / (64 / fs));
    return 0;
}
