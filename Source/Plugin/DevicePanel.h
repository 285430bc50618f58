#pragma once
// Device / port / calibration / OSC settings with link statistics. Every control carries an
// accessible title and description and is reachable with Tab. While a guided calibration runs,
// its panel takes the place of the link statistics and the OSC settings.
#include "Plugin/CalibrationPanel.h"
#include <juce_gui_basics/juce_gui_basics.h>

namespace armadillo::plugin {

class ArmadilloProcessor;

class DevicePanel : public juce::Component, private juce::Timer {
public:
    explicit DevicePanel(ArmadilloProcessor& processor);
    ~DevicePanel() override;
    void resized() override;
    void paint(juce::Graphics&) override;

private:
    void timerCallback() override;
    void rescanPorts();
    void chooseCalibration();
    void startCalibration();

    ArmadilloProcessor& processor_;
    juce::Label deviceHeading_, oscHeading_;
    juce::ComboBox port_;
    juce::TextButton rescan_ {"Rescan"}, connect_ {"Connect"}, calibration_ {"Calibration file..."},
        calibrate_ {"Calibrate..."};
    juce::Label calibrationFile_, link_;
    juce::ComboBox side_;
    juce::ToggleButton backMotors_ {"Back motors (12)"};
    juce::ToggleButton connectOnStart_ {"Connect on start"};
    juce::ToggleButton oscOut_ {"OSC out"}, oscIn_ {"OSC in"};
    juce::TextEditor oscHost_, oscPort_, oscInPort_;
    juce::Label hostLabel_, portLabel_, inPortLabel_;
    std::unique_ptr<juce::FileChooser> chooser_;
    CalibrationPanel calibrationPanel_;
    bool calibrating_ = false;   // calibrationPanel_ shown (layout changes with it)
};

} // namespace armadillo::plugin
