#pragma once
// Standard MIDI File writing for `armadillo render --midi-out` (the MIDI Association's "Standard
// MIDI Files 1.0" specification, RP-001: header chunk MThd, track chunks MTrk, variable-length
// delta times, running status not used). Format 1: track 0 holds the tempo, track 1 the events.
// Times are exact to the control updates: 960 ticks per quarter note at 500000 µs per quarter
// (120 bpm) makes one tick 520.8 µs, so an event lands within 0.27 ms of its time. Not real-time.
#include "Mapping/Mapper.h"
#include <cstdint>
#include <string>
#include <vector>

namespace armadillo::mapping {

inline constexpr int kSmfTicksPerQuarter = 960;
inline constexpr int kSmfMicrosPerQuarter = 500000;

/// Seconds → ticks at the file's fixed tempo (rounded to the nearest tick).
std::uint32_t smfTicks(double seconds) noexcept;

/// Collects MIDI events (MappingOutput::midi, times in s from the file's start) in time order.
class MidiFileWriter {
public:
    /// t0: the time that becomes tick 0 (the first motion row).
    explicit MidiFileWriter(double t0 = 0.0) : t0_(t0) {}
    void add(const MidiEvent& e);
    void addAll(const MappingOutput& out);
    std::size_t size() const noexcept { return events_.size(); }
    /// The whole file (format 1, two tracks). Events keep their order; equal times keep arrival order.
    std::vector<std::uint8_t> bytes() const;
    /// Written atomically (Core/AtomicFile.h); IoError on failure.
    void write(const std::string& path) const;

private:
    double t0_;
    std::vector<MidiEvent> events_;
};

} // namespace armadillo::mapping
