// Audio files as read by libsndfile (Core/Wav.h readWav: recordings, cymbal samples, stems) and
// a multichannel WAV imported as a tactile score (Formats/ScoreImport.h importTactileWav). Both
// read paths only: the input goes through a file of this process's own.
#include "Core/Wav.h"
#include "Formats/ScoreImport.h"
#include "FuzzTarget.h"

ARMADILLO_FUZZ_TARGET(wav)
{
    const std::string path = armadillo::fuzz::scratchFile("wav", ".wav", data, size);
    try {
        (void)armadillo::core::readWav(path);
    } catch (const armadillo::core::InputError&) {
    }
    armadillo::formats::HapticImportOptions options;
    (void)armadillo::formats::importTactileWav(path, options);
}
