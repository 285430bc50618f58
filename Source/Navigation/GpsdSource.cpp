#include "Navigation/GpsdSource.h"
#include "Core/Errors.h"
#include "Core/Json.h"
#include "Osc/OscDialects.h"
#include <chrono>
#include <cmath>
#include <cerrno>
#include <cstring>
#include <gps.h>
#include <poll.h>
#include <sys/socket.h>
#include <vector>

namespace armadillo::navigation {

GpsdEndpoint parseGpsdEndpoint(const std::string& text)
{
    GpsdEndpoint e;
    if (text.empty()) return e;
    std::string host = text, port;
    if (text.front() == '[') {   // [IPv6]:PORT
        const auto close = text.find(']');
        if (close == std::string::npos) throw core::InputError("--gpsd", 0, "", "'" + text + "': an IPv6 address needs its closing ']'");
        host = text.substr(1, close - 1);
        if (close + 1 < text.size()) {
            if (text[close + 1] != ':') throw core::InputError("--gpsd", 0, "", "'" + text + "': expected ':PORT' after ']'");
            port = text.substr(close + 2);
        }
    } else if (const auto colon = text.rfind(':'); colon != std::string::npos) {
        host = text.substr(0, colon);
        port = text.substr(colon + 1);
    }
    if (!host.empty()) e.host = host;
    if (!port.empty() || text.back() == ':') {
        long p = 0;
        for (char c : port) {
            if (c < '0' || c > '9') throw core::InputError("--gpsd", 0, "", "'" + text + "': the port '" + port + "' is not a number");
            p = p * 10 + (c - '0');
            if (p > 65535) break;
        }
        if (port.empty() || p < 1 || p > 65535) throw core::InputError("--gpsd", 0, "", "'" + text + "': the port must be 1…65535");
        e.port = port;
    }
    return e;
}

GpsdReport readGpsdJson(std::string_view line, PositionFix& out)
{
    // The report is read here, not by libgps: libgps 3.22's reader never returns on some reports
    // a gpsd (which may be on another host: `--gpsd HOST:PORT`) could send — an unterminated
    // DEVICES array, or a "devices" array in any other report (found by fuzzing,
    // Tests/Fuzz/regressions/gpsd/). Only the TPV fields gpsd_json(5) documents are used.
    out = PositionFix {};
    core::JsonValue root;
    try {
        root = core::parseJson(line, "gpsd");
    } catch (const core::InputError&) {
        return GpsdReport::None;
    }
    if (root.kind != core::JsonValue::Kind::Object) return GpsdReport::None;
    const core::JsonValue* kind = root.find("class");
    if (!kind || kind->kind != core::JsonValue::Kind::String || kind->string != "TPV") return GpsdReport::None;   // VERSION, DEVICES, SKY, …
    const auto number = [&root](const char* key) {
        const core::JsonValue* v = root.find(key);
        return v && v->kind == core::JsonValue::Kind::Number ? v->number : std::nan("");
    };
    if (const core::JsonValue* t = root.find("time"); t && t->kind == core::JsonValue::Kind::String)
        out.sourceTime = osc::parseIsoTimestamp(t->string);
    const double mode = number("mode");   // 0 unknown, 1 no fix, 2 2D, 3 3D
    if (!(mode >= 2.0) || (!root.find("lat") && !root.find("lon"))) return GpsdReport::NoFix;
    out.pos = {number("lat"), number("lon")};
    if (!validLatLon(out.pos)) {   // garbage: refused, and said as "no fix"
        out = PositionFix {};
        return GpsdReport::Rejected;
    }
    out.quality = mode >= 3.0 ? FixQuality::Fix3D : FixQuality::Fix2D;
    const double eph = number("eph"), epx = number("epx"), epy = number("epy");
    if (std::isfinite(eph)) out.accuracyM = eph;
    else if (std::isfinite(epx) && std::isfinite(epy)) out.accuracyM = std::hypot(epx, epy);
    const double speed = number("speed"), track = number("track");
    if (std::isfinite(speed) && std::isfinite(track)) {
        out.speedMps = speed;
        out.courseDeg = track;
    }
    return GpsdReport::Fix;
}

struct GpsdSource::Impl {
    gps_data_t data {};
    bool open = false;
    std::string pending;   // the start of a report line not yet complete
    static constexpr std::size_t kMaxLine = 1 << 16;   // gpsd's longest reports (SKY) are a few KB
    /// Waits up to `ms` for bytes and appends the complete lines that arrived. False when gpsd
    /// closed the connection or it failed. The lines are read here rather than by gps_read, so
    /// each goes through readGpsdJson's check before libgps parses it.
    bool receive(int ms, std::vector<std::string>& lines)
    {
        pollfd p {data.gps_fd, POLLIN, 0};
        const int ready = ::poll(&p, 1, ms);
        if (ready < 0) return errno == EINTR;
        if (ready == 0) return true;
        char buffer[4096];
        const ssize_t n = ::recv(data.gps_fd, buffer, sizeof buffer, 0);
        if (n < 0) return errno == EINTR || errno == EAGAIN;
        if (n == 0) return false;
        pending.append(buffer, static_cast<std::size_t>(n));
        std::size_t start = 0;
        for (std::size_t nl; (nl = pending.find('\n', start)) != std::string::npos; start = nl + 1)
            lines.emplace_back(pending, start, nl - start);
        pending.erase(0, start);
        if (pending.size() > kMaxLine) pending.clear();   // no report is this long: dropped
        return true;
    }
    bool connect(const GpsdEndpoint& e, std::string& error)
    {
        std::memset(&data, 0, sizeof data);
        if (gps_open(e.host.c_str(), e.port.c_str(), &data) != 0) {
            error = gps_errstr(errno);
            return false;
        }
        open = true;
        if (gps_stream(&data, WATCH_ENABLE | WATCH_JSON, nullptr) != 0) {
            error = "gpsd refused the WATCH request";
            close();
            return false;
        }
        return true;
    }
    void close()
    {
        if (open) {
            gps_stream(&data, WATCH_DISABLE, nullptr);
            gps_close(&data);
        }
        open = false;
        pending.clear();
    }
};

GpsdSource::GpsdSource(const GpsdEndpoint& endpoint, PositionMailbox& mailbox) : endpoint_(endpoint), mailbox_(mailbox), impl_(std::make_unique<Impl>())
{
    std::string error;
    if (!impl_->connect(endpoint_, error)) throw core::IoError("gpsd at " + describe() + ": cannot connect (" + error + "); is gpsd running? (docs/NAVIGATION.md)");
    connected_ = true;
}

GpsdSource::~GpsdSource()
{
    stop();
    impl_->close();
}

void GpsdSource::start()
{
    if (running_.exchange(true)) return;
    thread_ = std::thread([this] { run(); });
}

void GpsdSource::stop()
{
    running_ = false;
    if (thread_.joinable()) thread_.join();
}

void GpsdSource::run()
{
    auto lastTry = std::chrono::steady_clock::now();
    std::vector<std::string> lines;
    while (running_.load()) {
        if (!impl_->open) {   // gpsd went away: try again every second, reporting nothing meanwhile
            if (std::chrono::steady_clock::now() - lastTry < std::chrono::seconds(1)) {
                std::this_thread::sleep_for(std::chrono::milliseconds(50));
                continue;
            }
            lastTry = std::chrono::steady_clock::now();
            std::string error;
            if (impl_->connect(endpoint_, error)) connected_ = true;
            continue;
        }
        lines.clear();
        if (!impl_->receive(200, lines)) {
            impl_->close();
            connected_ = false;
            disconnects_.fetch_add(1);
            lastTry = std::chrono::steady_clock::now();
            continue;
        }
        for (const std::string& line : lines) {
            PositionFix fix;
            const GpsdReport report = readGpsdJson(line, fix);
            if (report == GpsdReport::None) continue;   // not a TPV report (VERSION, DEVICES, SKY, …) or not JSON
            if (report == GpsdReport::Rejected) {
                rejected_.fetch_add(1);
                mailbox_.countRejected();
                mailbox_.store(PositionFix {});
                continue;
            }
            if (report == GpsdReport::Fix) fixes_.fetch_add(1);
            else noFix_.fetch_add(1);
            mailbox_.store(fix);
        }
    }
}

} // namespace armadillo::navigation
