#pragma once
// The app's status line: which source drives the arm and how many samples per second it really
// delivers, whether audio is flowing (and the input, when the scene listens), and whether the
// motors are driven. It only reports what the counters show: a source whose counter stopped is
// "silent" after kSilentAfter seconds (well within a second of the last packet), never "alive".
//
// Plain logic over counters sampled by a front end's timer (the app editor's, on the message
// thread), so a test can drive it with made-up times and counts. JUCE-free: the rig's status in
// words; the app only shows the line.
#include "Live/Step/ControlLoop.h"
#include <cstdint>
#include <deque>
#include <string>

namespace armadillo::live {

struct StatusSnapshot {
    double now = 0.0;                  ///< s, any monotonic clock
    SourceKind source = SourceKind::Simulator;
    std::uint64_t sourceSamples = 0;   ///< counter of the chosen source (ArmadilloProcessor::sourceSamples)
    bool deviceConnected = false;      ///< a device link is open
    std::string deviceName;            ///< the port (for the device source)
    int oscPort = 0;                   ///< the OSC input's port (0: OSC in is off)
    std::uint64_t audioBlocks = 0;     ///< processBlock calls so far
    float outputPeak = 0.0f;           ///< largest output magnitude since the previous snapshot
    bool listens = false;              ///< the scene listens to the audio input
    float inputPeak = 0.0f;            ///< largest input magnitude since the previous snapshot
    int inputMuted = -1;               ///< 1 muted (standalone's mute), 0 not, -1 unknown (plugin)
    int motorsActive = 0;              ///< motors above level 0 in the newest frame
    int motorCount = 9;
    int leftArmPort = 0;               ///< the left arm's OSC port (0: no left arm; docs/STAGE.md "Two arms")
    std::uint64_t leftArmSamples = 0;  ///< its orientation/IMU messages so far
};

class StatusLine {
public:
    /// Seconds without a new sample after which a source is shown as silent.
    static constexpr double kSilentAfter = 0.5;
    /// The window the rate is measured over.
    static constexpr double kRateWindow = 1.0;

    /// Takes a snapshot and returns the line to show.
    std::string update(const StatusSnapshot& s);

    /// After update(): samples per second of the source over the last second (0 when silent).
    double sourceRate() const noexcept { return rate_; }
    bool sourceSilent() const noexcept { return silent_; }
    bool audioFlowing() const noexcept { return audioFlowing_; }
    /// After update(): whether the left arm's sender is silent (true while there is no left arm).
    bool leftArmSilent() const noexcept { return leftSilent_; }

private:
    struct Sample { double t; std::uint64_t count; };
    std::deque<Sample> history_, audioHistory_;
    SourceKind source_ = SourceKind::HostAutomation;
    bool first_ = true;
    double sourceSince_ = 0.0;         ///< when the current source was chosen
    double lastChange_ = -1.0;         ///< when its counter last moved (< 0: never)
    double lastAudio_ = -1.0;
    float heldOutPeak_ = 0.0f, heldInPeak_ = 0.0f;
    double peakSince_ = 0.0;
    double rate_ = 0.0;
    bool silent_ = true, audioFlowing_ = false;
    // The left arm's sender: live while its counter moved within kSilentAfter.
    void updateLeftArm(const StatusSnapshot& s);
    std::uint64_t leftCount_ = 0;
    double leftLastChange_ = -1.0;
    int leftPort_ = 0;
    bool leftSilent_ = true;
};

} // namespace armadillo::live
