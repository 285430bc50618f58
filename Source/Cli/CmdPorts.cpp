#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Link/LinkPort.h"
#include <cstdio>
#include <iostream>

namespace armadillo::cli {

int runPorts(const Arguments& args)
{
    return guarded("ports", [&] {
        CommandLine cl("ports", "[--json]",
                       "Lists the serial ports found: name, description, transport and USB vendor:product ids.\n"
                       "Ports come from libserialport, plus bound Bluetooth RFCOMM ports (/dev/rfcomm*) that it\n"
                       "does not list; `armadillo play --port NAME` opens either kind (and pseudo-terminals).",
                       {{"--json", "", "one JSON object per line instead of a table"}});
        if (!cl.parse(args)) return 0;
        const auto ports = link::listSerialPorts();
        const bool json = cl.has("--json");
        if (ports.empty() && !json) std::cout << "no serial ports found\n";
        for (const auto& p : ports) {
            char ids[32] = "";
            if (p.usbVid >= 0) std::snprintf(ids, sizeof ids, "%04x:%04x", p.usbVid & 0xFFFF, p.usbPid & 0xFFFF);
            if (json) {
                auto q = [](const std::string& s) {
                    std::string o = "\"";
                    for (const char c : s) {
                        if (c == '"' || c == '\\') o += '\\';
                        if (static_cast<unsigned char>(c) >= 0x20) o += c;
                    }
                    return o + "\"";
                };
                std::cout << "{\"name\":" << q(p.name) << ",\"description\":" << q(p.description) << ",\"transport\":" << q(p.transport)
                          << ",\"usb_id\":" << q(ids) << ",\"manufacturer\":" << q(p.manufacturer) << ",\"product\":" << q(p.product)
                          << ",\"serial\":" << q(p.serial) << ",\"bluetooth_address\":" << q(p.bluetoothAddress) << "}\n";
            } else {
                std::string name = p.name;
                if (name.size() < 20) name.resize(20, ' ');
                std::string transport = p.transport;
                transport.resize(10, ' ');
                std::cout << name << " " << transport << " " << (ids[0] ? ids : "         ") << "  " << p.description;
                if (!p.bluetoothAddress.empty()) std::cout << " [" << p.bluetoothAddress << "]";
                std::cout << "\n";
            }
        }
        return 0;
    });
}

} // namespace armadillo::cli
