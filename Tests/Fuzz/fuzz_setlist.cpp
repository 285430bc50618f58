// Set lists (Live/Stage/SetList.h parseSetList) and the cue changes a performance log gives
// (parseCueChange, `render --cues`). Input: the set list; its last line is also read as a cue change.
#include "FuzzTarget.h"
#include "Live/Stage/SetList.h"

ARMADILLO_FUZZ_TARGET(setlist)
{
    const auto text = armadillo::fuzz::text(data, size);
    const auto lastLine = text.substr(std::min(text.size(), text.rfind('\n') + 1));
    try {
        (void)armadillo::live::parseCueChange(std::string(lastLine));
    } catch (const armadillo::core::InputError&) {
    }
    (void)armadillo::live::parseSetList(text, "fuzz.json");
}
