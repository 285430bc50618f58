#include "Plugin/MountCalibrationPanel.h"
#include "Plugin/Accessibility.h"
#include "Plugin/PluginProcessor.h"
#include "Link/Mount.h"

namespace armadillo::plugin {

MountCalibrationPanel::MountCalibrationPanel(ArmadilloProcessor& processor) : processor_(processor)
{
    setTitle("Guided mount calibration");
    setDescription("Finds how the OSC sensor is strapped on the forearm from two or three held poses: follow the "
                   "instruction, press Next when the bar is full.");
    setFocusContainerType(FocusContainerType::focusContainer);
    heading_.setFont(juce::Font(15.0f, juce::Font::bold));
    describe(heading_, "Mount calibration pose", "Which pose of the mount calibration runs now.");
    describe(instruction_, "Mount calibration instruction", "How to hold the arm for this pose.");
    instruction_.setJustificationType(juce::Justification::topLeft);
    describe(message_, "Mount calibration message", "Why a pose cannot finish yet, or where the mount was saved.");
    message_.setJustificationType(juce::Justification::topLeft);
    message_.setColour(juce::Label::textColourId, juce::Colour(0xffffc870));
    describe(progress_, "Pose progress", "How many of the still samples this pose needs have arrived.");
    progress_.setPercentageDisplay(false);
    progress_.setColour(juce::ProgressBar::foregroundColourId, juce::Colour(0xff3f9bd8));
    progress_.setColour(juce::ProgressBar::backgroundColourId, juce::Colour(0xff0f151c));
    describe(next_, "Next pose", "Accept this pose and go on; enabled once the pose has enough still samples.");
    next_.onClick = [this] { next(); };
    describe(skip_, "Skip the roll pose", "The third pose is optional: finish with the first two.");
    skip_.onClick = [this] { skip(); };
    describe(cancel_, "Cancel mount calibration", "Stop; the OSC input keeps the mount it had.");
    cancel_.onClick = [this] { close(); };
    describe(save_, "Save mount", "Write the calibrated mount as a JSON file too, and use that file.");
    save_.onClick = [this] { save(); };
    for (juce::Component* c : std::initializer_list<juce::Component*> {&heading_, &instruction_, &progress_, &message_, &next_, &skip_, &save_, &cancel_})
        addAndMakeVisible(*c);
}

MountCalibrationPanel::~MountCalibrationPanel()
{
    if (open_) processor_.oscInput().enableSensorTap(false);
}

juce::File MountCalibrationPanel::mountFileFor(const std::string& device)
{
    return juce::File::getSpecialLocation(juce::File::userApplicationDataDirectory)
        .getChildFile("ARMadillo")
        .getChildFile("mounts")
        .getChildFile(juce::String(procedures::MountCalibration::fileNameForDevice(device)));
}

void MountCalibrationPanel::start()
{
    if (! static_cast<bool>(processor_.settings()[SettingIds::oscInEnabled])) {
        open_ = false;
        announce("Turn OSC input on first: the mount calibration uses the sender's accelerometer.");
        return;
    }
    auto& osc = processor_.oscInput();
    osc.enableSensorTap(true);
    osc::SensorFrameSample stale;
    while (osc.popSensorSample(stale)) {}   // samples from before the start are not a pose
    session_.begin(osc.deviceName());
    open_ = true;
    shown_.clear();
    message_.setText({}, juce::dontSendNotification);
    refresh();
}

void MountCalibrationPanel::focusInstruction()
{
    if (instruction_.isShowing()) instruction_.grabKeyboardFocus();
}

void MountCalibrationPanel::showStep()
{
    heading_.setText(juce::String(session_.stepTitle()), juce::dontSendNotification);
    instruction_.setText(juce::String(session_.instruction()), juce::dontSendNotification);
    const juce::String now = heading_.getText() + ". " + instruction_.getText();
    if (now != shown_) {
        shown_ = now;
        announce(now + " " + message_.getText());
    }
}

bool MountCalibrationPanel::refresh()
{
    if (! open_) return false;
    auto& osc = processor_.oscInput();
    session_.drain([&osc](osc::SensorFrameSample& s) { return osc.popSensorSample(s); });
    showStep();
    const bool finished = session_.finished(), failed = ! session_.failure().empty();
    progressValue_ = finished ? 1.0 : session_.progress();
    next_.setButtonText(failed ? "Start again" : "Next");
    next_.setTitle(failed ? "Start the mount calibration again" : "Next pose");
    next_.setVisible(! finished);
    skip_.setVisible(! finished && ! failed);
    skip_.setEnabled(session_.canSkip());
    save_.setVisible(finished);
    cancel_.setButtonText(finished || failed ? "Close" : "Cancel");
    cancel_.setTitle(finished || failed ? "Close mount calibration" : "Cancel mount calibration");
    const bool ready = failed || session_.ready();
    if (ready != next_.isEnabled()) {
        next_.setEnabled(ready);
        if (ready && ! failed) announce("Pose complete: press Next.");
    }
    return true;
}

void MountCalibrationPanel::next()
{
    if (! session_.failure().empty()) {
        start();
        return;
    }
    std::string why;
    if (session_.next(why)) {
        message_.setText({}, juce::dontSendNotification);
        if (session_.finished()) apply();
    } else {
        message_.setText(juce::String(why), juce::dontSendNotification);
        announce(why);
    }
    refresh();
    if (session_.finished()) save_.grabKeyboardFocus();
}

void MountCalibrationPanel::skip()
{
    std::string why;
    if (session_.skip(why)) apply();
    else announce(why);
    refresh();
    if (session_.finished()) save_.grabKeyboardFocus();
}

void MountCalibrationPanel::apply()
{
    // Kept per device in the app's data folder and used at once (the OSC input reopens with it).
    link::Mount mount = session_.result();
    if (mount.device.empty()) mount.device = processor_.oscInput().deviceName();
    const juce::File file = mountFileFor(mount.device);
    juce::String message;
    try {
        file.getParentDirectory().createDirectory();
        link::saveMount(file.getFullPathName().toStdString(), mount);
        processor_.settings().setProperty(SettingIds::oscInMount, file.getFullPathName(), nullptr);
        message = "Applied; kept for this sender as " + file.getFileName() + " (app data folder, ARMadillo/mounts).";
    } catch (const std::exception& e) {
        message = "Mount found but not saved: " + juce::String(e.what());
    }
    message_.setText(message, juce::dontSendNotification);   // announced with the "done" step by refresh()
    processor_.oscInput().enableSensorTap(false);
}

void MountCalibrationPanel::save()
{
    chooser_ = std::make_unique<juce::FileChooser>(
        "Save mount", juce::File::getSpecialLocation(juce::File::userDocumentsDirectory).getChildFile("armadillo-mount.json"), "*.json");
    chooser_->launchAsync(juce::FileBrowserComponent::saveMode | juce::FileBrowserComponent::canSelectFiles
                              | juce::FileBrowserComponent::warnAboutOverwriting,
                          [this](const juce::FileChooser& fc) {
                              auto file = fc.getResult();
                              if (file == juce::File()) return;
                              if (! file.hasFileExtension("json")) file = file.withFileExtension("json");
                              link::Mount mount = session_.result();
                              if (mount.device.empty()) mount.device = processor_.oscInput().deviceName();
                              juce::String message;
                              try {
                                  link::saveMount(file.getFullPathName().toStdString(), mount);
                                  processor_.settings().setProperty(SettingIds::oscInMount, file.getFullPathName(), nullptr);
                                  message = "Saved as " + file.getFileName() + " and in use.";
                              } catch (const std::exception& e) {
                                  message = "Mount not saved: " + juce::String(e.what());
                              }
                              message_.setText(message, juce::dontSendNotification);
                              announce(message);
                          });
}

void MountCalibrationPanel::close()
{
    session_.cancel();
    processor_.oscInput().enableSensorTap(false);
    open_ = false;
    message_.setText({}, juce::dontSendNotification);
}

void MountCalibrationPanel::announce(const juce::String& text)
{
    plugin::announce(processor_, "mount calibration", text, juce::AccessibilityHandler::AnnouncementPriority::medium);
}

void MountCalibrationPanel::paint(juce::Graphics& g) { paintPanel(g, *this); }

void MountCalibrationPanel::resized()
{
    auto r = getLocalBounds().reduced(6, 4);
    const int row = juce::jmax(14, r.getHeight() / 6);
    const float font = juce::jlimit(12.0f, 20.0f, row * 0.72f);
    heading_.setFont(juce::Font(font + 1.0f, juce::Font::bold));
    instruction_.setFont(juce::Font(font));
    message_.setFont(juce::Font(font * 0.9f));
    heading_.setBounds(r.removeFromTop(row));
    auto buttons = r.removeFromBottom(row);
    progress_.setBounds(r.removeFromBottom(row).reduced(0, 2));
    message_.setBounds(r.removeFromBottom(row));
    instruction_.setBounds(r);
    const int w = buttons.getWidth() / 3;
    next_.setBounds(buttons.removeFromLeft(w).reduced(2, 0));
    save_.setBounds(next_.getBounds());
    skip_.setBounds(buttons.removeFromLeft(w).reduced(2, 0));
    cancel_.setBounds(buttons.reduced(2, 0));
}

} // namespace armadillo::plugin
