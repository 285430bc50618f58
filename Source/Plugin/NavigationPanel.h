#pragma once
// The Navigation window (issue 34, docs/NAVIGATION.md "In the app"): choose a route (GPX or JSON)
// and a position source (gpsd host:port, or a UDP port for OSC /armadillo/position and ZIG SIM's
// gps), start the walk, and read the next waypoint's name, distance and bearing in large type.
// The arm alone guides (the navigation scene in place of the chosen scene); this window is for
// setting it up and for a sighted companion or a screen-reader user: every control has an
// accessible title and is reached with Tab, "Say where" (or Space anywhere in the window)
// speaks the status, and arrivals, a lost fix and the route's end are announced (self-voiced too).
#include "Plugin/Controls.h"
#include <juce_gui_basics/juce_gui_basics.h>

namespace armadillo::plugin {

class ArmadilloProcessor;

class NavigationPanel : public juce::Component, private juce::Timer {
public:
    explicit NavigationPanel(ArmadilloProcessor& processor);
    ~NavigationPanel() override;
    void resized() override;
    void paint(juce::Graphics&) override;
    bool keyPressed(const juce::KeyPress&) override;
    /// What "Say where" speaks (tests, screenshots).
    juce::String spokenStatus() const;
    juce::Label& waypointLabel() noexcept { return waypoint_; }
    juce::Label& distanceLabel() noexcept { return distance_; }
    juce::Label& bearingLabel() noexcept { return bearing_; }

private:
    void timerCallback() override;
    void chooseRoute();
    void toggle();
    void say(const juce::String& text, bool urgent);

    ArmadilloProcessor& processor_;
    juce::Label heading_, routeLabel_, routeFile_, sourceLabel_, whereLabel_, waypoint_, distance_, bearing_, detail_;
    juce::TextButton chooseRoute_ {"Route..."}, start_ {"Start walking"}, sayWhere_ {"Say where"};
    ChoiceBox source_;
    juce::TextEditor where_;
    juce::File route_;
    juce::String said_;   // the last thing said, shown under the status
    std::unique_ptr<juce::FileChooser> chooser_;
    // What was announced last (so each change is said once).
    int lastWaypoint_ = -1, lastArrivals_ = 0;
    int lastFix_ = -1;
    bool lastFinished_ = false, lastOffRoute_ = false;
};

} // namespace armadillo::plugin
