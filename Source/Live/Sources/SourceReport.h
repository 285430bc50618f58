#pragma once
// What a live session's sources tell the person who runs it, in words: the OSC input's kind at
// the start, its serial errors, the rates of its streams once they have run a while, the dialect
// it detected, and — when a port or OSC source delivers nothing — what it did hear. The rig owns
// the sources, so it describes them; a front end (`play`, the app's status) only shows the lines.
// Message side only (it reads the sources' counters, which are atomics).
#include <cstdint>
#include <string>
#include <vector>

namespace armadillo::live {

class LiveSession;

class SourceReport {
public:
    explicit SourceReport(live::LiveSession& session) : session_(session) {}

    /// Lines to say once before the session starts (how the OSC input listens).
    std::vector<std::string> startup() const;
    /// New lines since the last call, `elapsed` s into the session: a serial OSC port's error (once
    /// per error), the OSC streams' rates after 3 s (and a warning when too slow for fusion), the
    /// dialect and sender of each arm's OSC input once detected.
    std::vector<std::string> poll(double elapsed);
    /// A port or OSC source (`left`: the left arm's) that delivered no sensor data within
    /// `seconds`: what was heard instead, and what to check.
    std::string noData(double seconds, bool left = false) const;
    /// The left arm's usable sensor packets so far (its device's, or its OSC sender's samples).
    std::uint64_t leftPackets() const;
    /// Two arms: the session summary's left-arm members (`,"left_packets":N` and, for an OSC
    /// sender, `,"left_osc":{…}`: its input's counters); "" with one arm.
    std::string leftSummaryJson() const;

private:
    live::LiveSession& session_;
    bool shownRates_ = false, shownFormat_ = false, shownLeftFormat_ = false;
    std::string shownSerialError_;
    std::vector<std::string> shownOthers_;   // other OSC senders named so far (each once)
};

} // namespace armadillo::live
