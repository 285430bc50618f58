#include "Plugin/DevicePanel.h"
#include "Plugin/Accessibility.h"
#include "Plugin/PluginProcessor.h"
#include "Device/LinkPort.h"

namespace armadillo::plugin {

DevicePanel::DevicePanel(ArmadilloProcessor& processor) : processor_(processor), calibrationPanel_(processor)
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
    describe(oscIn_, "OSC input", "Listen for /armadillo/orientation or /armadillo/imu (source OSC).");
    oscIn_.getToggleStateValue().referTo(settings.getPropertyAsValue(SettingIds::oscInEnabled, nullptr));
    describe(oscInPort_, "OSC input port", "UDP port to listen on.");
    oscInPort_.setInputRestrictions(5, "0123456789");
    oscInPort_.getTextValue().referTo(settings.getPropertyAsValue(SettingIds::oscInPort, nullptr));
    hostLabel_.setText("host", juce::dontSendNotification);
    portLabel_.setText("port", juce::dontSendNotification);
    inPortLabel_.setText("port", juce::dontSendNotification);
    hostLabel_.attachToComponent(&oscHost_, true);
    portLabel_.attachToComponent(&oscPort_, true);
    inPortLabel_.attachToComponent(&oscInPort_, true);

    for (juce::Component* c : std::initializer_list<juce::Component*> {&port_, &rescan_, &connect_, &calibration_, &calibrate_, &calibrationFile_, &connectOnStart_,
                                &side_, &backMotors_, &link_, &oscOut_, &oscHost_, &oscPort_, &oscIn_, &oscInPort_})
        addAndMakeVisible(*c);
    addChildComponent(calibrationPanel_);
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
    std::vector<device::PortInfo> ports;
    try {
        ports = device::listSerialPorts();
    } catch (const std::exception&) {
        // No enumeration (no sysfs, no permission): the simulated forearm is still offered.
    }
    std::vector<juce::String> names {DeviceConnection::kSimulatedPort};
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

void DevicePanel::timerCallback()
{
    // The calibration panel replaces the link statistics and OSC rows while it is wanted.
    const bool showCalibration = calibrationPanel_.refresh();
    calibrate_.setEnabled(processor_.deviceConnected() && ! showCalibration);
    if (showCalibration != calibrating_) {
        calibrating_ = showCalibration;
        calibrationPanel_.setVisible(calibrating_);
        for (juce::Component* c : std::initializer_list<juce::Component*> {&link_, &oscHeading_, &oscOut_, &oscHost_, &oscPort_, &oscIn_, &oscInPort_,
                                                                            &hostLabel_, &portLabel_, &inPortLabel_})
            c->setVisible(! calibrating_);
        if (calibrating_) startTimerHz(20); else startTimerHz(5);   // the Next button follows the data promptly
        resized();
        // Back from the calibration: focus returns to where it started (unless the device went away).
        if (! calibrating_ && calibrate_.isShowing() && calibrate_.isEnabled()) calibrate_.grabKeyboardFocus();
    }
    connect_.setButtonText(processor_.deviceConnected() ? "Disconnect" : "Connect");
    const auto cal = processor_.settings()[SettingIds::calibrationFile].toString();
    calibrationFile_.setText(cal.isEmpty() ? "no calibration file" : juce::File(cal).getFileName(), juce::dontSendNotification);
    link_.setText(processor_.linkStatus(), juce::dontSendNotification);
}

void DevicePanel::paint(juce::Graphics& g)
{
    g.fillAll(juce::Colour(0xff161c24));
}

void DevicePanel::resized()
{
    auto r = getLocalBounds().reduced(6);
    // Eleven rows (the link statistics take three): fit them all, whatever the height.
    const int row = juce::jlimit(16, 40, (r.getHeight() - 30) / 11);
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
    if (calibrating_) {
        // Link statistics (three rows) and the OSC section (three rows) make room for the steps.
        calibrationPanel_.setBounds(r.removeFromTop(row * 6 + 9));
        return;
    }
    link_.setBounds(r.removeFromTop(row * 3));
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
    oscInPort_.setBounds(l5.removeFromLeft(l5.getWidth() / 3));
}

} // namespace armadillo::plugin
