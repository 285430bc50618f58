#include "Live/Session/StatusLine.h"
#include <algorithm>
#include <cmath>

namespace armadillo::live {

namespace {
/// Rounded to the nearest whole number, ties to even (as the app's JUCE did).
std::string whole(double v) { return std::to_string(std::lrint(v)); }

std::string decibels(float peak)
{
    if (peak <= 1.0e-5f) return "silent";
    return whole(20.0 * std::log10(static_cast<double>(peak))) + " dBFS peak";
}

} // namespace

std::string StatusLine::update(const StatusSnapshot& s)
{
    if (first_ || s.source != source_) {
        first_ = false;
        source_ = s.source;
        sourceSince_ = s.now;
        lastChange_ = -1.0;
        history_.clear();
    }
    if (! history_.empty() && s.sourceSamples != history_.back().count) lastChange_ = s.now;
    if (! history_.empty() && s.sourceSamples < history_.back().count) history_.clear();   // counter restarted (reconnect)
    history_.push_back({s.now, s.sourceSamples});
    while (history_.size() > 2 && s.now - history_[1].t >= kRateWindow) history_.pop_front();

    const double since = lastChange_ >= 0.0 ? lastChange_ : sourceSince_;
    // Nothing received since the source was chosen counts as silent at once (never "0/s, alive").
    silent_ = lastChange_ < 0.0 || s.now - since >= kSilentAfter;
    rate_ = 0.0;
    if (! silent_ && history_.size() >= 2) {
        const double dt = history_.back().t - history_.front().t;
        if (dt > 0.0) rate_ = static_cast<double>(history_.back().count - history_.front().count) / dt;
    }
    if (silent_) rate_ = 0.0;

    // Audio: blocks arriving within the last half second.
    if (! audioHistory_.empty() && s.audioBlocks != audioHistory_.back().count) lastAudio_ = s.now;
    audioHistory_.clear();
    audioHistory_.push_back({s.now, s.audioBlocks});
    audioFlowing_ = lastAudio_ >= 0.0 && s.now - lastAudio_ < kSilentAfter;
    // Peaks held for a second, so a quiet moment between two notes does not flicker "silent".
    if (s.now - peakSince_ >= kRateWindow) {
        heldOutPeak_ = 0.0f;
        heldInPeak_ = 0.0f;
        peakSince_ = s.now;
    }
    heldOutPeak_ = std::max(heldOutPeak_, s.outputPeak);
    heldInPeak_ = std::max(heldInPeak_, s.inputPeak);

    std::string line = "Source: ";
    const std::string samples = silent_ ? std::string("silent, nothing received") : whole(rate_) + " samples/s";
    switch (s.source) {
    case SourceKind::Simulator:
        line += "simulated arm (" + (silent_ ? samples : whole(rate_) + " steps/s") + ")";
        break;
    case SourceKind::Device:
        if (! s.deviceConnected) line += "device, not connected (choose a port, press Connect)";
        else line += "device " + s.deviceName + " (" + (silent_ ? samples : whole(rate_) + " packets/s") + ")";
        break;
    case SourceKind::Osc:
        if (s.oscPort <= 0) line += "OSC, but OSC in is off (turn it on in the device panel)";
        else line += "OSC port " + std::to_string(s.oscPort) + " (" + (silent_ ? samples : whole(rate_) + " messages/s") + ")";
        break;
    case SourceKind::HostAutomation:
        line += "host automation (the elevation, azimuth and roll parameters)";
        silent_ = false;
        break;
    }
    updateLeftArm(s);
    if (s.leftArmPort > 0)
        line += "  |  Left arm: OSC port " + std::to_string(s.leftArmPort) + " (" + (leftSilent_ ? "silent, nothing received" : "live") + ")";
    line += "  |  Audio: ";
    if (! audioFlowing_) line += "not running (no sound card or output device: the arm and motors still run)";
    else line += "running, output " + decibels(heldOutPeak_);
    if (s.listens) {
        line += "  |  Input: ";
        if (s.inputMuted == 1) line += "MUTED (this scene listens: unmute it in Help or Options)";
        else if (! audioFlowing_) line += "no audio";
        else line += decibels(heldInPeak_);
    }
    line += "  |  Motors: ";
    if (! s.deviceConnected) line += "off (no device connected; the levels are only shown)";
    else if (s.motorsActive > 0) line += "on (" + std::to_string(s.motorsActive) + " of " + std::to_string(s.motorCount) + " driven)";
    else line += "off";
    return line;
}

void StatusLine::updateLeftArm(const StatusSnapshot& s)
{
    if (s.leftArmPort != leftPort_ || s.leftArmSamples < leftCount_) leftLastChange_ = -1.0;   // turned on, moved, or restarted
    else if (s.leftArmSamples != leftCount_) leftLastChange_ = s.now;
    leftPort_ = s.leftArmPort;
    leftCount_ = s.leftArmSamples;
    leftSilent_ = leftPort_ <= 0 || leftLastChange_ < 0.0 || s.now - leftLastChange_ >= kSilentAfter;
}

} // namespace armadillo::live
