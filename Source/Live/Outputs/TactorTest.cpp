#include "Live/Outputs/TactorTest.h"
#include "Core/Errors.h"
#include "Live/Outputs/TactorOutput.h"
#include "Tactile/TactileEngine.h"
#include <chrono>
#include <thread>

namespace armadillo::live {

TactorTest::TactorTest(const TactorOutputConfig& config, int motors)
    : config_(config), motors_(motors), output_(std::make_unique<TactorOutput>(config))
{
}

TactorTest::~TactorTest()
{
    if (output_) output_->stop();
}

std::string TactorTest::describe() const
{
    return output_->describe();
}

std::string TactorTest::motorPlace(int m)
{
    if (m >= 9) return "back " + std::to_string(m - 8);
    static const char* rows[] = {"wrist", "middle", "elbow"};
    static const char* cols[] = {"left", "underside", "right"};
    return std::string(rows[m / 3]) + ", " + cols[m % 3];
}

void TactorTest::run(const Options& options, const OnChannel& onChannel, const std::function<bool()>& interrupted)
{
    tactile::TactileConfig tc;
    tc.motorCount = motors_;
    tactile::TactileEngine engine;
    engine.prepare(tc);
    output_->start();
    constexpr double kStep = 0.005;   // the control rate of a live rig (200 Hz)
    double t = 0.0;
    const auto start = std::chrono::steady_clock::now();
    // Runs the engine for `seconds`, pushing each step to the output on the wall clock.
    const auto runFor = [&](double seconds) {
        const double end = t + seconds;
        while (t < end - 1e-9 && !interrupted()) {
            output_->push(t, engine.tick(t == 0.0 ? 0.0 : kStep));
            t += kStep;
            std::this_thread::sleep_until(start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(t)));
        }
    };
    runFor(0.1);
    for (int c = 0; c < output_->channels() && !interrupted(); ++c) {
        const int m = config_.map.motor[static_cast<std::size_t>(c)];
        onChannel(c, m);
        if (m < 0) continue;
        engine.setSoftLevel(m, static_cast<float>(options.level));
        runFor(options.on);
        engine.clearLevels();
        runFor(options.gap);
    }
    engine.allOff();
    output_->push(t, engine.tick(kStep));
    runFor(0.05);
    output_->stop();
    if (output_->failed()) throw core::IoError("the tactor output stopped during the test (its JACK server or sound card went away)");
}

} // namespace armadillo::live
