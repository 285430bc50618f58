#include "Navigation/NavigationRig.h"
#include "Navigation/Route.h"
#include <cctype>
#include <charconv>
#include <filesystem>

namespace armadillo::navigation {

namespace {

std::string trimmed(const std::string& s)
{
    std::size_t a = 0, b = s.size();
    while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
    while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
    return s.substr(a, b - a);
}

} // namespace

std::string NavigationRig::start(const std::string& routePath, Source source, const std::string& where)
{
    stop();
    try {
        auto route = std::make_shared<const Route>(readRouteFile(routePath));   // InputError / IoError naming the file
        auto link = std::make_shared<NavigationLink>();
        const std::string w = trimmed(where);
        if (source == Source::Gpsd) {
            gpsd_ = std::make_unique<GpsdSource>(parseGpsdEndpoint(w), link->position);   // IoError: not reachable
            gpsd_->start();
        } else {
            int port = 0;
            const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), port);
            if (ec != std::errc() || end != w.data() + w.size() || port < 1 || port > 65535)
                return "Navigation: the OSC port must be 1 to 65535";
            osc_ = std::make_unique<OscPositionSource>(port, link->position);   // IoError: port taken
            osc_->start();
            oscPort_ = port;
        }
        route_ = std::move(route);
        link_ = std::move(link);
        return {};
    } catch (const std::exception& e) {
        stop();
        return std::string("Navigation: ") + e.what();
    }
}

void NavigationRig::stop()
{
    if (gpsd_ != nullptr) gpsd_->stop();
    if (osc_ != nullptr) osc_->stop();
    gpsd_.reset();
    osc_.reset();
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
