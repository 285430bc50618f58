#pragma once
// The guided calibration in the device panel (thesis §2.4): the current step's instruction, a
// progress bar, Next (enabled once the step has enough data), Skip and Cancel; at the end the
// result is already applied to the link and Save... writes it as calibration JSON. All logic is
// in procedures::DeviceCalibration / the processor; this only shows it. Every control has an accessible
// title and description and takes keyboard focus; each new step is announced to screen readers.
#include "Procedures/DeviceCalibration.h"
#include <juce_gui_basics/juce_gui_basics.h>
#include <memory>

namespace armadillo::plugin {

class ArmadilloProcessor;

class CalibrationPanel : public juce::Component {
public:
    explicit CalibrationPanel(ArmadilloProcessor& processor);
    /// Starts a calibration (or says why it cannot) and shows the first step.
    void start();
    /// Keyboard (and screen reader) focus to the instruction, once the panel is visible.
    void focusInstruction();
    /// Message-thread timer of the owner: follows the procedure. Returns false when there is
    /// nothing to show any more (the owner hides the panel).
    bool refresh();
    /// Shown while a calibration runs or its result waits to be saved / closed.
    bool wanted() const noexcept { return open_; }
    void resized() override;
    void paint(juce::Graphics&) override;

private:
    void next();
    void save();
    void close();
    void announce(const juce::String& text);

    ArmadilloProcessor& processor_;
    juce::Label heading_, instruction_, message_;
    double progressValue_ = 0.0;   // read by the progress bar on its own repaint timer
    juce::ProgressBar progress_ {progressValue_};
    juce::TextButton next_ {"Next"}, skip_ {"Skip"}, cancel_ {"Cancel"}, save_ {"Save..."};
    std::unique_ptr<juce::FileChooser> chooser_;
    bool open_ = false;
    int shownStep_ = -1;   // the step last announced
    float baseFont_ = 14.0f;   // px: the panel's text size; the instruction shrinks below it only to fit
};

} // namespace armadillo::plugin
