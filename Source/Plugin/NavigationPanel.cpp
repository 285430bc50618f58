#include "Plugin/NavigationPanel.h"
#include "Plugin/Accessibility.h"
#include "Plugin/PluginProcessor.h"
#include <cmath>

namespace armadillo::plugin {

namespace {
const char* compassPoint(double deg)
{
    static const char* names[] {"north", "north-east", "east", "south-east", "south", "south-west", "west", "north-west"};
    const int i = static_cast<int>(std::floor(std::fmod(deg + 22.5 + 360.0, 360.0) / 45.0)) % 8;
    return names[i];
}
juce::String metres(double m)
{
    if (! std::isfinite(m)) return "-";
    return m >= 1000.0 ? juce::String(m / 1000.0, 2) + " km" : juce::String(juce::roundToInt(m)) + " m";
}
} // namespace

NavigationPanel::NavigationPanel(ArmadilloProcessor& processor) : processor_(processor)
{
    setWantsKeyboardFocus(true);
    heading_.setText("Navigation", juce::dontSendNotification);
    heading_.setFont(juce::Font(15.0f, juce::Font::bold));
    routeLabel_.setText("Route", juce::dontSendNotification);
    sourceLabel_.setText("Position from", juce::dontSendNotification);
    whereLabel_.setText("gpsd host:port", juce::dontSendNotification);
    routeFile_.setTitle("Route file");
    routeFile_.setText("none chosen", juce::dontSendNotification);
    for (auto* l : {&waypoint_, &distance_, &bearing_}) {
        l->setFont(juce::Font(40.0f, juce::Font::bold));
        l->setJustificationType(juce::Justification::centredLeft);
        l->setColour(juce::Label::textColourId, juce::Colours::white);
    }
    waypoint_.setTitle("Next waypoint");
    distance_.setTitle("Distance to it");
    bearing_.setTitle("Bearing to it");
    detail_.setTitle("Navigation status");
    detail_.setJustificationType(juce::Justification::topLeft);
    for (auto* l : {&heading_, &routeLabel_, &routeFile_, &sourceLabel_, &whereLabel_, &waypoint_, &distance_, &bearing_, &detail_})
        addAndMakeVisible(*l);

    describe(chooseRoute_, "Choose route", "Choose the route: a GPX file (route, track or waypoints) or a JSON list of waypoints.");
    chooseRoute_.onClick = [this] { chooseRoute(); };
    describe(source_, "Position source", "Where positions come from: gpsd (a GPS receiver or a phone forwarding NMEA) or OSC from a phone.");
    source_.addItem("gpsd", 1);
    source_.addItem("OSC (phone app, ZIG SIM)", 2);
    source_.setSelectedId(1, juce::dontSendNotification);
    source_.onChange = [this] {
        const bool gpsd = source_.getSelectedId() == 1;
        whereLabel_.setText(gpsd ? "gpsd host:port" : "UDP port", juce::dontSendNotification);
        where_.setText(gpsd ? "localhost:2947" : "9004", false);
    };
    describe(where_, "Position source address", "gpsd: host and port (localhost:2947). OSC: the UDP port positions arrive on.");
    where_.setText("localhost:2947", false);
    describe(start_, "Start or stop walking", "Start guiding along the route (the arm takes over from the scene), or stop.");
    start_.onClick = [this] { toggle(); };
    describe(sayWhere_, "Say where", "Speak the next waypoint, its distance and bearing (also the Space key in this window).");
    sayWhere_.onClick = [this] { say(spokenStatus(), true); };
    for (auto* c : std::initializer_list<juce::Component*> {&chooseRoute_, &source_, &where_, &start_, &sayWhere_}) addAndMakeVisible(*c);
    timerCallback();
    startTimerHz(4);
}

NavigationPanel::~NavigationPanel()
{
    stopTimer();
}

void NavigationPanel::chooseRoute()
{
    chooser_ = std::make_unique<juce::FileChooser>("Choose a route", route_, "*.gpx;*.json");
    chooser_->launchAsync(juce::FileBrowserComponent::canSelectFiles | juce::FileBrowserComponent::openMode, [this](const juce::FileChooser& fc) {
        const auto file = fc.getResult();
        if (file == juce::File()) return;
        route_ = file;
        routeFile_.setText(file.getFileName(), juce::dontSendNotification);
        say("Route " + file.getFileName() + " chosen", false);
    });
}

void NavigationPanel::toggle()
{
    if (processor_.navigation().running()) {
        processor_.stopNavigation();
        say("Navigation stopped: the scene has the motors again", true);
    } else if (route_ == juce::File()) {
        say("Choose a route first", true);
    } else {
        const auto why = processor_.startNavigation(route_, source_.getSelectedId() == 1 ? navigation::NavigationRig::Source::Gpsd : navigation::NavigationRig::Source::Osc,
                                                    where_.getText());
        say(why.isNotEmpty() ? why : "Walking " + juce::String(processor_.navigation().routeName()) + ": the arm guides", true);
    }
    lastWaypoint_ = -1;
    lastArrivals_ = 0;
    lastFix_ = -1;
    lastFinished_ = lastOffRoute_ = false;
    timerCallback();
}

juce::String NavigationPanel::spokenStatus() const
{
    const auto& rig = processor_.navigation();
    if (! rig.running()) return "Not walking. Choose a route and start.";
    const auto s = rig.status();
    if (s.waypoint == 0) return "Starting: waiting for the first update.";
    if (s.finished) return "The end of the route: all " + juce::String(s.arrivals) + " waypoints reached.";
    juce::String text = "Waypoint " + juce::String(s.waypoint) + " of " + juce::String(s.waypointCount);
    if (s.name[0] != '\0') text << ", " << juce::String::fromUTF8(s.name);
    if (s.fix != navigation::FixState::Ok) return text + ". " + (s.fix == navigation::FixState::Lost ? "Fix lost." : "Waiting for a position fix.");
    text << ": " << metres(s.distanceM) << ", bearing " << juce::roundToInt(s.bearingDeg) << " degrees, " << compassPoint(s.bearingDeg) << ".";
    if (s.offRoute) text << " Off route.";
    return text;
}

void NavigationPanel::say(const juce::String& text, bool urgent)
{
    said_ = text;
    if (! processor_.navigation().running()) detail_.setText(text, juce::dontSendNotification);   // else the timer shows it under the status
    announce(processor_, "navigation", text,
             urgent ? juce::AccessibilityHandler::AnnouncementPriority::high : juce::AccessibilityHandler::AnnouncementPriority::medium);
}

bool NavigationPanel::keyPressed(const juce::KeyPress& key)
{
    if (key == juce::KeyPress::spaceKey) {
        say(spokenStatus(), true);
        return true;
    }
    return juce::Component::keyPressed(key);
}

void NavigationPanel::timerCallback()
{
    const auto& rig = processor_.navigation();
    start_.setButtonText(rig.running() ? "Stop walking" : "Start walking");
    for (auto* c : std::initializer_list<juce::Component*> {&chooseRoute_, &source_, &where_}) c->setEnabled(! rig.running());
    if (! rig.running()) {
        waypoint_.setText("Not walking", juce::dontSendNotification);
        distance_.setText({}, juce::dontSendNotification);
        bearing_.setText({}, juce::dontSendNotification);
        return;
    }
    routeFile_.setText(juce::String(rig.routeName()) + " (" + juce::String(rig.sourceStatus()) + ")", juce::dontSendNotification);
    const auto s = rig.status();
    const bool fix = s.fix == navigation::FixState::Ok;
    const auto name = s.name[0] != '\0' ? juce::String::fromUTF8(s.name) : "Waypoint " + juce::String(s.waypoint);
    waypoint_.setText(s.finished ? juce::String("Route done") : name, juce::dontSendNotification);
    distance_.setText(fix && ! s.finished ? metres(s.distanceM) : juce::String(), juce::dontSendNotification);
    bearing_.setText(fix && ! s.finished && std::isfinite(s.bearingDeg)
                         ? juce::String(juce::roundToInt(s.bearingDeg)) + juce::String::fromUTF8("\xc2\xb0 ") + compassPoint(s.bearingDeg)
                         : juce::String(),
                     juce::dontSendNotification);
    juce::String detail = juce::String(rig.routeName()) + ": waypoint " + juce::String(s.waypoint) + " of " + juce::String(s.waypointCount) + ", "
                          + juce::String(s.arrivals) + " reached. Fix: " + navigation::fixStateName(s.fix) + ".";
    if (s.offRoute) detail << " Off route.";
    if (s.magDisturbed) detail << " Magnetic disturbance: heading from the gyroscope.";
    if (s.headingLearned) detail << " Strap offset learned: " << juce::roundToInt(s.offsetDeg) << " degrees.";
    if (said_.isNotEmpty()) detail << "\n" << said_;
    detail_.setText(detail, juce::dontSendNotification);
    // Each change said once: a new waypoint (after an arrival), the fix lost or back, off route, the end.
    if (s.arrivals > lastArrivals_ && s.waypoint > 1) say("Arrived at waypoint " + juce::String(s.waypoint - 1) + ". " + spokenStatus(), true);
    else if (s.waypoint != lastWaypoint_ && lastWaypoint_ < 0 && s.waypoint > 0) say(spokenStatus(), false);
    if (static_cast<int>(s.fix) != lastFix_ && lastFix_ >= 0) say(s.fix == navigation::FixState::Ok ? "Fix back. " + spokenStatus() : "Fix lost", true);
    if (s.offRoute && ! lastOffRoute_) say("Off route", true);
    if (s.finished && ! lastFinished_) say("The end of the route", true);
    lastWaypoint_ = s.waypoint;
    lastArrivals_ = s.arrivals;
    lastFix_ = static_cast<int>(s.fix);
    lastOffRoute_ = s.offRoute;
    lastFinished_ = s.finished;
}

void NavigationPanel::paint(juce::Graphics& g)
{
    g.fillAll(juce::Colour(0xff16202a));
}

void NavigationPanel::resized()
{
    auto area = getLocalBounds().reduced(12);
    heading_.setBounds(area.removeFromTop(24));
    const auto row = [&area] { return takeRow(area); };
    auto r = row();
    routeLabel_.setBounds(r.removeFromLeft(120));
    chooseRoute_.setBounds(r.removeFromRight(100));
    routeFile_.setBounds(r);
    r = row();
    sourceLabel_.setBounds(r.removeFromLeft(120));
    source_.setBounds(r.removeFromLeft(220).reduced(0, 2));
    r.removeFromLeft(8);
    whereLabel_.setBounds(r.removeFromLeft(110));
    where_.setBounds(r.reduced(0, 2));
    r = row();
    start_.setBounds(r.removeFromLeft(160));
    r.removeFromLeft(8);
    sayWhere_.setBounds(r.removeFromLeft(120));
    area.removeFromTop(6);
    waypoint_.setBounds(area.removeFromTop(56));
    distance_.setBounds(area.removeFromTop(56));
    bearing_.setBounds(area.removeFromTop(56));
    detail_.setBounds(area);
}

} // namespace armadillo::plugin
