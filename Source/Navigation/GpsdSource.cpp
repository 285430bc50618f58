#include "Navigation/GpsdSource.h"
#include "Core/Errors.h"
#include <chrono>
#include <cmath>
#include <cstring>
#include <gps.h>

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

struct GpsdSource::Impl {
    gps_data_t data {};
    bool open = false;
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
        if (!gps_waiting(&impl_->data, 200000)) {   // µs; also false on a closed socket, read below tells
            continue;
        }
        impl_->data.set = 0;
        if (gps_read(&impl_->data, nullptr, 0) < 0) {
            impl_->close();
            connected_ = false;
            disconnects_.fetch_add(1);
            lastTry = std::chrono::steady_clock::now();
            continue;
        }
        if (!(impl_->data.set & MODE_SET)) continue;   // not a TPV report (VERSION, DEVICES, SKY, …)
        const gps_fix_t& f = impl_->data.fix;
        PositionFix fix;
        fix.sourceTime = static_cast<double>(f.time.tv_sec) + 1e-9 * static_cast<double>(f.time.tv_nsec);
        if (f.mode >= MODE_2D && (impl_->data.set & LATLON_SET)) {
            fix.pos = {f.latitude, f.longitude};
            if (!validLatLon(fix.pos)) {   // garbage: refused, and said as "no fix"
                rejected_.fetch_add(1);
                mailbox_.countRejected();
                mailbox_.store(PositionFix {});
                continue;
            }
            fix.quality = f.mode >= MODE_3D ? FixQuality::Fix3D : FixQuality::Fix2D;
            if (std::isfinite(f.eph)) fix.accuracyM = f.eph;
            else if (std::isfinite(f.epx) && std::isfinite(f.epy)) fix.accuracyM = std::hypot(f.epx, f.epy);
            if ((impl_->data.set & SPEED_SET) && std::isfinite(f.speed)) fix.speedMps = f.speed;
            if ((impl_->data.set & TRACK_SET) && std::isfinite(f.track)) fix.courseDeg = f.track;
            if (!std::isfinite(fix.speedMps) || !std::isfinite(fix.courseDeg)) fix.speedMps = fix.courseDeg = std::nan("");
            fixes_.fetch_add(1);
        } else {
            noFix_.fetch_add(1);
        }
        mailbox_.store(fix);
    }
}

} // namespace armadillo::navigation
