#include "Plugin/TactorsPanel.h"
#include "Plugin/Accessibility.h"
#include "Plugin/PluginProcessor.h"

namespace armadillo::plugin {

namespace {
constexpr const char* kModels[] = {"erm", "lra", "voice-coil"};
constexpr const char* kModelText[] = {"ERM (spinning mass)", "LRA (170 Hz resonance)", "Voice coil (250 Hz carrier)"};
}

TactorsPanel::TactorsPanel(ArmadilloProcessor& processor)
    : processor_(processor), standalone_(processor.wrapperType == juce::AudioProcessor::wrapperType_Standalone)
{
    auto& settings = processor_.settings();
    heading_.setText("Tactors", juce::dontSendNotification);
    heading_.setFont(juce::Font(15.0f, juce::Font::bold));
    intro_.setText(standalone_ ? "The motor grid on a tactor rig: one channel per motor on a sound card or JACK, separate from the sound "
                                 "output. Channel k carries motor k unless the map says otherwise."
                               : "The motor grid on the Tactors output bus: enable the bus (9 or 12 channels) in the host's routing and "
                                 "send it to an interface with tactor amplifiers, or record it as a tactile track.",
                   juce::dontSendNotification);
    intro_.setJustificationType(juce::Justification::topLeft);
    for (auto* l : {&heading_, &intro_, &deviceLabel_, &connectLabel_, &modelLabel_, &mapLabel_, &gainsLabel_, &gainsFile_, &testLabel_, &status_})
        addAndMakeVisible(*l);
    deviceLabel_.setText("Output", juce::dontSendNotification);
    connectLabel_.setText("JACK connect", juce::dontSendNotification);
    modelLabel_.setText("Model", juce::dontSendNotification);
    mapLabel_.setText("Channel map", juce::dontSendNotification);
    gainsLabel_.setText("Gains", juce::dontSendNotification);
    testLabel_.setText("Test a channel", juce::dontSendNotification);
    status_.setTitle("Tactor status");
    status_.setJustificationType(juce::Justification::topLeft);

    describe(device_, "Tactor output device", "jack, or an ALSA device such as hw:UMC1820 (its channels: one per motor).");
    device_.setText(settings[SettingIds::tactorDevice].toString(), false);
    device_.setTextToShowWhenEmpty("jack, or hw:1", juce::Colours::grey);
    describe(connect_, "JACK connections", "With jack: connect tactor_1, tactor_2, ... to the playback ports matching this pattern.");
    connect_.setText(settings[SettingIds::tactorConnect].toString(), false);
    connect_.setTextToShowWhenEmpty("system:playback_.*", juce::Colours::grey);
    describe(map_, "Channel map", "One entry per channel: a motor number or - for a silent channel, ranges allowed (1-9). Empty: channel k is motor k.");
    map_.setText(settings[SettingIds::tactorMap].toString(), false);
    map_.setTextToShowWhenEmpty("1-9", juce::Colours::grey);
    commitOnEnter(device_, processor_.settings(), SettingIds::tactorDevice);
    commitOnEnter(connect_, processor_.settings(), SettingIds::tactorConnect);
    commitOnEnter(map_, processor_.settings(), SettingIds::tactorMap);
    describe(output_, "Tactor output", "Open the tactor output and drive it from every control step, beside the serial device.");
    output_.setToggleState(processor_.tactorRig().outputOpen(), juce::dontSendNotification);
    output_.onClick = [this] {
        processor_.settings().setProperty(SettingIds::tactorDevice, device_.getText().trim(), nullptr);
        processor_.settings().setProperty(SettingIds::tactorConnect, connect_.getText().trim(), nullptr);
        const auto why = processor_.setTactorOutput(output_.getToggleState());
        output_.setToggleState(processor_.tactorRig().outputOpen(), juce::dontSendNotification);
        say(why.isNotEmpty() ? why : (processor_.tactorRig().outputOpen() ? "Tactor output on: " + juce::String(processor_.tactorRig().outputStatus()) : "Tactor output off"));
    };
    for (auto* c : std::initializer_list<juce::Component*> {&device_, &connect_, &output_, &deviceLabel_, &connectLabel_}) {
        c->setVisible(standalone_);
        if (standalone_) addAndMakeVisible(*c);
    }

    describe(model_, "Actuator model", "How a motor's level becomes a signal: ERM, LRA or voice coil (docs/TACTORS.md).");
    for (int i = 0; i < 3; ++i) model_.addItem(kModelText[i], i + 1);
    const auto model = settings[SettingIds::tactorModel].toString();
    for (int i = 0; i < 3; ++i)
        if (model == kModels[i]) model_.setSelectedId(i + 1, juce::dontSendNotification);
    model_.onChange = [this] {
        const int i = model_.getSelectedId() - 1;
        if (i >= 0 && i < 3) processor_.settings().setProperty(SettingIds::tactorModel, kModels[i], nullptr);
    };
    describe(sound_, "Scene's sound on the voice coils",
             "With the voice-coil model: the scene's own sound, band-limited to 40 to 400 Hz, is the carrier (the cymbal felt as its own waveform).");
    sound_.getToggleStateValue().referTo(settings.getPropertyAsValue(SettingIds::tactorSound, nullptr));
    describe(gains_, "Gain file", "Choose a per-channel gain file (JSON, 0 to 1 per channel) for tactors that differ.");
    gains_.onClick = [this] { chooseGains(); };
    describe(clearGains_, "No gain file", "Every channel at full gain (level/15 of full scale).");
    clearGains_.onClick = [this] { processor_.settings().setProperty(SettingIds::tactorGains, "", nullptr); };
    gainsFile_.setTitle("Gain file name");
    for (auto* c : std::initializer_list<juce::Component*> {&model_, &sound_, &map_, &gains_, &clearGains_}) addAndMakeVisible(*c);

    for (int k = 0; k < kChannels; ++k) {
        auto& b = test_[static_cast<std::size_t>(k)];
        b.setButtonText(juce::String(k + 1));
        describe(b, "Test tactor channel " + juce::String(k + 1), "Buzz this channel's motor for half a second and say which motor it is.");
        b.onClick = [this, k] {
            const auto why = processor_.testTactorChannel(k);
            const int motor = processor_.tactorRig().motorOfChannel(k, PluginState::tactorSettings(processor_.settings()), processor_.motorCount());
            say(why.isNotEmpty() ? why : "Channel " + juce::String(k + 1) + ": motor m" + juce::String(motor + 1));
        };
        addAndMakeVisible(b);
    }
    timerCallback();
    startTimerHz(4);
}

TactorsPanel::~TactorsPanel()
{
    stopTimer();
}

void TactorsPanel::chooseGains()
{
    chooser_ = std::make_unique<juce::FileChooser>("Choose a tactor gain file", juce::File(), "*.json");
    chooser_->launchAsync(juce::FileBrowserComponent::canSelectFiles | juce::FileBrowserComponent::openMode, [this](const juce::FileChooser& fc) {
        const auto file = fc.getResult();
        if (file != juce::File()) processor_.settings().setProperty(SettingIds::tactorGains, file.getFullPathName(), nullptr);
    });
}

void TactorsPanel::say(const juce::String& text)
{
    shown_ = text;
    announce(processor_, "tactors", text, juce::AccessibilityHandler::AnnouncementPriority::medium);
    timerCallback();
}

void TactorsPanel::timerCallback()
{
    auto& rig = processor_.tactorRig();
    const auto gains = processor_.settings()[SettingIds::tactorGains].toString();
    gainsFile_.setText(gains.isEmpty() ? "none: every channel at full gain" : juce::File(gains).getFileName(), juce::dontSendNotification);
    sound_.setEnabled(processor_.settings()[SettingIds::tactorModel].toString() == "voice-coil");
    const int motors = processor_.motorCount();
    const int channels = standalone_ ? motors : (rig.busChannels() > 0 ? rig.busChannels() : motors);
    for (int k = 0; k < kChannels; ++k) test_[static_cast<std::size_t>(k)].setVisible(k < channels);
    juce::String line = standalone_ ? "Output: " + juce::String(rig.outputStatus())
                                    : (rig.busChannels() > 0 ? "Tactors bus: " + juce::String(rig.busChannels()) + " channels, enabled"
                                                             : "Tactors bus: disabled in the host");
    if (shown_.isNotEmpty()) line << "\n" << shown_;
    status_.setText(line, juce::dontSendNotification);
    if (output_.getToggleState() != rig.outputOpen()) output_.setToggleState(rig.outputOpen(), juce::dontSendNotification);
}

void TactorsPanel::paint(juce::Graphics& g)
{
    g.fillAll(juce::Colour(0xff16202a));
}

void TactorsPanel::resized()
{
    auto area = getLocalBounds().reduced(12);
    heading_.setBounds(area.removeFromTop(24));
    intro_.setBounds(area.removeFromTop(40));
    area.removeFromTop(6);
    const auto row = [&area] { return takeRow(area); };
    constexpr int labelWidth = 110;
    if (standalone_) {
        auto r = row();
        deviceLabel_.setBounds(r.removeFromLeft(labelWidth));
        output_.setBounds(r.removeFromRight(150));
        device_.setBounds(r.reduced(0, 2));
        r = row();
        connectLabel_.setBounds(r.removeFromLeft(labelWidth));
        connect_.setBounds(r.reduced(0, 2));
    }
    auto r = row();
    modelLabel_.setBounds(r.removeFromLeft(labelWidth));
    sound_.setBounds(r.removeFromRight(280));
    model_.setBounds(r.reduced(0, 2));
    r = row();
    mapLabel_.setBounds(r.removeFromLeft(labelWidth));
    map_.setBounds(r.reduced(0, 2));
    r = row();
    gainsLabel_.setBounds(r.removeFromLeft(labelWidth));
    clearGains_.setBounds(r.removeFromRight(110));
    gains_.setBounds(r.removeFromRight(110));
    gainsFile_.setBounds(r);
    r = row();
    testLabel_.setBounds(r.removeFromLeft(labelWidth));
    const int w = juce::jmin(44, r.getWidth() / kChannels);
    for (auto& b : test_) b.setBounds(r.removeFromLeft(w).reduced(2, 0));
    status_.setBounds(area);
}

} // namespace armadillo::plugin
