#pragma once
// A walk's sources, for a front end that starts and stops walks while it runs (the app's
// Navigation window; issue 34, docs/NAVIGATION.md "In the app"): the route read and checked, the
// position source opened (gpsd, or OSC /armadillo/position and ZIG SIM's gps on a UDP port), and
// the NavigationLink the navigation scene reads. While a walk runs, the front end's engine request
// names the route and the link, so the navigation scene (the one `armadillo navigate` runs) is
// built in place of the chosen scene and the control step drives it from the arm like any scene.
// JUCE-free. Threads: one thread starts, stops and asks (the app's message thread); the position
// sources run on their own threads and hand fixes over through the link.
#include "Navigation/GpsdSource.h"
#include "Navigation/NavigationScene.h"
#include "Navigation/OscPositionSource.h"
#include <memory>
#include <string>

namespace armadillo::navigation {

class NavigationRig {
public:
    NavigationRig() = default;
    ~NavigationRig() { stop(); }
    NavigationRig(const NavigationRig&) = delete;
    NavigationRig& operator=(const NavigationRig&) = delete;

    enum class Source { Gpsd, Osc };
    /// Starts a walk (stopping one that runs): the route file read and checked, the position
    /// source opened — `where` is gpsd's "host[:port]" or the OSC UDP port. "" or why not,
    /// beginning "Navigation: " (the route's file and line, gpsd not reachable, the port taken or
    /// out of range); nothing is left running then.
    std::string start(const std::string& routePath, Source source, const std::string& where);
    void stop();
    bool running() const noexcept { return link_ != nullptr; }

    /// For the engine request: the route and the link while a walk runs (null otherwise).
    std::shared_ptr<const Route> route() const noexcept { return route_; }
    std::shared_ptr<NavigationLink> link() const noexcept { return link_; }
    /// The scene's latest snapshot (waypoint 0 before its first update).
    NavigationStatus status() const;
    /// "gpsd localhost:2947, connected, 12 fixes" / "OSC UDP 9004, 3 fixes" / "no position source".
    std::string sourceStatus() const;
    /// The route's name, else its file's name; "" while no walk runs.
    std::string routeName() const;

private:
    std::shared_ptr<const Route> route_;
    std::shared_ptr<NavigationLink> link_;
    std::unique_ptr<GpsdSource> gpsd_;
    std::unique_ptr<OscPositionSource> osc_;
    int oscPort_ = 0;
};

} // namespace armadillo::navigation
