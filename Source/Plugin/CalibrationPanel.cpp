#include "Plugin/CalibrationPanel.h"
#include "Plugin/Accessibility.h"
#include "Plugin/PluginProcessor.h"

namespace armadillo::plugin {

namespace {
/// The largest font (from `base` down to 9 px) in which `label`'s text fits its bounds, so a long
/// instruction stays whole in a small editor instead of ending in "...".
void fitText(juce::Label& label, float base)
{
    const auto area = label.getLocalBounds().reduced(label.getBorderSize().getLeft(), label.getBorderSize().getTop());
    if (area.isEmpty()) return;
    float size = base;
    for (; size > 9.0f; size -= 0.5f) {
        juce::AttributedString text(label.getText());
        text.setFont(juce::Font(size));
        juce::TextLayout layout;
        layout.createLayout(text, static_cast<float>(area.getWidth()) * 0.95f);   // Label wraps a little tighter
        if (layout.getHeight() + size * 0.5f <= static_cast<float>(area.getHeight())) break;
    }
    label.setFont(juce::Font(size));
}
} // namespace

CalibrationPanel::CalibrationPanel(ArmadilloProcessor& processor) : processor_(processor)
{
    setTitle("Guided calibration");
    setDescription("Calibrates the connected device step by step: follow the instruction, press Next when the bar is full.");
    setFocusContainerType(FocusContainerType::focusContainer);

    heading_.setFont(juce::Font(15.0f, juce::Font::bold));
    describe(heading_, "Calibration step", "Which calibration step runs now.");
    // A label's accessible title is its text, so a screen reader reads the instruction itself.
    describe(instruction_, "Calibration instruction", "What to do with the arm in this step.");
    instruction_.setJustificationType(juce::Justification::topLeft);
    instruction_.setMinimumHorizontalScale(0.9f);
    describe(message_, "Calibration message", "Why a step cannot finish yet, or where the calibration was saved.");
    message_.setJustificationType(juce::Justification::topLeft);
    message_.setColour(juce::Label::textColourId, juce::Colour(0xffffc870));
    describe(progress_, "Step progress", "How much of the data this step needs has been measured.");
    progress_.setPercentageDisplay(false);   // too small to read at this height; screen readers get the value
    progress_.setColour(juce::ProgressBar::foregroundColourId, juce::Colour(0xff3f9bd8));
    progress_.setColour(juce::ProgressBar::backgroundColourId, juce::Colour(0xff0f151c));

    describe(next_, "Next calibration step", "Accept this step's measurement and go on; enabled once the step has enough data.");
    next_.onClick = [this] { next(); };
    describe(skip_, "Skip calibration step", "Keep the current numbers for this step and go on.");
    skip_.onClick = [this] {
        processor_.calibrationSkip();
        message_.setText({}, juce::dontSendNotification);
        refresh();
    };
    describe(cancel_, "Cancel calibration", "Stop the calibration; the device keeps the calibration it had.");
    cancel_.onClick = [this] { close(); };
    describe(save_, "Save calibration", "Write the new calibration as a JSON file; the next connection loads it.");
    save_.onClick = [this] { save(); };

    for (juce::Component* c : std::initializer_list<juce::Component*> {&heading_, &instruction_, &progress_, &message_, &next_, &skip_, &save_, &cancel_})
        addAndMakeVisible(*c);
    // A calibration outlives a closed editor (the processor keeps feeding it): a reopened
    // editor shows it again instead of offering a fresh start.
    open_ = processor_.calibration().running() || processor_.calibration().finished();
}

void CalibrationPanel::start()
{
    juce::String why;
    if (! processor_.beginCalibration(why)) {
        open_ = false;
        announce(why);   // the owner shows it too (link statistics); screen readers hear it now
        return;
    }
    open_ = true;
    shownStep_ = -1;
    message_.setText({}, juce::dontSendNotification);
    refresh();
}

void CalibrationPanel::focusInstruction()
{
    // Next is disabled until the step has data: the instruction is what to read first.
    if (instruction_.isShowing()) instruction_.grabKeyboardFocus();
}

bool CalibrationPanel::refresh()
{
    if (! open_) return false;
    const auto& session = processor_.calibration();
    if (! session.running() && ! session.finished()) {
        // Cancelled under us (the device was disconnected).
        open_ = false;
        return false;
    }
    const int step = session.stepNumber();
    if (step != shownStep_) {
        shownStep_ = step;
        heading_.setText(juce::String(session.stepTitle()), juce::dontSendNotification);
        if (session.finished()) {
            juce::String skipped;
            for (int k = 0; k < procedures::DeviceCalibration::kStepCount; ++k) {
                const auto st = static_cast<procedures::DeviceCalibration::Step>(k);
                // The level magnetometer circle only feeds the vertical one: not a result of its own.
                if (st != procedures::DeviceCalibration::Step::MagHorizontal && ! session.measured(st))
                    skipped << (skipped.isEmpty() ? "" : ", ") << procedures::DeviceCalibration::shortLabel(st);
            }
            instruction_.setText("Applied to the device. "
                                     + (skipped.isEmpty() ? juce::String("Every step was measured.")
                                                          : "Skipped, so kept from before: " + skipped + "."),
                                 juce::dontSendNotification);
            message_.setText("Save it to load it on the next connection.", juce::dontSendNotification);
        } else {
            instruction_.setText(juce::String(session.instruction()), juce::dontSendNotification);
            // The turn steps fill their bar at half a turn (the procedure's minimum), but the
            // scale is 2π over the whole turn: Next belongs after the full turn.
            const auto st = session.step();
            const bool turn = st == procedures::DeviceCalibration::Step::GyroTurnX || st == procedures::DeviceCalibration::Step::GyroTurnY
                              || st == procedures::DeviceCalibration::Step::GyroTurnZ;
            message_.setText(turn ? "Press Next only after the whole turn, with the arm still." : "", juce::dontSendNotification);
        }
        fitText(instruction_, baseFont_);
        announce(heading_.getText() + ". " + instruction_.getText() + " " + message_.getText());
    }
    const bool finished = session.finished();
    progressValue_ = finished ? 1.0 : session.progress();
    next_.setVisible(! finished);
    skip_.setVisible(! finished);
    save_.setVisible(finished);
    cancel_.setButtonText(finished ? "Close" : "Cancel");
    cancel_.setTitle(finished ? "Close calibration" : "Cancel calibration");
    cancel_.setDescription(finished ? "Close the calibration; the device keeps the new calibration."
                                    : "Stop the calibration; the device keeps the calibration it had.");
    const bool ready = session.ready();
    if (ready != next_.isEnabled()) {
        next_.setEnabled(ready);
        if (ready) announce("Step complete: press Next.");
    }
    return true;
}

void CalibrationPanel::next()
{
    juce::String why;
    if (! processor_.calibrationNext(why)) {
        message_.setText(why, juce::dontSendNotification);
        announce(why);
    } else {
        message_.setText({}, juce::dontSendNotification);
    }
    refresh();
    if (processor_.calibration().finished()) save_.grabKeyboardFocus();
}

void CalibrationPanel::save()
{
    chooser_ = std::make_unique<juce::FileChooser>(
        "Save calibration", juce::File::getSpecialLocation(juce::File::userDocumentsDirectory).getChildFile("armadillo-calibration.json"), "*.json");
    chooser_->launchAsync(juce::FileBrowserComponent::saveMode | juce::FileBrowserComponent::canSelectFiles
                              | juce::FileBrowserComponent::warnAboutOverwriting,
                          [this](const juce::FileChooser& fc) {
                              auto file = fc.getResult();
                              if (file == juce::File()) return;   // dismissed
                              if (! file.hasFileExtension("json")) file = file.withFileExtension("json");
                              juce::String message;
                              processor_.saveCalibration(file, message);
                              message_.setText(message, juce::dontSendNotification);
                              announce(message);
                          });
}

void CalibrationPanel::close()
{
    processor_.cancelCalibration();
    open_ = false;
    message_.setText({}, juce::dontSendNotification);
}

void CalibrationPanel::announce(const juce::String& text)
{
    plugin::announce(processor_, "calibration", text, juce::AccessibilityHandler::AnnouncementPriority::medium);
}

void CalibrationPanel::paint(juce::Graphics& g) { paintPanel(g, *this); }

void CalibrationPanel::resized()
{
    auto r = getLocalBounds().reduced(6, 4);
    // Six rows: heading, instruction (two), message, progress, buttons.
    const int row = juce::jmax(14, r.getHeight() / 6);
    const float font = juce::jlimit(12.0f, 20.0f, row * 0.72f);
    heading_.setFont(juce::Font(font + 1.0f, juce::Font::bold));
    baseFont_ = font;
    message_.setFont(juce::Font(font));
    heading_.setBounds(r.removeFromTop(row));
    auto buttons = r.removeFromBottom(row);
    progress_.setBounds(r.removeFromBottom(row).reduced(0, 2));
    message_.setBounds(r.removeFromBottom(row));
    instruction_.setBounds(r);
    fitText(instruction_, baseFont_);
    const int w = buttons.getWidth() / 3;
    next_.setBounds(buttons.removeFromLeft(w).reduced(2, 0));
    save_.setBounds(next_.getBounds());
    skip_.setBounds(buttons.removeFromLeft(w).reduced(2, 0));
    cancel_.setBounds(buttons.reduced(2, 0));
}

} // namespace armadillo::plugin
