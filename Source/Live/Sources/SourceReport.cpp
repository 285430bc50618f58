#include "Live/Sources/SourceReport.h"
#include "Live/Session/LiveSession.h"
#include "Osc/OscIo.h"
#include <algorithm>
#include <cstdio>
#include <utility>

namespace armadillo::live {

using live::LiveConfig;

std::vector<std::string> SourceReport::startup() const
{
    std::vector<std::string> lines;
    if (osc::OscReceiver* osc = session_.oscReceiver()) {
        if (!osc->serialPath().empty())
            lines.push_back("OSC input: SLIP-framed OSC on serial port " + osc->serialPath());
        else if (!osc->tcpError().empty())
            lines.push_back("OSC input: UDP port " + std::to_string(osc->port()) + " only (no TCP input: " + osc->tcpError() + ")");
    }
    return lines;
}

std::vector<std::string> SourceReport::poll(double elapsed)
{
    std::vector<std::string> lines;
    const LiveConfig& config = session_.config();
    if (osc::OscReceiver* osc = session_.oscReceiver()) {
        const osc::OscInputStats st = osc->stats();
        const bool usable = st.imu + st.orientation > 0;
        // Who else tried: a second sender is ignored while the first streams, and named once.
        if (const std::string other = osc->merger().otherDeviceName(); !other.empty() && shownOthers_.size() < 16 &&
                                                                       std::find(shownOthers_.begin(), shownOthers_.end(), other) == shownOthers_.end()) {
            shownOthers_.push_back(other);
            lines.push_back("OSC input: ignored messages from " + other + " (another device; " +
                            (osc->deviceName().empty() ? std::string("the first sender") : osc->deviceName()) + " streams, one device at a time)");
        }
        if (!osc->serialPath().empty()) {
            const std::string se = osc->serialError();
            if (se != shownSerialError_ && !se.empty()) lines.push_back(se + " (reopening)");
            shownSerialError_ = se;
        }
        // Once the streams have run a while: the rate of each, and a warning when too slow.
        if (usable && !shownRates_ && elapsed >= 3.0) {
            shownRates_ = true;
            const osc::OscSensorRates r = osc->merger().rates();
            std::string line;
            for (const auto& [name, hz] : {std::pair<const char*, double> {"gyro", r.gyro}, {"accel", r.accel}, {"gravity", r.gravity},
                                           {"user accel", r.userAccel}, {"mag", r.mag}, {"compass", r.heading}, {"imu", r.imu},
                                           {"orientation", r.orientation}}) {
                if (!(hz > 0.0)) continue;
                char buf[48];
                std::snprintf(buf, sizeof buf, "%s%s %.0f Hz", line.empty() ? "" : ", ", name, hz);
                line += buf;
            }
            if (st.unchanged > 0) line += " (Sensors2OSC sends only changed readings: rates are of changes)";
            lines.push_back("OSC rates: " + (line.empty() ? std::string("none measured") : line));
            const std::string advice = osc::lowRateAdvice(osc->format(), r.fusion());
            if (!advice.empty() && st.unchanged == 0) lines.push_back("warning: " + advice);
        }
        if (!shownFormat_ && osc->format() != osc::OscFormat::Auto) {
            const std::string sender = osc->deviceName();
            if (!sender.empty() || usable) {
                lines.push_back("OSC input: " + std::string(osc::oscFormatName(osc->format())) +
                                (config.osc.format != osc::OscFormat::Auto ? " (forced)" : " (detected)") + " from " +
                                (sender.empty() ? "?" : sender) + ", mount " + osc->merger().mount().name);
                shownFormat_ = true;
            }
        }
    }
    if (osc::OscReceiver* osc = session_.leftOscReceiver(); osc && !shownLeftFormat_ && osc->format() != osc::OscFormat::Auto &&
                                                              osc->stats().imu + osc->stats().orientation > 0) {
        lines.push_back("left arm OSC input: " + std::string(osc::oscFormatName(osc->format())) +
                        (config.leftOsc.format != osc::OscFormat::Auto ? " (forced)" : " (detected)") + " from " +
                        (osc->deviceName().empty() ? std::string("?") : osc->deviceName()) + ", mount " + osc->merger().mount().name);
        shownLeftFormat_ = true;
    }
    return lines;
}

std::uint64_t SourceReport::leftPackets() const
{
    if (osc::OscReceiver* osc = session_.leftOscReceiver()) return osc->stats().imu + osc->stats().orientation;
    return session_.leftLink() ? session_.leftLink()->stats().packets : 0;
}

std::string SourceReport::leftSummaryJson() const
{
    if (osc::OscReceiver* osc = session_.leftOscReceiver())   // the left sender's usable samples and its input's counters
        return ",\"left_packets\":" + std::to_string(osc->stats().imu + osc->stats().orientation) + ",\"left_osc\":{" + osc->statsJson() + "}";
    if (link::DeviceLink* link = session_.leftLink()) return ",\"left_packets\":" + std::to_string(link->stats().packets);
    return {};
}

std::string SourceReport::noData(double seconds, bool left) const
{
    const LiveConfig& config = session_.config();
    char within[64];
    std::snprintf(within, sizeof within, "%.1f s", seconds);
    const bool port = left ? config.leftSource == LiveConfig::LeftSource::Port : config.source == LiveConfig::Source::Port;
    if (port) {
        link::DeviceLink* link = left ? session_.leftLink() : session_.deviceLink();
        const link::LinkStats l = link ? link->stats() : link::LinkStats {};
        std::string m = std::string(left ? "the left arm: " : "") + "no sensor data from " + (left ? config.leftPort : config.port) + " (" +
                        std::to_string(left ? config.leftBaud : config.baud) + " baud) within " + within + ": ";
        if (l.bytesIn == 0)
            return m + "not a byte was heard. Is the device switched on, and is this its port? ('armadillo ports' lists them)";
        return m + std::to_string(l.bytesIn) + " bytes were heard but no valid sensor packet (" + std::to_string(l.badPackets) +
               " bad packets, " + std::to_string(l.resyncs) + " resyncs, " + std::to_string(l.discardedBytes) +
               " bytes discarded): is the baud rate right (--baud), and is it an ARMadillo board?";
    }
    osc::OscReceiver* osc = left ? session_.leftOscReceiver() : session_.oscReceiver();
    const osc::OscInputStats o = osc ? osc->stats() : osc::OscInputStats {};
    const bool serial = osc && !osc->serialPath().empty();
    std::string m = std::string(left ? "the left arm: " : "") + "no usable sensor data on " +
                    (serial ? "serial port " + osc->serialPath() + " (SLIP-framed OSC)" : "UDP/TCP port " + std::to_string(osc ? osc->port() : 0)) +
                    " within " + within + ": ";
    if (o.datagrams == 0)
        return m + (serial ? std::string("not a message arrived. Is the NGIMU switched on, and is this its port? ('armadillo ports' lists them)")
                           : std::string("not a datagram arrived. Is the sender pointed at this machine's address and port, on the same "
                                         "network, and not blocked by a firewall? (docs/SENSORS.md)"));
    return m + std::to_string(o.datagrams) + " datagrams arrived but none carried usable sensor data; heard instead: " +
           osc::describeHeard(osc->merger().heard()) + (osc->lastError().empty() ? std::string() : "; last refusal: " + osc->lastError()) +
           " (" + osc->statsJson() + ")";
}

} // namespace armadillo::live
