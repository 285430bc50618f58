#pragma once
// 3D view of the forearm on the environment sphere (software projection with juce::Graphics).
// Earth frame of INTERFACES.md: X east, Y up, Z south. The camera stands behind the performer
// (south), raised; Shift+arrows or a right-drag turn it. Scene objects are drawn on the sphere:
// theremin frets (latitudes of the notes), the cymbal's surface, the panel's two levels, the
// compass target. Mouse drag / arrow keys move the simulated arm (source = simulator) or write
// the orientation parameters (source = host automation).
#include "Core/Pose.h"
#include <juce_gui_basics/juce_gui_basics.h>
#include <Eigen/Geometry>
#include <deque>

namespace armadillo::plugin {

class ArmadilloProcessor;

class ArmView : public juce::Component, private juce::Timer {
public:
    explicit ArmView(ArmadilloProcessor& processor);
    ~ArmView() override;
    void paint(juce::Graphics&) override;
    void mouseDown(const juce::MouseEvent&) override;
    void mouseDrag(const juce::MouseEvent&) override;
    bool keyPressed(const juce::KeyPress&) override;
    void focusGained(FocusChangeType) override { repaint(); }
    void focusLost(FocusChangeType) override { repaint(); }
    std::unique_ptr<juce::AccessibilityHandler> createAccessibilityHandler() override;

    /// Text a screen reader gets as the view's value.
    juce::String describePose() const;

private:
    struct Projected { juce::Point<float> p; float depth; };
    void timerCallback() override;
    Projected project(const Eigen::Vector3d& world) const;
    bool unproject(juce::Point<float> screen, Eigen::Vector3d& world) const;
    void drawCircle(juce::Graphics&, const std::vector<Eigen::Vector3d>& pts, juce::Colour c, float width, bool closed = true) const;
    void drawLatitude(juce::Graphics&, double elevationDeg, juce::Colour c, float width) const;
    void drawSceneObjects(juce::Graphics&) const;
    void moveArm(const core::Pose& pose);
    core::Pose currentPose() const;
    float paramValue(const char* id, float fallback) const;

    ArmadilloProcessor& processor_;
    double cameraAzimuthDeg_ = 25.0;    ///< turn of the camera about the vertical
    double cameraElevationDeg_ = 22.0;  ///< tilt: looking down on the horizon
    juce::Point<float> centre_;
    float radius_ = 100.0f;
    juce::Point<float> lastDrag_;
    std::deque<Eigen::Vector3d> trail_;
    Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
    bool valid_ = false;
};

} // namespace armadillo::plugin
