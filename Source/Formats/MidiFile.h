#pragma once
// A Standard MIDI File reader (format 0 and 1), written from the MIDI Manufacturers Association's
// "Standard MIDI Files 1.0" (RP-001): chunks MThd/MTrk (other chunk types skipped), variable-length
// quantities, running status, meta events (tempo 0x51, track name 0x03, marker 0x06, cue point
// 0x07, end of track 0x2F), SysEx (F0/F7) skipped. Division in ticks per quarter note, or SMPTE
// (frames per second × ticks per frame: time in seconds, no tempo map). Format 2 (independent
// sequences) is refused. No JUCE: the core reads MIDI files on its own.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace armadillo::formats {

struct MidiNote {
    std::int64_t start = 0, end = 0;   ///< ticks (end > start)
    int key = 60;                      ///< 0..127, 60 = middle C (C4)
    int velocity = 64;                 ///< 1..127
    int channel = 0;                   ///< 0..15 (9 = General MIDI percussion)
    int track = 0;                     ///< 0-based index of the MTrk chunk
};

struct MidiTempoChange {
    std::int64_t tick = 0;
    double microsPerQuarter = 500000.0;   ///< 500000 = 120 bpm
};

struct MidiMarker {
    std::int64_t tick = 0;
    std::string text;
    bool cuePoint = false;   ///< meta 0x07 (else marker 0x06)
};

struct MidiFile {
    int format = 0;                        ///< 0 or 1
    int ticksPerQuarter = 480;             ///< when !smpte
    bool smpte = false;
    double ticksPerSecond = 0.0;           ///< when smpte: frames/s × ticks/frame
    std::vector<std::string> trackNames;   ///< per track ("" when none)
    std::vector<MidiNote> notes;           ///< sorted by start, then key
    std::vector<MidiTempoChange> tempo;    ///< sorted; always one at tick 0 (120 bpm unless the file says)
    std::vector<MidiMarker> markers;       ///< sorted by tick
    std::int64_t endTick = 0;              ///< the latest end of track
    int unmatchedNoteOffs = 0;             ///< note-offs without a note sounding (ignored)
    int unterminatedNotes = 0;             ///< notes still on at their track's end (ended there)

    /// Seconds at a tick through the tempo map (or the SMPTE rate).
    double secondsAt(std::int64_t tick) const noexcept;
};

/// Parses the bytes of a file. InputError(source, 0, "byte N", message) for anything that is not
/// a well-formed format 0/1 Standard MIDI File (truncated chunks, a running status with none
/// set, a variable-length number longer than 4 bytes, format 2, no tracks...).
MidiFile parseMidiFile(std::string_view bytes, const std::string& source);
/// Reads and parses a file (IoError when it cannot be read).
MidiFile readMidiFile(const std::string& path);

} // namespace armadillo::formats
