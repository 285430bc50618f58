#pragma once
// The web page's JSON: the instrument's status (each server-sent event, GET /api/status), the
// scene with its parameters (GET /api/scene) and the answers to the two state changes. Field
// names are docs/INTERFACES.md's ("The web page"). Numbers that are not finite are written null.
#include "Web/WebInstrument.h"
#include <string>
#include <vector>

namespace armadillo::web {

std::string statusJson(const InstrumentStatus& status);
/// `scenes`: the scenes the page may choose now; `sceneChoice`: why none may be ("" = they may).
std::string sceneJson(const InstrumentStatus& status, const std::vector<ParameterInfo>& parameters, const std::vector<std::string>& scenes,
                      const std::string& sceneChoice);
std::string commandJson(const std::string& command, double t);
std::string parameterSetJson(const std::string& id, double value);

} // namespace armadillo::web
