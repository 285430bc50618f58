#include "Navigation/NavigationRig.h"
#include "Core/Text.h"
#include "Navigation/Route.h"
#include <cctype>
#include <cstdio>
#include <charconv>
#include <filesystem>
#include <stdexcept>

namespace armadillo::navigation {

std::string NavigationRig::start(const std::string& routePath, Source source, const std::string& where)
{
    stop();
    try {
        open(std::make_shared<const Route>(readRouteFile(routePath)), source, where);   // InputError / IoError naming the file
        startSource();
        return {};
    } catch (const std::exception& e) {
        stop();
        return std::string("Navigation: ") + e.what();
    }
}

void NavigationRig::open(std::shared_ptr<const Route> route, Source source, const std::string& where)
{
    stop();
    auto link = std::make_shared<NavigationLink>();
    const std::string w = core::trimmed(where);
    if (source == Source::Gpsd) {
        gpsd_ = std::make_unique<GpsdSource>(parseGpsdEndpoint(w), link->position);   // IoError: not reachable
    } else {
        int port = 0;
        const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), port);
        if (ec != std::errc() || end != w.data() + w.size() || port < 1 || port > 65535)
            throw std::invalid_argument("the OSC port must be 1 to 65535");
        if (source == Source::Osc) osc_ = std::make_unique<OscPositionSource>(port, link->position);   // IoError: port taken
        else armCounters_ = std::make_shared<PositionCounters>();
        oscPort_ = port;
    }
    route_ = std::move(route);
    link_ = std::move(link);
}

void NavigationRig::startSource()
{
    if (gpsd_ != nullptr) gpsd_->start();
    if (osc_ != nullptr) osc_->start();
}

std::string NavigationRig::describeSource() const
{
    if (gpsd_ != nullptr) return "positions from gpsd at " + gpsd_->describe();
    if (osc_ != nullptr) return "positions over OSC on UDP port " + std::to_string(osc_->port());
    if (armCounters_ != nullptr) return "the arm's motion and the positions over OSC on port " + std::to_string(oscPort_);
    return "no position source";
}

bool NavigationRig::sourceConnected() const noexcept
{
    return gpsd_ == nullptr || gpsd_->connected();
}

std::function<void(const std::uint8_t*, std::size_t)> NavigationRig::datagramTap() const
{
    if (armCounters_ == nullptr || link_ == nullptr) return {};
    return [link = link_, counters = armCounters_](const std::uint8_t* d, std::size_t n) { storePositionDatagram(d, n, link->position, *counters); };
}

std::string NavigationRig::summaryJson() const
{
    const NavigationStatus st = status();
    const auto u = [](std::uint64_t v) { return static_cast<unsigned long long>(v); };
    char extra[400];
    const std::size_t waypoints = route_ != nullptr && !route_->points.empty() ? route_->points.size() - 1 : 0;
    const std::uint64_t dropped = link_ != nullptr ? link_->droppedLog.load() : 0;
    if (gpsd_ != nullptr)
        std::snprintf(extra, sizeof extra,
                      ",\"finished\":%s,\"arrivals\":%d,\"waypoints\":%zu,\"gpsd_fixes\":%llu,\"gpsd_no_fix\":%llu,\"gpsd_rejected\":%llu,"
                      "\"gpsd_disconnects\":%llu,\"log_dropped\":%llu",
                      st.finished ? "true" : "false", st.arrivals, waypoints, u(gpsd_->fixes()), u(gpsd_->noFix()), u(gpsd_->rejected()),
                      u(gpsd_->disconnects()), u(dropped));
    else
        std::snprintf(extra, sizeof extra, ",\"finished\":%s,\"arrivals\":%d,\"waypoints\":%zu,\"osc_fixes\":%llu,\"osc_rejected\":%llu,\"osc_ignored\":%llu,\"log_dropped\":%llu",
                      st.finished ? "true" : "false", st.arrivals, waypoints, u(osc_ ? osc_->fixes() : armCounters_ ? armCounters_->fixes.load() : 0),
                      u(osc_ ? osc_->rejected() : armCounters_ ? armCounters_->rejected.load() : 0),
                      u(osc_ ? osc_->ignored() : armCounters_ ? armCounters_->ignored.load() : 0), u(dropped));
    return extra;
}

void NavigationRig::stopSource()
{
    if (gpsd_ != nullptr) gpsd_->stop();
    if (osc_ != nullptr) osc_->stop();
}

void NavigationRig::stop()
{
    stopSource();
    gpsd_.reset();
    osc_.reset();
    armCounters_.reset();
    // The scene keeps its own reference to the link until its engine is replaced and deleted.
    link_.reset();
    route_.reset();
}

NavigationStatus NavigationRig::status() const
{
    return link_ != nullptr ? link_->status.load() : NavigationStatus {};
}

std::string NavigationRig::sourceStatus() const
{
    if (gpsd_ != nullptr)
        return "gpsd " + gpsd_->describe() + (gpsd_->connected() ? ", connected, " : ", not connected, ") + std::to_string(gpsd_->fixes()) + " fixes";
    if (osc_ != nullptr) return "OSC UDP " + std::to_string(oscPort_) + ", " + std::to_string(osc_->fixes()) + " fixes";
    return "no position source";
}

std::string NavigationRig::routeName() const
{
    if (route_ == nullptr) return {};
    return route_->name.empty() ? std::filesystem::path(route_->source).filename().string() : route_->name;
}

} // namespace armadillo::navigation
