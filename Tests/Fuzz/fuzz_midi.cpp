// Standard MIDI Files (Formats/MidiFile.h parseMidiFile) and their import as a tactile score
// (Formats/ScoreImport.h importMidi: the pitch rule, the budget, the level curve).
#include "Formats/MidiFile.h"
#include "Formats/ScoreImport.h"
#include "FuzzTarget.h"

ARMADILLO_FUZZ_TARGET(midi)
{
    using namespace armadillo::formats;
    const MidiFile midi = parseMidiFile(armadillo::fuzz::text(data, size), "fuzz.mid");
    MidiImportOptions options;
    options.maxMotors = 1 + static_cast<int>(size % 9);
    options.follow = (size & 1) != 0;
    (void)importMidi(midi, options, "fuzz.mid");
}
