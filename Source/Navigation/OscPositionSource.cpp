#include "Navigation/OscPositionSource.h"
#include "Core/Errors.h"
#include "Core/Json.h"
#include "Osc/Osc.h"
#include "Osc/OscIo.h"
#include <array>
#include <cmath>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

namespace armadillo::navigation {
namespace {

bool endsWithGps(std::string_view a) noexcept
{
    // "/<uuid>/gps" or "/ZIGSIM/<uuid>/gps": the last element is "gps" and there is one before it.
    if (a.size() < 6 || a.substr(a.size() - 4) != "/gps") return false;
    const std::string_view head = a.substr(0, a.size() - 4);
    if (head.substr(0, 8) == "/ZIGSIM/") {
        const std::string_view uuid = head.substr(8);
        return !uuid.empty() && uuid.find('/') == std::string_view::npos;
    }
    return head.size() > 1 && head.front() == '/' && head.find('/', 1) == std::string_view::npos;
}

struct Decoded {
    PositionFix fix {};
    bool position = false, rejected = false;
};

void onMessage(void* context, const osc::OscMessage& m)
{
    auto& d = *static_cast<Decoded*>(context);
    const bool ours = m.address == "/armadillo/position";
    if (!ours && !endsWithGps(m.address)) return;
    d.position = true;
    double lat = NAN, lon = NAN, acc = NAN;
    const bool typed = m.count >= 2 && m.args[0].asNumber(lat) && m.args[1].asNumber(lon) &&
                       (m.count == 2 || (ours && m.count == 3 && m.args[2].asNumber(acc)));
    PositionFix f;
    f.pos = {lat, lon};
    if (!typed || !validLatLon(f.pos) || (std::isfinite(acc) ? acc < 0.0 : m.count == 3)) {
        d.rejected = true;
        d.fix = {};
        return;
    }
    f.quality = FixQuality::Fix2D;
    f.accuracyM = acc;
    d.fix = f;
    d.rejected = false;
}

} // namespace

bool decodePositionDatagram(const std::uint8_t* data, std::size_t size, PositionFix& out, bool& rejected)
{
    Decoded d;
    if (size > 0 && data[0] == '{') {   // ZIG SIM's JSON mode
        try {
            const armadillo::core::JsonValue root = armadillo::core::parseJson(std::string_view(reinterpret_cast<const char*>(data), size), "ZIG SIM JSON");
            const armadillo::core::JsonValue* sensors = root.find("sensordata");
            const armadillo::core::JsonValue* gps = sensors ? sensors->find("gps") : nullptr;
            if (!gps) return false;
            const armadillo::core::JsonValue* la = gps->find("latitude");
            const armadillo::core::JsonValue* lo = gps->find("longitude");
            PositionFix f;
            if (la && lo && la->kind == armadillo::core::JsonValue::Kind::Number && lo->kind == armadillo::core::JsonValue::Kind::Number) f.pos = {la->number, lo->number};
            else f.pos = {NAN, NAN};
            rejected = !validLatLon(f.pos);
            if (!rejected) f.quality = FixQuality::Fix2D;
            out = rejected ? PositionFix {} : f;
            return true;
        } catch (const core::InputError&) {
            return false;
        }
    }
    const char* error = nullptr;
    osc::decodeOscPacket(data, size, &onMessage, &d, &error);
    if (!d.position) return false;
    out = d.fix;
    rejected = d.rejected;
    return true;
}

bool storePositionDatagram(const std::uint8_t* data, std::size_t size, PositionMailbox& mailbox, PositionCounters& counters)
{
    PositionFix fix;
    bool rejected = false;
    if (!decodePositionDatagram(data, size, fix, rejected)) {
        counters.ignored.fetch_add(1, std::memory_order_relaxed);
        return false;
    }
    if (rejected) {
        counters.rejected.fetch_add(1, std::memory_order_relaxed);
        mailbox.countRejected();
    } else {
        counters.fixes.fetch_add(1, std::memory_order_relaxed);
    }
    mailbox.store(fix);
    return true;
}

OscPositionSource::OscPositionSource(int port, PositionMailbox& mailbox) : mailbox_(mailbox)
{
    fd_ = osc::bindUdpAnyInterface(port, "position OSC in", port_);
}

OscPositionSource::~OscPositionSource()
{
    stop();
    if (fd_ >= 0) ::close(fd_);
}

void OscPositionSource::start()
{
    if (running_.exchange(true)) return;
    thread_ = std::thread([this] { run(); });
}

void OscPositionSource::stop()
{
    running_ = false;
    if (thread_.joinable()) thread_.join();
}

void OscPositionSource::run()
{
    std::array<std::uint8_t, 65536> buffer {};
    while (running_.load()) {
        pollfd p {fd_, POLLIN, 0};
        if (::poll(&p, 1, 100) <= 0) continue;
        const ssize_t n = ::recv(fd_, buffer.data(), buffer.size(), MSG_DONTWAIT);
        if (n <= 0) continue;
        storePositionDatagram(buffer.data(), static_cast<std::size_t>(n), mailbox_, counters_);
    }
}

} // namespace armadillo::navigation
