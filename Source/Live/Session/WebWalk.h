#pragma once
// A walk as the web page shows it (web::InstrumentStatus::Walk), read from the navigation rig the
// same way for both clocks' presenters (SessionWebView, BlockWebView). Any thread: the rig's
// status is a lock-free snapshot.
#include "Navigation/Guidance.h"
#include "Navigation/NavigationRig.h"
#include "Web/WebInstrument.h"
#include <cmath>

namespace armadillo::live {

/// The walk of `nav` (off while it runs none).
inline web::InstrumentStatus::Walk webWalk(const navigation::NavigationRig& nav)
{
    web::InstrumentStatus::Walk w;
    if (!nav.running()) return w;
    const navigation::NavigationStatus n = nav.status();
    w.on = true;
    w.route = nav.routeName();
    w.waypoint = n.waypoint;
    w.waypointCount = n.waypointCount;
    w.waypointName = n.name;
    w.arrivals = n.arrivals;
    w.distanceM = std::isfinite(n.distanceM) ? n.distanceM : -1.0;
    w.bearingDeg = std::isfinite(n.bearingDeg) ? n.bearingDeg : -1.0;
    w.finished = n.finished;
    w.fix = navigation::fixStateName(n.fix);
    return w;
}

} // namespace armadillo::live
