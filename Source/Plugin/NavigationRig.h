#pragma once
// Navigation in the app (issue 34, docs/NAVIGATION.md "In the app"): the message thread's side of
// a walk. It reads the route, opens the position source (gpsd, or OSC /armadillo/position and ZIG
// SIM's gps on a UDP port) and keeps the NavigationLink the navigation scene reads; while a walk
// runs, the processor's engine request names them, so EngineHandover builds the navigation scene
// (Source/Navigation, the one `armadillo navigate` runs) in place of the chosen scene, and the
// control step drives it from the arm like any scene. The status the window shows comes from the
// scene's snapshot. Nothing here is real-time.
#include "Navigation/GpsdSource.h"
#include "Navigation/NavigationScene.h"
#include "Navigation/OscPositionSource.h"
#include <juce_core/juce_core.h>
#include <memory>

namespace armadillo::plugin {

class NavigationRig {
public:
    NavigationRig() = default;
    ~NavigationRig() { stop(); }

    enum class Source { Gpsd, Osc };
    /// Starts a walk: the route file read and checked, the position source opened. "" or why not
    /// (the route's file and line, gpsd not reachable, the port taken); nothing is left running then.
    juce::String start(const juce::File& route, Source source, const juce::String& where);
    void stop();
    bool running() const noexcept { return link_ != nullptr; }

    /// For the engine request: the route and the link while a walk runs (null otherwise).
    std::shared_ptr<const nav::Route> route() const noexcept { return route_; }
    std::shared_ptr<nav::NavigationLink> link() const noexcept { return link_; }
    /// The scene's latest snapshot (waypoint 0 before its first update).
    nav::NavigationStatus status() const;
    /// "gpsd localhost:2947, connected, 12 fixes" / "OSC UDP 9004, 3 fixes".
    juce::String sourceStatus() const;
    juce::String routeName() const;

private:
    std::shared_ptr<const nav::Route> route_;
    std::shared_ptr<nav::NavigationLink> link_;
    std::unique_ptr<nav::GpsdSource> gpsd_;
    std::unique_ptr<nav::OscPositionSource> osc_;
    int oscPort_ = 0;
};

} // namespace armadillo::plugin
