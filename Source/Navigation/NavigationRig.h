#pragma once
// A walk's sources, the one place a position source is built (issue 45): for the app's
// Navigation window (issue 34, docs/NAVIGATION.md "In the app"), which starts and stops walks
// while it runs, and for the live session `armadillo navigate` runs (Live/Session/LiveSession.h). The
// route read and checked, the position source opened (gpsd, OSC /armadillo/position and ZIG SIM's
// gps on a UDP port of its own, or those messages on the arm's own OSC port), and the
// NavigationLink the navigation scene reads. While a walk runs, the front end's engine request
// names the route and the link, so the navigation scene (the one `armadillo navigate` runs) is
// built in place of the chosen scene and the control step drives it from the arm like any scene.
// JUCE-free. Threads: one thread starts, stops and asks (the app's message thread); the position
// sources run on their own threads and hand fixes over through the link.
#include "Navigation/GpsdSource.h"
#include "Navigation/NavigationScene.h"
#include "Navigation/OscPositionSource.h"
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace armadillo::navigation {

class NavigationRig {
public:
    NavigationRig() = default;
    ~NavigationRig() { stop(); }
    NavigationRig(const NavigationRig&) = delete;
    NavigationRig& operator=(const NavigationRig&) = delete;

    /// Gpsd: `where` is "host[:port]"; Osc: a UDP port of its own; ArmOsc: the positions come on
    /// the arm's own OSC port (a phone sending motion and gps): the arm's receiver hands every
    /// datagram to datagramTap(), `where` is that port (for the messages).
    enum class Source { Gpsd, Osc, ArmOsc };
    /// Starts a walk (stopping one that runs): the route file read and checked, the position
    /// source opened — `where` is gpsd's "host[:port]" or the OSC UDP port. "" or why not,
    /// beginning "Navigation: " (the route's file and line, gpsd not reachable, the port taken or
    /// out of range); nothing is left running then.
    std::string start(const std::string& routePath, Source source, const std::string& where);
    /// The same with a route already read, throwing: IoError when gpsd cannot be reached or the
    /// port is taken, InputError for a bad endpoint or port (the command line's exit codes).
    /// The sources are opened now and run from start().
    void open(std::shared_ptr<const Route> route, Source source, const std::string& where);
    /// Starts the position source's thread (after open()); stopSource() stops it, keeping the
    /// route, the link and the counters for the summary.
    void startSource();
    void stopSource();
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
    /// Where positions come from, for a line on start: "positions from gpsd at localhost:2947".
    std::string describeSource() const;
    /// The position source reaches its positions (gpsd connected; always for OSC).
    bool sourceConnected() const noexcept;
    /// Source::ArmOsc: every datagram of the arm's OSC port, on its receiver's thread (positions
    /// stored, anything else ignored and counted). Empty for the other sources.
    std::function<void(const std::uint8_t*, std::size_t)> datagramTap() const;
    /// The walk's JSON members for a summary line (docs/NAVIGATION.md): ,"finished":…,
    /// "arrivals":…,"waypoints":…, the source's counters and "log_dropped".
    std::string summaryJson() const;

private:
    std::shared_ptr<const Route> route_;
    std::shared_ptr<NavigationLink> link_;
    std::unique_ptr<GpsdSource> gpsd_;
    std::unique_ptr<OscPositionSource> osc_;
    std::shared_ptr<PositionCounters> armCounters_;   // Source::ArmOsc: what the arm's port carried
    int oscPort_ = 0;
};

} // namespace armadillo::navigation
