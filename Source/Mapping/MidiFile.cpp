#include "Mapping/MidiFile.h"
#include "Core/Errors.h"

namespace armadillo::mapping {
std::uint32_t smfTicks(double) noexcept { return 0; }
void MidiFileWriter::add(const MidiEvent& e) { events_.push_back(e); }
void MidiFileWriter::addAll(const MappingOutput& out) { for (int i = 0; i < out.midiCount; ++i) add(out.midi[static_cast<std::size_t>(i)]); }
std::vector<std::uint8_t> MidiFileWriter::bytes() const { return {}; }
void MidiFileWriter::write(const std::string&) const { throw IoError("MIDI file writing: not implemented yet"); }
} // namespace armadillo::mapping
