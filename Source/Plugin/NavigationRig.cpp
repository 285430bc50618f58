#include "Plugin/NavigationRig.h"
#include "Navigation/Route.h"

namespace armadillo::plugin {

juce::String NavigationRig::start(const juce::File& routeFile, Source source, const juce::String& where)
{
    stop();
    try {
        auto route = std::make_shared<const nav::Route>(nav::readRouteFile(routeFile.getFullPathName().toStdString()));
        auto link = std::make_shared<nav::NavigationLink>();
        if (source == Source::Gpsd) {
            gpsd_ = std::make_unique<nav::GpsdSource>(nav::parseGpsdEndpoint(where.trim().toStdString()), link->position);   // IoError: not reachable
            gpsd_->start();
        } else {
            const int port = where.trim().getIntValue();
            if (port < 1 || port > 65535) return "Navigation: the OSC port must be 1 to 65535";
            osc_ = std::make_unique<nav::OscPositionSource>(port, link->position);   // IoError: port taken
            osc_->start();
            oscPort_ = port;
        }
        route_ = std::move(route);
        link_ = std::move(link);
        return {};
    } catch (const std::exception& e) {
        stop();
        return "Navigation: " + juce::String(e.what());
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

nav::NavigationStatus NavigationRig::status() const
{
    return link_ != nullptr ? link_->status.load() : nav::NavigationStatus {};
}

juce::String NavigationRig::sourceStatus() const
{
    if (gpsd_ != nullptr)
        return "gpsd " + juce::String(gpsd_->describe()) + (gpsd_->connected() ? ", connected, " : ", not connected, ")
               + juce::String(gpsd_->fixes()) + " fixes";
    if (osc_ != nullptr) return "OSC UDP " + juce::String(oscPort_) + ", " + juce::String(osc_->fixes()) + " fixes";
    return "no position source";
}

juce::String NavigationRig::routeName() const
{
    if (route_ == nullptr) return {};
    return route_->name.empty() ? juce::File(route_->source).getFileName() : juce::String(route_->name);
}

} // namespace armadillo::plugin
