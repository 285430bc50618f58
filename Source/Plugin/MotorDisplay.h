#pragma once
// The tactile display on screen: the 3×3 grid (rows wrist → elbow, hand at the top as the thesis
// draws it; columns left / underside / right for the right arm) plus the three optional back
// motors. Levels are the ones after the safety stage, the same the device receives.
#include "Core/Types.h"
#include <juce_gui_basics/juce_gui_basics.h>

namespace armadillo::plugin {

class ArmadilloProcessor;

class MotorDisplay : public juce::Component, private juce::Timer {
public:
    explicit MotorDisplay(ArmadilloProcessor& processor);
    void paint(juce::Graphics&) override;
    juce::String describeLevels() const;
    std::unique_ptr<juce::AccessibilityHandler> createAccessibilityHandler() override;

private:
    void timerCallback() override;
    ArmadilloProcessor& processor_;
    core::MotorLevels levels_ {};
    int motorCount_ = core::kGridMotors;
    juce::String lastGesture_;
    std::uint64_t gestureCount_ = 0;
    double gestureFlash_ = 0.0;
};

} // namespace armadillo::plugin
