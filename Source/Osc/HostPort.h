#pragma once
// A network destination as the command line and the app's settings write it ("HOST:PORT"): a
// plain value type, so front ends can name an OSC or MQTT destination without the sockets
// (Osc/OscIo.h) that use it.
#include <string>

namespace armadillo::osc {

struct HostPort {
    std::string host;
    int port = 0;
};
/// "HOST:PORT", "[v6addr]:PORT" or ":PORT"/"PORT" (localhost). Throws std::invalid_argument.
HostPort parseHostPort(const std::string& text);

} // namespace armadillo::osc
