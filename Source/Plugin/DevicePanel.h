#pragma once
// Device / port / calibration / OSC settings with link statistics. Every control carries an
// accessible title and description and is reachable with Tab. While a guided calibration runs,
// its panel takes the place of the link statistics and the OSC settings; so does the guided
// mount calibration of an OSC sensor (format and mount choices: docs/SENSORS.md).
#include "Plugin/CalibrationPanel.h"
#include "Plugin/Controls.h"
#include "Plugin/MountCalibrationPanel.h"
#include <juce_gui_basics/juce_gui_basics.h>

namespace armadillo::plugin {

class ArmadilloProcessor;

class DevicePanel : public juce::Component, private juce::Timer {
public:
    explicit DevicePanel(ArmadilloProcessor& processor);
    ~DevicePanel() override;
    void resized() override;
    void paint(juce::Graphics&) override;
    /// The height below which rows would overlap: the editor scrolls the panel instead.
    static constexpr int kMinimumHeight = 12 * 20 + 33 + 12;
    /// The welcome's shortcuts: focus on the port list, or on the OSC input switch.
    void focusDevice() { port_.grabKeyboardFocus(); }
    void focusOscInput() { oscIn_.grabKeyboardFocus(); }

private:
    void timerCallback() override;
    void rescanPorts();
    void chooseCalibration();
    void startCalibration();
    void startMountCalibration();
    void chooseMountFile();
    /// The format and mount choices follow the settings (a loaded state, the calibration).
    void syncOscChoices();

    ArmadilloProcessor& processor_;
    juce::Label deviceHeading_, oscHeading_;
    ChoiceBox port_;
    juce::TextButton rescan_ {"Rescan"}, connect_ {"Connect"}, calibration_ {"Calibration file..."},
        calibrate_ {"Calibrate..."};
    juce::Label calibrationFile_, link_;
    ChoiceBox side_;
    juce::ToggleButton backMotors_ {"Back motors (12)"};
    juce::ToggleButton connectOnStart_ {"Connect on start"};
    juce::ToggleButton oscOut_ {"OSC out"}, oscIn_ {"OSC in"};
    juce::TextEditor oscHost_, oscPort_, oscInPort_;
    juce::Label hostLabel_, portLabel_, inPortLabel_;
    // Two arms (docs/STAGE.md): an OSC sender as the left arm, and its port.
    juce::ToggleButton leftArmOsc_ {"Left arm OSC in"};
    juce::TextEditor leftArmPort_;
    juce::Label leftPortLabel_;
    // OSC sender format and mount (docs/SENSORS.md), and the input's status line.
    ChoiceBox oscFormat_, oscMount_;
    juce::Label formatLabel_, mountLabel_, oscStatus_;
    juce::TextButton mountFile_ {"Mount file..."}, calibrateMount_ {"Calibrate mount..."};
    juce::StringArray mountPresets_;
    juce::String mountFileError_;   // a refused mount file, shown above the status line until the next choice
    std::unique_ptr<juce::FileChooser> chooser_;
    CalibrationPanel calibrationPanel_;
    MountCalibrationPanel mountPanel_;
    bool calibrating_ = false;   // calibrationPanel_ shown (layout changes with it)
    bool mountCalibrating_ = false;   // mountPanel_ shown instead of the link statistics
};

} // namespace armadillo::plugin
