#include "Plugin/WelcomePanel.h"
#include "Plugin/Accessibility.h"
#include "Plugin/PluginProcessor.h"
#include "Plugin/StandaloneAccess.h"
#include <cmath>

namespace armadillo::plugin {

namespace {
std::unique_ptr<juce::PropertiesFile> appSettings()
{
    juce::PropertiesFile::Options o;
    o.applicationName = "app";
    o.filenameSuffix = ".settings";
    o.folderName = ".config/armadillo";   // Linux: ~/.config/armadillo/app.settings
    o.osxLibrarySubFolder = "Application Support";
    return std::make_unique<juce::PropertiesFile>(o);
}
constexpr const char* kShowWelcome = "showWelcomeAtStart";
} // namespace

bool WelcomePanel::showAtStart()
{
    return appSettings()->getBoolValue(kShowWelcome, true);
}

void WelcomePanel::setShowAtStart(bool show)
{
    auto file = appSettings();
    file->setValue(kShowWelcome, show);
    file->saveIfNeeded();
}

WelcomePanel::WelcomePanel(ArmadilloProcessor& processor) : processor_(processor)
{
    setTitle("Welcome");
    setDescription("What ARMadillo is playing now, how to hear it, how to connect an arm or a phone, and the audio input.");
    heading_.setText("Welcome to ARMadillo", juce::dontSendNotification);
    heading_.setFont(juce::Font(20.0f, juce::Font::bold));
    describe(heading_, "Welcome to ARMadillo", "The first steps: press Tab to go through them, Escape to close.");
    describe(playing_, "Playing now", "Which source moves the arm now.");
    describe(hearing_, "Hearing it", "The audio output in use, and the test tone.");
    describe(connecting_, "Connecting an arm or a phone", "Where to connect a real ARMadillo arm or a phone's sensors.");
    describe(input_, "Audio input", "Whether the audio input is on; the score and audio-touch scenes listen to it.");
    describe(keys_, "Keyboard", "How to use the app with the keyboard.");
    for (auto* l : {&playing_, &hearing_, &connecting_, &input_, &keys_}) {
        l->setJustificationType(juce::Justification::topLeft);
        l->setMinimumHorizontalScale(1.0f);
    }
    describe(testTone_, "Test tone", "Plays a 440 hertz tone for one second on the output: you should hear it.");
    testTone_.onClick = [this] {
        processor_.playTestTone(1.0);
        refresh();
    };
    describe(audioSettings_, "Audio settings", "Choose the sound card, output, input and sample rate.");
    audioSettings_.onClick = [] { showStandaloneAudioSettings(); };
    describe(device_, "Go to the device panel", "Closes the welcome and puts the focus on the serial port list.");
    device_.onClick = [this] {
        close();
        if (onShowDevice) onShowDevice();
    };
    describe(osc_, "Go to the OSC input", "Closes the welcome and puts the focus on the OSC input switch, for a phone sensor app.");
    osc_.onClick = [this] {
        close();
        if (onShowOsc) onShowOsc();
    };
    describe(unmute_, "Unmute the audio input", "The app starts with its input muted (against feedback); the listening scenes need it.");
    unmute_.onClick = [this] {
        setStandaloneInputMuted(false);
        refresh();
    };
    describe(atStart_, "Show this at start", "Show this welcome each time the app starts.");
    atStart_.setToggleState(showAtStart(), juce::dontSendNotification);
    atStart_.onClick = [this] { setShowAtStart(atStart_.getToggleState()); };
    describe(close_, "Close the welcome", "Closes this page; Help or F1 opens it again.");
    close_.onClick = [this] { close(); };
    for (juce::Component* c : std::initializer_list<juce::Component*> {&heading_, &playing_, &testTone_, &audioSettings_, &hearing_,
                                                                        &connecting_, &device_, &osc_, &input_, &unmute_, &keys_,
                                                                        &atStart_, &close_})
        addAndMakeVisible(*c);
    setFocusContainerType(FocusContainerType::keyboardFocusContainer);   // Tab stays inside while shown
    setWantsKeyboardFocus(false);
}

WelcomePanel::~WelcomePanel()
{
    stopTimer();
}

void WelcomePanel::open()
{
    refresh();
    setVisible(true);
    toFront(false);
    startTimerHz(4);
    close_.grabKeyboardFocus();
    plugin::announce(processor_, "welcome", text(), juce::AccessibilityHandler::AnnouncementPriority::medium);
}

void WelcomePanel::close()
{
    stopTimer();
    setVisible(false);
    if (onClose) onClose();
}

void WelcomePanel::timerCallback()
{
    refresh();
    // Opened before the window had the keyboard (the app's first start): once it has it, the
    // focus comes here rather than staying on the window's own Options button.
    if (isShowing() && ! hasKeyboardFocus(true)) {
        auto* focused = juce::Component::getCurrentlyFocusedComponent();
        auto* editor = getParentComponent();
        if (editor != nullptr && (focused == nullptr || ! editor->isParentOf(focused))) close_.grabKeyboardFocus();
    }
}

void WelcomePanel::refresh()
{
    const auto source = processor_.source();
    juce::String playing = "Playing now: ";
    if (source == SourceKind::Simulator)
        playing << "the simulated arm. It wanders by itself (Wander); drag it on the arm view, or Tab to the arm view "
                   "and use the arrow keys. Nothing is connected.";
    else if (source == SourceKind::Device)
        playing << (processor_.deviceConnected() ? "the device on " + processor_.settings()[SettingIds::serialPort].toString() + "."
                                                 : juce::String("the device source, but no device is connected: the arm stands still."));
    else if (source == SourceKind::Osc)
        playing << "OSC input (a phone or a sensor sending to this computer).";
    else
        playing << "host automation (the elevation, azimuth and roll parameters).";
    playing << " The scene plays sound and drives the motors from the arm's movement.";
    playing_.setText(playing, juce::dontSendNotification);

    const auto audio = standaloneAudio();
    juce::String hearing = "Hearing it: ";
    if (! audio.standalone) hearing << "the host's audio output (this is the plugin).";
    else if (! audio.deviceOpen || audio.output.isEmpty())
        hearing << "no sound card is open, so nothing is heard; the arm and the motors still run. Choose an output in Audio settings.";
    else
        hearing << audio.output << " (" << audio.deviceType << ", " << juce::String(juce::roundToInt(audio.sampleRate)) << " Hz). "
                << "Test tone plays a 1 s beep: if you do not hear it, choose another output.";
    if (processor_.testTonePlaying()) hearing << " (tone playing)";
    hearing_.setText(hearing, juce::dontSendNotification);
    audioSettings_.setEnabled(audio.standalone);

    connecting_.setText("A real arm: choose its port in the device panel and press Connect; the source switches to the device, "
                        "and the status line at the bottom shows its packets per second. A phone: turn on OSC in (port "
                            + processor_.settings()[SettingIds::oscInPort].toString()
                            + ") and point a sensor app at this computer (docs/SENSORS.md).",
                        juce::dontSendNotification);

    juce::String input = "Audio input: ";
    const bool listens = processor_.sceneListens();
    if (audio.inputMuted == 1)
        input << "muted (the app mutes it at start, against feedback through speakers). "
              << (listens ? "This scene listens to it: unmute it (use headphones)." : "The score and audio-touch scenes listen to it: unmute it for them.");
    else if (audio.inputMuted == 0)
        input << (audio.inputChannels > 0 ? "on (" + audio.input + ")." : juce::String("not muted, but no input device is open (Audio settings)."));
    else
        input << "the track the plugin is on (the score and audio-touch scenes listen to it).";
    input_.setText(input, juce::dontSendNotification);
    unmute_.setVisible(audio.inputMuted == 1);

    keys_.setText("Keys: Tab and Shift+Tab move between controls (the focused one has a blue outline); arrows, Space and Return act "
                  "on it only; F1 opens this page; Escape closes it.",
                  juce::dontSendNotification);
    resized();
}

juce::String WelcomePanel::text() const
{
    return heading_.getText() + "\n" + playing_.getText() + "\n" + hearing_.getText() + "\n" + connecting_.getText() + "\n"
           + input_.getText() + "\n" + keys_.getText();
}

bool WelcomePanel::keyPressed(const juce::KeyPress& key)
{
    if (key == juce::KeyPress::escapeKey) {
        close();
        return true;
    }
    return false;
}

void WelcomePanel::paint(juce::Graphics& g)
{
    g.setColour(juce::Colour(0xff1a2430));
    g.fillRoundedRectangle(getLocalBounds().toFloat(), 8.0f);
    g.setColour(juce::Colour(0xff4fc3ff).withAlpha(0.6f));
    g.drawRoundedRectangle(getLocalBounds().toFloat().reduced(1.0f), 8.0f, 1.5f);
}

void WelcomePanel::resized()
{
    // The largest text size (18 down to 10 points) at which everything fits: the page never
    // cuts off its own Close button, at the editor's minimum size or at 200 %.
    const auto area = getLocalBounds().reduced(14, 10);
    const int width = juce::jmax(1, area.getWidth() - 8);
    float font = 18.0f;
    int line = 0, button = 0, gap = 0;
    const auto lines = [&](const juce::Label& l) {
        // Word wrapping loses part of each line: count 15 % more than the bare width needs.
        const float needed = juce::Font(font).getStringWidthFloat(l.getText()) * 1.15f / static_cast<float>(width);
        return juce::jmax(1, static_cast<int>(std::ceil(needed))) * line + 4;
    };
    const auto measure = [&] {
        line = juce::roundToInt(font * 1.2f);
        button = juce::jmax(22, juce::roundToInt(font * 1.8f));
        gap = juce::roundToInt(font * 0.4f);
        return juce::roundToInt(font * 1.9f) + lines(playing_) + lines(hearing_) + button + gap + lines(connecting_) + button + gap
               + lines(input_) + (unmute_.isVisible() ? button + gap : 0) + lines(keys_) + button;
    };
    while (font > 10.0f && measure() > area.getHeight()) font -= 0.5f;
    measure();

    auto r = area;
    heading_.setFont(juce::Font(font + 5.0f, juce::Font::bold));
    for (auto* l : {&playing_, &hearing_, &connecting_, &input_, &keys_}) l->setFont(juce::Font(font));
    const auto buttonWidth = [&](const juce::Button& b) {
        return juce::roundToInt(juce::Font(font).getStringWidthFloat(b.getButtonText())) + juce::roundToInt(font * 2.0f);
    };
    heading_.setBounds(r.removeFromTop(juce::roundToInt(font * 1.9f)));
    playing_.setBounds(r.removeFromTop(lines(playing_)));
    hearing_.setBounds(r.removeFromTop(lines(hearing_)));
    auto b1 = r.removeFromTop(button);
    testTone_.setBounds(b1.removeFromLeft(buttonWidth(testTone_)));
    b1.removeFromLeft(8);
    audioSettings_.setBounds(b1.removeFromLeft(buttonWidth(audioSettings_)));
    r.removeFromTop(gap);
    connecting_.setBounds(r.removeFromTop(lines(connecting_)));
    auto b2 = r.removeFromTop(button);
    device_.setBounds(b2.removeFromLeft(buttonWidth(device_)));
    b2.removeFromLeft(8);
    osc_.setBounds(b2.removeFromLeft(buttonWidth(osc_)));
    r.removeFromTop(gap);
    input_.setBounds(r.removeFromTop(lines(input_)));
    if (unmute_.isVisible()) {
        auto b3 = r.removeFromTop(button);
        unmute_.setBounds(b3.removeFromLeft(buttonWidth(unmute_)));
        r.removeFromTop(gap);
    }
    auto bottom = r.removeFromBottom(button);
    close_.setBounds(bottom.removeFromRight(juce::jmax(buttonWidth(close_), 90)));
    bottom.removeFromRight(8);
    atStart_.setBounds(bottom.removeFromLeft(buttonWidth(atStart_) + button));
    keys_.setBounds(r);
}

} // namespace armadillo::plugin
