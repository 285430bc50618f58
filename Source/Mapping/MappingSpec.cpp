#include "Mapping/MappingSpec.h"
#include "Core/Errors.h"

namespace armadillo::mapping {
std::string sourceName(const SourceSpec&) { return {}; }
bool parseSourceName(std::string_view, SourceSpec&) { return false; }
bool isEventSource(SourceKind k) noexcept { return k == SourceKind::Gesture || k == SourceKind::Posture; }
bool isAngleSource(SourceKind) noexcept { return false; }
void defaultInputRange(SourceKind, double& lo, double& hi) noexcept { lo = 0.0; hi = 1.0; }
MappingDocument parseMappingDocument(std::string_view, const std::string& sourceName)
{
    throw InputError(sourceName, 0, "", "mapping files: not implemented yet");
}
std::string toJson(const MappingDocument&) { return {}; }
std::vector<std::string> presetNames(const std::string&) { return {}; }
MappingDocument loadMapping(const std::string& presetOrPath, const std::string&)
{
    throw IoError("--map " + presetOrPath + ": not implemented yet");
}
} // namespace armadillo::mapping
