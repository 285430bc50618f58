#pragma once
// The guided mount calibration in the device panel (docs/SENSORS.md "Mounting"): two or three
// poses of the arm held still while the OSC sender streams; the pose's instruction, a progress
// bar, Next (enabled once the pose has enough still samples), Skip (the optional roll pose only)
// and Cancel. At the end the mount is saved for the sender's device in the app's data folder and
// applied at once (the oscInMount setting); Save... writes it elsewhere too. The logic is in
// procedures::MountCalibration; this only shows it. Every control has an accessible title and
// description and takes keyboard focus; each new pose is announced to screen readers.
#include "Procedures/MountCalibration.h"
#include <juce_gui_basics/juce_gui_basics.h>
#include <memory>

namespace armadillo::plugin {

class ArmadilloProcessor;

class MountCalibrationPanel : public juce::Component {
public:
    explicit MountCalibrationPanel(ArmadilloProcessor& processor);
    ~MountCalibrationPanel() override;
    /// Starts a mount calibration (or says why it cannot: the OSC input is off).
    void start();
    void focusInstruction();
    /// The owner's message-thread timer: drains the OSC samples and follows the session. False
    /// when there is nothing to show (the owner hides the panel).
    bool refresh();
    bool wanted() const noexcept { return open_; }
    /// Where the app keeps the mount of `device` (user application data / ARMadillo / mounts).
    static juce::File mountFileFor(const std::string& device);
    void resized() override;
    void paint(juce::Graphics&) override;

private:
    void next();
    void skip();
    void apply();
    void save();
    void close();
    void showStep();
    void announce(const juce::String& text);

    ArmadilloProcessor& processor_;
    procedures::MountCalibration session_;
    juce::Label heading_, instruction_, message_;
    double progressValue_ = 0.0;
    juce::ProgressBar progress_ {progressValue_};
    juce::TextButton next_ {"Next"}, skip_ {"Skip"}, cancel_ {"Cancel"}, save_ {"Save..."};
    std::unique_ptr<juce::FileChooser> chooser_;
    bool open_ = false;
    juce::String shown_;   // heading + instruction last announced
};

} // namespace armadillo::plugin
