#include "Plugin/DevicePanel.h"
#include "Plugin/Accessibility.h"
#include "Plugin/PluginProcessor.h"
#include "Link/LinkPort.h"
#include "Link/Mount.h"
#include "Osc/OscDialects.h"

namespace armadillo::plugin {

DevicePanel::DevicePanel(ArmadilloProcessor& processor)
    : processor_(processor), calibrationPanel_(processor), mountPanel_(processor)
{
    auto& settings = processor_.settings();
    deviceHeading_.setText("Device", juce::dontSendNotification);
    oscHeading_.setText("OSC (Max/MSP, Pd)", juce::dontSendNotification);
    for (auto* l : {&deviceHeading_, &oscHeading_}) {
        l->setFont(juce::Font(15.0f, juce::Font::bold));
        addAndMakeVisible(*l);
    }

    describe(port_, "Serial port", "The serial port of the ARMadillo board (thesis protocol, 57600 baud).");
    port_.setTextWhenNothingSelected("choose a port");
    port_.setTextWhenNoChoicesAvailable("no serial ports found");
    port_.onChange = [this] {
        processor_.settings().setProperty(SettingIds::serialPort, port_.getText(), nullptr);
    };
    describe(rescan_, "Rescan ports", "Look for serial ports again.");
    rescan_.onClick = [this] { rescanPorts(); };
    describe(connect_, "Connect device", "Open the chosen port; only one ARMadillo instance may own a port.");
    connect_.onClick = [this] { processor_.connectDevice(! processor_.deviceConnected()); timerCallback(); };
    describe(calibration_, "Calibration file", "Choose the device's calibration JSON file (INTERFACES.md).");
    calibration_.onClick = [this] { chooseCalibration(); };
    describe(calibrate_, "Calibrate device",
             "Guided calibration of the connected device (or the simulated forearm): seven steps of holding and "
             "turning the arm; the result applies at once and can be saved as a calibration file.");
    calibrate_.onClick = [this] { startCalibration(); };
    calibrationFile_.setTitle("Calibration file name");
    link_.setTitle("Link statistics");
    link_.setJustificationType(juce::Justification::topLeft);
    link_.setFont(juce::Font(13.0f));

    describe(side_, "Arm side", "Which forearm wears the device; the left arm mirrors the motor columns.");
    side_.addItem("Right arm", 1);
    side_.addItem("Left arm", 2);
    side_.setSelectedId(settings[SettingIds::armSide].toString() == "left" ? 2 : 1, juce::dontSendNotification);
    side_.onChange = [this] {
        processor_.settings().setProperty(SettingIds::armSide, side_.getSelectedId() == 2 ? "left" : "right", nullptr);
    };
    describe(backMotors_, "Back motors", "Drive the three optional back motors (motors 10 to 12).");
    backMotors_.getToggleStateValue().referTo(settings.getPropertyAsValue(SettingIds::backMotors, nullptr));

    describe(connectOnStart_, "Connect on start", "Open the chosen port by itself when the source is device.");
    connectOnStart_.getToggleStateValue().referTo(settings.getPropertyAsValue(SettingIds::connectOnStart, nullptr));
    describe(oscOut_, "OSC output", "Send /armadillo/orientation, pose, gyro, motors and gesture messages.");
    oscOut_.getToggleStateValue().referTo(settings.getPropertyAsValue(SettingIds::oscOutEnabled, nullptr));
    describe(oscHost_, "OSC output host", "Host name or address the OSC messages go to.");
    oscHost_.getTextValue().referTo(settings.getPropertyAsValue(SettingIds::oscOutHost, nullptr));
    describe(oscPort_, "OSC output port", "UDP port the OSC messages go to.");
    oscPort_.setInputRestrictions(5, "0123456789");
    oscPort_.getTextValue().referTo(settings.getPropertyAsValue(SettingIds::oscOutPort, nullptr));
    describe(oscIn_, "OSC input", "Listen for a phone sensor app, an NGIMU or ARMadillo's own /armadillo messages (source OSC).");
    oscIn_.getToggleStateValue().referTo(settings.getPropertyAsValue(SettingIds::oscInEnabled, nullptr));
    describe(oscInPort_, "OSC input port", "UDP port to listen on.");
    oscInPort_.setInputRestrictions(5, "0123456789");
    oscInPort_.getTextValue().referTo(settings.getPropertyAsValue(SettingIds::oscInPort, nullptr));
    describe(leftArmOsc_, "Left arm OSC input",
             "Listen for a second OSC sender as the left arm: two-arm scenes such as theremin-duo hear both arms, "
             "and the mapping's left and arms sources send.");
    leftArmOsc_.getToggleStateValue().referTo(settings.getPropertyAsValue(SettingIds::leftArmOsc, nullptr));
    describe(leftArmPort_, "Left arm OSC input port", "UDP port the left arm's sender sends to.");
    leftArmPort_.setInputRestrictions(5, "0123456789");
    leftArmPort_.getTextValue().referTo(settings.getPropertyAsValue(SettingIds::leftArmOscPort, nullptr));
    leftPortLabel_.setText("port", juce::dontSendNotification);
    leftPortLabel_.attachToComponent(&leftArmPort_, true);
    hostLabel_.setText("host", juce::dontSendNotification);
    portLabel_.setText("port", juce::dontSendNotification);
    inPortLabel_.setText("port", juce::dontSendNotification);
    describe(oscFormat_, "OSC sender format",
             "Which app or sensor sends: auto detects it from the first messages; choose one to accept only its messages.");
    oscFormat_.addItem("auto (detect)", 1);
    for (int i = 1; i < osc::kOscFormatCount; ++i) oscFormat_.addItem(osc::oscFormatName(static_cast<osc::OscFormat>(i)), i + 1);
    oscFormat_.onChange = [this] {
        const int id = oscFormat_.getSelectedId();
        processor_.settings().setProperty(SettingIds::oscInFormat, id <= 1 ? juce::String() : oscFormat_.getItemText(id - 1), nullptr);
    };
    describe(oscMount_, "Sensor mount",
             "How the sensor is strapped on the forearm: the sender's usual way, a preset, or a mount file (Mount file... or "
             "Calibrate mount...).");
    mountPresets_.addTokens(juce::String(link::mountPresetNames()), ", ", "");
    mountPresets_.removeEmptyStrings();
    oscMount_.onChange = [this] {
        const int id = oscMount_.getSelectedId();
        mountFileError_.clear();
        if (id == 1) processor_.settings().setProperty(SettingIds::oscInMount, juce::String(), nullptr);
        else if (id >= 2 && id < 2 + mountPresets_.size())
            processor_.settings().setProperty(SettingIds::oscInMount, mountPresets_[id - 2], nullptr);
        // The file item stands for the file already set.
    };
    describe(mountFile_, "Mount file", "Load a mount JSON file (armadillo play --calibrate-mount or Calibrate mount... writes one).");
    mountFile_.onClick = [this] { chooseMountFile(); };
    describe(calibrateMount_, "Calibrate mount",
             "Guided mount calibration of the OSC sensor: hold the arm level ahead, then hanging down, optionally rolled; the "
             "mount applies at once and is kept for that sender.");
    calibrateMount_.onClick = [this] { startMountCalibration(); };
    oscStatus_.setTitle("OSC input status");
    oscStatus_.setDescription("The detected sender format, device and mount, and the messages refused by kind.");
    oscStatus_.setJustificationType(juce::Justification::topLeft);
    formatLabel_.setText("format", juce::dontSendNotification);
    mountLabel_.setText("mount", juce::dontSendNotification);
    formatLabel_.attachToComponent(&oscFormat_, true);
    mountLabel_.attachToComponent(&oscMount_, true);
    syncOscChoices();
    hostLabel_.attachToComponent(&oscHost_, true);
    portLabel_.attachToComponent(&oscPort_, true);
    inPortLabel_.attachToComponent(&oscInPort_, true);

    for (juce::Component* c : std::initializer_list<juce::Component*> {&port_, &rescan_, &connect_, &calibration_, &calibrate_, &calibrationFile_, &connectOnStart_,
                                &side_, &backMotors_, &link_, &oscOut_, &oscHost_, &oscPort_, &oscIn_, &oscInPort_,
                                &oscFormat_, &oscMount_, &mountFile_, &calibrateMount_, &leftArmOsc_, &leftArmPort_, &oscStatus_})
        addAndMakeVisible(*c);
    addChildComponent(calibrationPanel_);
    addChildComponent(mountPanel_);
    setFocusContainerType(FocusContainerType::focusContainer);
    setTitle("Device and OSC settings");
    rescanPorts();
    timerCallback();
    startTimerHz(5);
}

DevicePanel::~DevicePanel() = default;

void DevicePanel::rescanPorts()
{
    const auto current = processor_.settings()[SettingIds::serialPort].toString();
    port_.clear(juce::dontSendNotification);
    int id = 1, selected = 0;
    std::vector<link::PortInfo> ports;
    try {
        ports = link::listSerialPorts();
    } catch (const std::exception&) {
        // No enumeration (no sysfs, no permission): the simulated forearm is still offered.
    }
    std::vector<juce::String> names {live::DeviceConnection::kSimulatedPort};
    for (const auto& p : ports) names.push_back(juce::String(p.name));
    for (const auto& name : names) {
        port_.addItem(name, id);
        if (name == current) selected = id;
        ++id;
    }
    if (selected == 0 && current.isNotEmpty()) {
        port_.addItem(current, id);   // remembered port, not present now
        selected = id;
    }
    if (selected != 0) port_.setSelectedId(selected, juce::dontSendNotification);
}

void DevicePanel::chooseCalibration()
{
    chooser_ = std::make_unique<juce::FileChooser>("Calibration file", juce::File(), "*.json");
    chooser_->launchAsync(juce::FileBrowserComponent::openMode | juce::FileBrowserComponent::canSelectFiles,
                          [this](const juce::FileChooser& fc) {
                              const auto file = fc.getResult();
                              if (file != juce::File())
                                  processor_.settings().setProperty(SettingIds::calibrationFile, file.getFullPathName(), nullptr);
                              timerCallback();
                          });
}

void DevicePanel::startCalibration()
{
    calibrationPanel_.start();
    timerCallback();
    calibrationPanel_.focusInstruction();
}

void DevicePanel::syncOscChoices()
{
    const auto& settings = processor_.settings();
    const auto format = settings[SettingIds::oscInFormat].toString();
    int formatId = 1;
    for (int i = 1; i < oscFormat_.getNumItems(); ++i)
        if (oscFormat_.getItemText(i).equalsIgnoreCase(format)) formatId = i + 1;
    if (oscFormat_.getSelectedId() != formatId) oscFormat_.setSelectedId(formatId, juce::dontSendNotification);

    const auto mount = settings[SettingIds::oscInMount].toString();
    const int presetIndex = mountPresets_.indexOf(mount);
    const juce::String fileItem = (mount.isEmpty() || presetIndex >= 0) ? juce::String() : "file: " + juce::File(mount).getFileName();
    const int fileId = 2 + mountPresets_.size();
    const bool itemsOk = oscMount_.getNumItems() == (fileItem.isEmpty() ? fileId - 1 : fileId)
                         && (fileItem.isEmpty() || oscMount_.getItemText(fileId - 1) == fileItem);
    if (! itemsOk) {
        oscMount_.clear(juce::dontSendNotification);
        oscMount_.addItem("usual for the format", 1);
        for (int i = 0; i < mountPresets_.size(); ++i) oscMount_.addItem(mountPresets_[i], i + 2);
        if (fileItem.isNotEmpty()) oscMount_.addItem(fileItem, fileId);
    }
    const int mountId = mount.isEmpty() ? 1 : presetIndex >= 0 ? presetIndex + 2 : fileId;
    if (oscMount_.getSelectedId() != mountId) oscMount_.setSelectedId(mountId, juce::dontSendNotification);
}

void DevicePanel::chooseMountFile()
{
    chooser_ = std::make_unique<juce::FileChooser>("Mount file", juce::File(), "*.json");
    chooser_->launchAsync(juce::FileBrowserComponent::openMode | juce::FileBrowserComponent::canSelectFiles,
                          [this](const juce::FileChooser& fc) {
                              const auto file = fc.getResult();
                              if (file == juce::File()) return;
                              try {
                                  (void) link::loadMount(file.getFullPathName().toStdString());   // a clear refusal now, not later
                                  processor_.settings().setProperty(SettingIds::oscInMount, file.getFullPathName(), nullptr);
                                  mountFileError_.clear();
                              } catch (const std::exception& e) {
                                  mountFileError_ = "Mount file not used: " + juce::String(e.what());
                                  announce(processor_, "mount", mountFileError_, juce::AccessibilityHandler::AnnouncementPriority::high);
                                  timerCallback();
                                  return;
                              }
                              timerCallback();
                          });
}

void DevicePanel::startMountCalibration()
{
    mountPanel_.start();
    timerCallback();
    mountPanel_.focusInstruction();
}

void DevicePanel::timerCallback()
{
    // The calibration panel replaces the link statistics and OSC rows while it is wanted.
    const bool showCalibration = calibrationPanel_.refresh();
    const bool showMount = mountPanel_.refresh();
    calibrate_.setEnabled(processor_.deviceConnected() && ! showCalibration && ! showMount);
    calibrateMount_.setEnabled(static_cast<bool>(processor_.settings()[SettingIds::oscInEnabled]) && ! showCalibration && ! showMount);
    if (showCalibration != calibrating_ || showMount != mountCalibrating_) {
        const bool wasMount = mountCalibrating_;
        calibrating_ = showCalibration;
        mountCalibrating_ = showMount && ! showCalibration;
        calibrationPanel_.setVisible(calibrating_);
        mountPanel_.setVisible(mountCalibrating_);
        const bool either = calibrating_ || mountCalibrating_;
        for (juce::Component* c : std::initializer_list<juce::Component*> {&link_, &oscHeading_, &oscOut_, &oscHost_, &oscPort_, &oscIn_, &oscInPort_,
                                                                            &hostLabel_, &portLabel_, &inPortLabel_, &oscFormat_, &oscMount_,
                                                                            &formatLabel_, &mountLabel_, &mountFile_, &calibrateMount_, &oscStatus_,
                                                                            &leftArmOsc_, &leftArmPort_, &leftPortLabel_})
            c->setVisible(! either);
        if (either) startTimerHz(20); else startTimerHz(5);   // the Next button follows the data promptly
        resized();
        // Back from a calibration: focus returns to where it started (unless the device went away).
        if (! calibrating_ && ! wasMount && calibrate_.isShowing() && calibrate_.isEnabled()) calibrate_.grabKeyboardFocus();
        if (! mountCalibrating_ && wasMount && calibrateMount_.isShowing()) calibrateMount_.grabKeyboardFocus();
    }
    connect_.setButtonText(processor_.deviceConnected() ? "Disconnect" : "Connect");
    const auto cal = processor_.settings()[SettingIds::calibrationFile].toString();
    calibrationFile_.setText(cal.isEmpty() ? "no calibration file" : juce::File(cal).getFileName(), juce::dontSendNotification);
    // The OSC input's own line (format, device, mount, refusals) sits in the OSC section; the
    // link statistics show everything else.
    const juce::String oscLine(processor_.oscInput().statusText());
    juce::StringArray lines;
    lines.addLines(processor_.linkStatus());
    for (int i = lines.size(); --i >= 0;)
        if (lines[i] == "OSC input off" || (lines[i].startsWith("OSC in: ") && lines[i].contains("; refused ")))
            lines.remove(i);
    link_.setText(lines.joinIntoString("\n"), juce::dontSendNotification);
    oscStatus_.setText(mountFileError_.isEmpty() ? oscLine : mountFileError_ + "\n" + oscLine, juce::dontSendNotification);
    syncOscChoices();
}

void DevicePanel::paint(juce::Graphics& g)
{
    g.fillAll(juce::Colour(0xff161c24));
}

void DevicePanel::resized()
{
    auto r = getLocalBounds().reduced(6);
    // Twelve rows (the link statistics and the OSC status take two each): fit them all, whatever the height.
    const int row = juce::jlimit(16, 40, (r.getHeight() - 33) / 12);
    auto line = [&] { auto l = r.removeFromTop(row); r.removeFromTop(3); return l; };
    deviceHeading_.setBounds(line());
    auto l1 = line();
    rescan_.setBounds(l1.removeFromRight(l1.getWidth() / 5));
    l1.removeFromRight(4);
    connect_.setBounds(l1.removeFromRight(l1.getWidth() / 3));
    l1.removeFromRight(4);
    port_.setBounds(l1);
    auto l2 = line();
    const int third = l2.getWidth() / 3;
    calibration_.setBounds(l2.removeFromLeft(third - 3));
    l2.removeFromLeft(6);
    calibrate_.setBounds(l2.removeFromLeft(third - 3));
    l2.removeFromLeft(6);
    calibrationFile_.setBounds(l2);
    auto l3 = line();
    const int thirds = l3.getWidth() / 3;
    side_.setBounds(l3.removeFromLeft(thirds - 3));
    l3.removeFromLeft(6);
    backMotors_.setBounds(l3.removeFromLeft(thirds));
    connectOnStart_.setBounds(l3);
    if (calibrating_ || mountCalibrating_) {
        // Link statistics (three rows) and the OSC section make room for the steps.
        (calibrating_ ? static_cast<juce::Component&>(calibrationPanel_) : mountPanel_).setBounds(r.removeFromTop(row * 8 + 18));
        return;
    }
    link_.setBounds(r.removeFromTop(row * 2));
    link_.setFont(juce::Font(juce::jlimit(11.0f, 18.0f, row * 0.55f)));
    oscHeading_.setBounds(line());
    auto l4 = line();
    oscOut_.setBounds(l4.removeFromLeft(l4.getWidth() / 4));
    l4.removeFromLeft(40);
    auto hostArea = l4.removeFromLeft(l4.getWidth() * 3 / 5);
    oscHost_.setBounds(hostArea);
    l4.removeFromLeft(40);
    oscPort_.setBounds(l4);
    auto l5 = line();
    oscIn_.setBounds(l5.removeFromLeft(l5.getWidth() / 4));
    l5.removeFromLeft(40);
    oscInPort_.setBounds(l5.removeFromLeft(l5.getWidth() / 4));
    l5.removeFromLeft(56);   // the "format" label
    oscFormat_.setBounds(l5);
    auto l6 = line();
    l6.removeFromLeft(50);   // the "mount" label
    oscMount_.setBounds(l6.removeFromLeft(l6.getWidth() * 2 / 5));
    l6.removeFromLeft(6);
    mountFile_.setBounds(l6.removeFromLeft(l6.getWidth() / 2 - 3));
    l6.removeFromLeft(6);
    calibrateMount_.setBounds(l6);
    auto l7 = line();
    leftArmOsc_.setBounds(l7.removeFromLeft(l7.getWidth() / 4));
    l7.removeFromLeft(40);
    leftArmPort_.setBounds(l7.removeFromLeft(l7.getWidth() / 4));
    oscStatus_.setBounds(r.removeFromTop(row * 2 + 3));
    oscStatus_.setFont(juce::Font(juce::jlimit(11.0f, 16.0f, row * 0.5f)));
}

} // namespace armadillo::plugin
