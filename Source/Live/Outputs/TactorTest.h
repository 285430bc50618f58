#pragma once
// `armadillo tactors test` as a procedure of the instrument (docs/TACTORS.md): each channel of a
// tactor output buzzes in turn, channel 1 first, at the motor's level through the tactile engine
// and its safety stage (as in `play`), on the wall clock at the live rig's 200 Hz control rate;
// silent channels (- in the map) are named and skipped. The front end only describes the output
// (TactorOutputConfig) and says what the walk reports.
//
// Threads: run() on the caller's thread; the output's audio thread renders what it pushes.
#include "Live/Outputs/TactorOutputConfig.h"
#include <functional>
#include <memory>
#include <string>

namespace armadillo::live {

class TactorOutput;

class TactorTest {
public:
    struct Options {
        double level = 5.0;   ///< each buzz (1..15)
        double on = 0.5;      ///< s each channel buzzes
        double gap = 0.5;     ///< s of silence between two channels
    };
    /// What the walk reaches: channel (0-based), its motor (-1 = silent in the map).
    using OnChannel = std::function<void(int channel, int motor)>;

    /// Opens the output (IoError / InputError before anything sounds).
    TactorTest(const TactorOutputConfig& config, int motors);
    ~TactorTest();
    TactorTest(const TactorTest&) = delete;
    TactorTest& operator=(const TactorTest&) = delete;

    /// The output as opened, in words ("tactors on JACK …").
    std::string describe() const;
    /// Every channel in turn; stops early when `interrupted` says so. After it, the output is
    /// stopped; IoError when it failed during the walk.
    void run(const Options& options, const OnChannel& onChannel, const std::function<bool()>& interrupted);

    /// Where motor index m sits on the right forearm (docs/TACTILE.md: index = 3·row + col).
    static std::string motorPlace(int m);

private:
    TactorOutputConfig config_;
    int motors_;
    std::unique_ptr<TactorOutput> output_;
};

} // namespace armadillo::live
